"""One case of a study: its overrides, validation, run and row of the results table.

:func:`run_case` is what a Dask worker executes. It runs the base scenario with the study's
fixed overrides and the case's parameter values (``KEY=VALUE`` strings, applied by the same
machinery as ``corneasim run --set``) into the case's results folder, and returns the row:
the outputs, ``status`` (completed or failed), the one-line ``error``, ``wall_s`` and the
``worker``. A case never raises: a bad value or a simulation that fails is a failed row, so one
case cannot stop a study. A case with ``fresh_kernels`` runs ``corneasim run`` in a process of
its own whose ``NUMBA_CACHE_DIR`` is an empty folder, so that its kernels are compiled anew.

Each attempt at a case runs in a hidden folder of its own next to the case's folder
(``.NAME.PID-NS``) and replaces the case's folder when it ends, if no newer attempt of the case
has started since (``.NAME.newest`` names the newest while it runs); an older one deletes its
folder instead. Dask cannot stop a case it cancels (a thread cannot be stopped): after a Ctrl-C
the cancelled case runs on, and the resumed study starts the case again, perhaps on another
worker at the same time. Neither attempt writes into the other's folder. The attempt that
takes the case's folder deletes the hidden folders of every earlier attempt of the case: they are
overtaken, and one whose worker was killed mid-case would otherwise stay behind (an earlier
attempt still running then fails into a folder nobody reads).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import tomli_w

from corneasim.errors import InputError


def toml_value(value) -> str:
    """A value as TOML text for ``KEY=VALUE`` (inline tables for dicts).

    >>> toml_value(0.2), toml_value("rounded"), toml_value([1, 2]), toml_value({"law": "none"})
    ('0.2', '"rounded"', '[1, 2]', '{ law = "none" }')
    """
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{key} = {toml_value(item)}" for key, item in value.items()) + " }"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(item) for item in value) + "]"
    if isinstance(value, np.generic):
        value = value.item()
    return tomli_w.dumps({"v": value}).split("=", 1)[1].strip()


def case_overrides(fixed: dict, values: dict) -> list[str]:
    """``KEY=VALUE`` overrides: the study's fixed ones, then the case's parameter values.

    Keys are those of ``--set``, entries of a list of tables included (``supports[0].stiffness``,
    or ``supports.lower_hemisphere.stiffness`` by the set the entry names).

    >>> case_overrides({"mesh.preset": "coarse"}, {"supports[0].stiffness": 0.05})
    ['mesh.preset="coarse"', 'supports[0].stiffness=0.05']
    """
    return [f"{key}={toml_value(value)}" for key, value in {**fixed, **values}.items()]


def worker_name() -> str:
    """The Dask worker's address, or host and process id outside a worker."""
    try:
        from distributed import get_worker

        return get_worker().address
    except (ImportError, ValueError):
        return f"{socket.gethostname()}:{os.getpid()}"


def one_line(error: BaseException) -> str:
    """An exception as one line: its type (unless an input error) and message."""
    text = " ".join(str(error).split())
    return text if isinstance(error, InputError) else f"{type(error).__name__}: {text}"


def run_case(scenario: str, overrides: list[str], case_dir: str, outputs: dict,
             fresh_kernels: bool = False, unset: list[str] = (), plots: bool = False) -> dict:
    """Run one case into ``case_dir`` (replaced at the end, module notes) and return its outputs and status.

    Parameters
    ----------
    scenario : str
        Built-in scenario name or absolute scenario file path.
    overrides : list of str
        ``KEY=VALUE`` overrides (fixed ones and the case's values).
    case_dir : str
        The case's results folder.
    outputs : dict
        Output name -> summary path or :class:`~corneasim.studies.spec.CurveOutput`.
    fresh_kernels : bool
        Run in a process of its own with an empty Numba cache.
    unset : list of str
        Dotted keys removed after the overrides (``--unset``).
    plots : bool
        Write the case's ``plots/`` and ``report.html`` (the study's ``case_plots``).

    Returns
    -------
    dict
        The outputs, ``status``, ``error``, ``wall_s`` (s) and ``worker``.
    """
    from corneasim.output import atomic_write_text
    from corneasim.studies.outputs import collect

    start = time.perf_counter()
    folder = Path(case_dir)
    attempt = folder.with_name(f".{folder.name}.{os.getpid()}-{time.time_ns()}")
    newest = folder.with_name(f".{folder.name}.newest")
    attempt.mkdir(parents=True)
    atomic_write_text(newest, attempt.name)
    status, error, summary, history = "completed", "", {}, {}
    try:
        if fresh_kernels:
            summary, history = _run_isolated(scenario, overrides, unset, attempt, plots)
        else:
            summary, history = _run_here(scenario, overrides, unset, attempt, plots)
        if summary.get("status") != "completed":
            status = "failed"
            error = " ".join(str(summary.get("error") or f"run {summary.get('status')}").split())
        row = collect(summary, history, outputs)
    except Exception as failure:  # noqa: BLE001 - any failure of a case is recorded, never raised
        status, error, row = "failed", one_line(failure), collect({}, {}, outputs)
    finally:
        _settle(attempt, folder, newest)
    row.update(status=status, error=error, wall_s=time.perf_counter() - start, worker=worker_name())
    return row


def _settle(attempt: Path, folder: Path, newest: Path) -> None:
    """Move the attempt's folder to the case's ``folder`` if it is still the newest attempt, else delete it."""
    try:
        current = newest.read_text()
    except FileNotFoundError:
        current = ""
    if current != attempt.name:
        shutil.rmtree(attempt, ignore_errors=True)
        return
    aside = attempt.with_name(f"{attempt.name}.replaced")
    if folder.exists():
        os.replace(folder, aside)
    os.replace(attempt, folder)
    newest.unlink(missing_ok=True)
    shutil.rmtree(aside, ignore_errors=True)
    for earlier in _earlier_attempts(folder, attempt.name):
        shutil.rmtree(earlier, ignore_errors=True)


def _earlier_attempts(folder: Path, name: str) -> list[Path]:
    """The hidden folders of ``folder``'s attempts started before the attempt called ``name``
    (``.CASE.PID-NS``, ``NS`` its start in ns since the epoch, perhaps with ``.replaced``)."""
    pattern = re.compile(rf"\.{re.escape(folder.name)}\.\d+-(\d+)(\.replaced)?")
    started = int(pattern.fullmatch(name).group(1))
    return [path for path in folder.parent.glob(f".{folder.name}.*")
            if path.is_dir() and (match := pattern.fullmatch(path.name)) and int(match.group(1)) < started]


def _run_here(scenario: str, overrides: list[str], unset: list[str], folder: Path, plots: bool) -> tuple[dict, dict]:
    from corneasim.scenarios import run_scenario
    from corneasim.solver import SimulationError

    try:
        result = run_scenario(scenario, overrides, unset=unset, out_dir=folder, progress=False, plots=plots)
    except SimulationError:
        return _read_folder(folder)
    return result.summary, result.history


def _run_isolated(scenario: str, overrides: list[str], unset: list[str], folder: Path,
                  plots: bool) -> tuple[dict, dict]:
    """``corneasim run`` in a child process whose Numba cache is an empty folder."""
    cache = tempfile.mkdtemp(prefix="corneasim-numba-")
    try:
        command = [sys.executable, "-m", "corneasim.cli.main", "run", scenario, "--out", str(folder),
                   "--no-progress", *([] if plots else ["--no-plots"])]
        for text in overrides:
            command += ["--set", text]
        for key in unset:
            command += ["--unset", key]
        environment = {**os.environ, "NUMBA_CACHE_DIR": cache}
        completed = subprocess.run(command, env=environment, capture_output=True, text=True)
        if completed.returncode == 2:
            raise InputError(completed.stderr.strip().splitlines()[-1].removeprefix("corneasim: error: "))
        if not (folder / "summary.json").exists():
            lines = (completed.stderr.strip() or f"exit status {completed.returncode}").splitlines()
            raise RuntimeError(lines[-1])
        return _read_folder(folder)
    finally:
        shutil.rmtree(cache, ignore_errors=True)


def _read_folder(folder: Path) -> tuple[dict, dict]:
    """summary.json and history.csv of a results folder (empty when missing)."""
    summary_file, history_file = folder / "summary.json", folder / "history.csv"
    summary = json.loads(summary_file.read_text()) if summary_file.exists() else {}
    if history_file.exists():
        from corneasim.data import read_table

        return summary, read_table(history_file)
    return summary, {}
