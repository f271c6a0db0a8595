"""What a run ran on: the facts that decide its wall time and its last digits.

An explicit run with element deletion amplifies round-off: the same scenario compiled for
another processor (Numba compiles for the host CPU, e.g. AVX-512 or not, with fused
multiply-adds where the target has them) can delete an element a step earlier and end
with a force curve that differs at the 10⁻³ N level (the needle's 1 mm/s RMSE was 0.0290 N
on the hosts of sessions 9–11 and 0.0279 N on session 12's, same code and inputs;
``docs/solver.md``, "Round-off and the host"). ``summary.json`` therefore records the
platform with the run figures, so two results folders can be compared knowingly.
"""

from __future__ import annotations

import os
import platform

import numba
import numpy as np

THREAD_SETTINGS = ("NUMBA_NUM_THREADS", "OMP_WAIT_POLICY", "GOMP_SPINCOUNT", "NUMBA_CPU_NAME",
                   "NUMBA_CPU_FEATURES")
"""Environment variables that change the threads' behaviour or the compiled code."""


def processor_name() -> str:
    """The CPU's model name (``/proc/cpuinfo`` on Linux, else :func:`platform.processor`)."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as cpuinfo:
            for line in cpuinfo:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def describe_platform() -> dict:
    """The platform of this process, as plain JSON values.

    Returns
    -------
    dict
        ``processor`` (model name), ``compiled_for`` (the LLVM CPU name Numba compiles for,
        e.g. ``znver5``: ``NUMBA_CPU_NAME`` if set, else the host's), ``logical_cpus``,
        ``numba_threads`` (the threads the kernels use now), ``threading_layer`` (``omp``,
        ``tbb`` or ``workqueue``; ``None`` before the first parallel kernel ran), ``python``,
        ``numpy``, ``numba``, ``corneasim`` (versions) and ``environment`` (the set ones of
        :data:`THREAD_SETTINGS`).
    """
    from llvmlite import binding

    from corneasim import __version__

    try:
        layer = numba.threading_layer()
    except ValueError:  # no parallel kernel has run in this process yet
        layer = None
    return {
        "processor": processor_name(),
        "compiled_for": numba.config.CPU_NAME or binding.get_host_cpu_name(),
        "logical_cpus": os.cpu_count(),
        "numba_threads": numba.get_num_threads(),
        "threading_layer": layer,
        "python": platform.python_version(),
        "numpy": np.__version__,
        "numba": numba.__version__,
        "corneasim": __version__,
        "environment": {name: os.environ[name] for name in THREAD_SETTINGS if name in os.environ},
    }
