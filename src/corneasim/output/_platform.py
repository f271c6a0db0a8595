"""What a run ran on: the facts that decide its wall time and its last digits.

An explicit run with element deletion amplifies round-off, and the machine code of the
kernels is not the same everywhere. Numba compiles for the host CPU (vector width, fused
multiply-adds), and a ``parallel=True`` kernel loaded from the on-disk cache is optimised
again when it is loaded, so it need not be the code that the compiling process ran
(numba/numba#8085, #10617). The needle's 1 mm/s RMSE, same code and inputs on one host,
was 0.0279 N with the cache the test suite wrote and 0.0291 N in the run that compiled its
own kernels (``docs/solver.md``, "Round-off, the host and the Numba cache").
``summary.json`` therefore records the platform with the run figures, and which kernels
the run compiled itself, so two results folders can be compared knowingly.
"""

from __future__ import annotations

import os
import platform
import time

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


def process_age() -> float | None:
    """Seconds since this process started (the interpreter's start, before any import), or
    None where the start time is not readable.

    The process's start time is field 22 of ``/proc/self/stat`` (Linux), in clock ticks since
    boot (1/``SC_CLK_TCK`` s, usually 10 ms: the resolution of the result), compared with the
    time since boot (``CLOCK_BOOTTIME``).
    """
    try:
        with open("/proc/self/stat", encoding="ascii") as stat:
            fields = stat.read().rsplit(")", 1)[1].split()  # after the command name, which may hold spaces
        return time.clock_gettime(time.CLOCK_BOOTTIME) - int(fields[19]) / os.sysconf("SC_CLK_TCK")
    except (OSError, AttributeError, ValueError, IndexError):
        return None


def compiled_in_process(functions) -> list[str]:
    """Names of the Numba functions among ``functions`` that this process compiled itself
    instead of loading them from the on-disk cache (module notes: their code may differ).

    Parameters
    ----------
    functions : iterable of numba dispatchers (``@njit(cache=True)`` functions)

    Returns
    -------
    list of str
        ``module.name`` of each function with a cache miss in this process.
    """
    return [f"{function.py_func.__module__}.{function.py_func.__name__}" for function in functions
            if sum(function.stats.cache_misses.values()) > 0]


def cached_for_this_machine(function) -> bool | None:
    """Whether Numba's on-disk cache holds compiled code of ``function`` for this machine.

    An entry of the cache index is keyed by the signature and the code generator's "magic
    tuple" (target triple, CPU name, CPU features): code compiled on another processor does
    not count. The answer is about any signature, so a first call with new argument types
    can still compile.

    Parameters
    ----------
    function : numba dispatcher (``@njit(cache=True)``)

    Returns
    -------
    bool or None
        None where the cache's index cannot be read (a Numba whose cache layout differs).
    """
    try:
        index = function._cache._cache_file._load_index()
        magic = function.targetctx.codegen().magic_tuple()
    except (AttributeError, OSError, TypeError, ValueError):
        return None
    return any(isinstance(key, tuple) and len(key) > 1 and key[1] == magic for key in index)
