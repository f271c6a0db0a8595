"""Studies: many runs of one scenario, in parallel on Dask, collected in one table.

A study file (``docs/studies.md``) names a base scenario, the parameters to vary (dotted
scenario keys with lists, ranges or distributions), a design (grid, Latin hypercube,
Sobol'/Saltelli, Morris, realizations) and the outputs to collect. From Python::

    import corneasim
    table = corneasim.study("validation/studies/needle_speed.toml", out="results/speed", workers=2)

``corneasim study run``, ``corneasim study report`` and ``corneasim calibrate`` are the
commands; this package needs the ``study`` extra (dask.distributed, SALib, optuna, pandas,
pyarrow), imported only when a study runs.
"""

__all__ = ["study"]


def __getattr__(name: str):
    """``study`` (:func:`corneasim.studies.runner.run_study`), imported on first use: a Dask worker
    that runs a case imports this package but needs neither pandas nor the runner."""
    if name == "study":
        from corneasim.studies.runner import run_study

        return run_study
    raise AttributeError(f"module 'corneasim.studies' has no attribute {name!r}")
