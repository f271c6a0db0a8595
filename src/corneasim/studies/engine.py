"""The Dask side of a study: a cluster, the cases submitted, rows collected as they finish.

By default a :class:`distributed.LocalCluster` of worker processes (one Dask thread each, so
one case at a time per worker) is started and closed with the study; ``scheduler`` names
any running Dask scheduler instead (for example one of a ``dask-jobqueue`` cluster on
SLURM or PBS), and ``client`` passes a :class:`distributed.Client` the caller owns.

Numba threads: each local worker gets ``NUMBA_NUM_THREADS = cores // workers`` in its
environment (at least 1), so that workers x threads never exceed the cores; the solver's
own default then uses at most that many. Workers of an external cluster keep their own
environment (set ``NUMBA_NUM_THREADS`` where they are started).

A worker lost in the middle of a case (killed, out of memory) hands the case to another
worker once: a local cluster's scheduler allows one such failure per task
(``distributed.scheduler.allowed-failures`` = 1) before it gives up on the case with
``KilledWorker``, and a case given up on that way is submitted again once; a case lost twice is
recorded as failed.
"""

from __future__ import annotations

import logging
import os
import time
from collections.abc import Callable
from contextlib import contextmanager

ALLOWED_FAILURES = 1
"""Worker losses a local cluster tolerates per case before giving the case up."""


def default_workers() -> int:
    """One worker per core."""
    return max(1, os.cpu_count() or 1)


def numba_threads(workers: int) -> int:
    """Numba threads per local worker so that workers x threads fit the cores."""
    return max(1, (os.cpu_count() or 1) // max(1, workers))


@contextmanager
def connect(client=None, scheduler: str | None = None, workers: int | None = None):
    """Yield a Dask client: ``client`` as given, one connected to ``scheduler``, or a local cluster
    of ``workers`` processes (closed on exit)."""
    from distributed import Client, LocalCluster

    if client is not None:
        yield client
        return
    if scheduler is not None:
        with Client(scheduler) as connected:
            yield connected
        return
    workers = workers or default_workers()
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                           silence_logs=logging.ERROR, scheduler_kwargs={"allowed_failures": ALLOWED_FAILURES},
                           env={"NUMBA_NUM_THREADS": str(numba_threads(workers))})
    try:
        with Client(cluster) as local:
            yield local
    finally:
        cluster.close()


def worker_count(client) -> int:
    """Workers the client's cluster has now (at least 1)."""
    return max(1, len(client.scheduler_info().get("workers", {})))


def execute(client, jobs: dict, on_row: Callable[[str, dict], None], failed_row: Callable[[str, str], dict]) -> None:
    """Run ``jobs`` ({case: (function, args)}) on the client; hand each row to ``on_row`` as it finishes.

    A job whose future fails (its worker lost more than the scheduler allows, or an error
    outside the case function) is submitted once more; a second such failure gives
    ``failed_row(case, message)``. Ctrl-C cancels what is still running and propagates.
    """
    from distributed import as_completed

    futures = {}
    resubmitted = set()

    def submit(name):
        function, arguments = jobs[name]
        future = client.submit(function, *arguments, key=f"{name}-{time.time_ns()}", pure=False)
        futures[future] = name
        return future

    pending = as_completed([submit(name) for name in jobs])
    try:
        for future in pending:
            name = futures.pop(future)
            if future.status == "finished":
                on_row(name, future.result())
                continue
            message = _failure(future)
            if name not in resubmitted:
                resubmitted.add(name)
                pending.add(submit(name))
            else:
                on_row(name, failed_row(name, message))
    except BaseException:
        client.cancel(list(futures))
        raise


def _failure(future) -> str:
    try:
        error = future.exception()
    except BaseException as cancelled:  # noqa: BLE001 - a cancelled future raises instead of returning it
        error = cancelled
    text = " ".join(str(error).split())
    name = type(error).__name__
    if name == "KilledWorker":
        return "worker lost while running the case, twice"
    return f"{name}: {text}"

