"""corneasim: explicit finite-element simulation of instruments cutting the cornea.

Units everywhere: length mm, time s, force N, stress MPa, density tonne/mm^3,
energy mJ (N*mm).

>>> import corneasim
>>> callable(corneasim.run_scenario)
True
"""

import os

# OpenMP threads that spin long while waiting make each explicit step 10-20x slower whenever
# another process holds a core (measured: 15.4 ms instead of 0.71 ms per step of the
# 16,745-element needle model on 2 threads of a busy 2-core machine; libgomp's default spin is
# about 3 ms). Threads that never spin pay a wake-up of about 50 us at every parallel region,
# which is 2.4 ns per element-step of a 20,000-element kernel (benchmarks/kernels.py). A short
# spin (GOMP_SPINCOUNT 1000, about 10 us by libgomp's own estimate of 100,000 spins per ms)
# keeps the threads awake from one region of a step to the next and yields soon under load.
# A user's own settings win. Must be set before the first parallel kernel runs.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
os.environ.setdefault("GOMP_SPINCOUNT", "1000")
# The BLAS behind numpy and scipy only sees small problems here (Gaussian fits, mesh
# preparation), where its threads cost far more than they give: the SVD of a 1750 x 6
# Jacobian took 0.17 ms on one thread and 25 ms on two threads of this 2-core machine
# while another process ran, which made the needle's force fit 0.8 s -> 11 s. Read by
# OpenBLAS when numpy is first imported (importing corneasim first makes it apply).
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from corneasim.scenarios import run_scenario  # noqa: E402

__version__ = "0.1.0"
__all__ = ["run_scenario", "study", "__version__"]


def __getattr__(name: str):
    """``corneasim.study`` (:func:`corneasim.studies.runner.run_study`), imported on first use so that
    importing corneasim does not import Dask."""
    if name == "study":
        from corneasim.studies import study

        return study
    raise AttributeError(f"module 'corneasim' has no attribute {name!r}")
