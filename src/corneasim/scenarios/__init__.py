"""Scenario configuration schema and the built-in scenarios (needle, trephine).

The one call to run a scenario from Python::

    import corneasim
    result = corneasim.run_scenario("needle", ["mesh.preset=coarse"])
    result.history["force_N"], result.summary["peak_force_N"]
"""

from __future__ import annotations

from pathlib import Path


def run_scenario(name_or_path: str, overrides: list[str] = (), *, out_dir: str | Path | None = None,
                 progress: bool = False, preload_from: str | Path | None = None, overwrite: bool = False):
    """Run a built-in scenario or a scenario file and return its results.

    Parameters
    ----------
    name_or_path : str
        ``"needle"``, ``"trephine"`` or the path of a scenario TOML file.
    overrides : list of str
        ``KEY=VALUE`` overrides, as ``--set`` on the command line (``"instrument.motion.insertion.rate=5"``).
    out_dir : path-like, optional
        Results folder to write (as ``corneasim run --out``); None writes nothing.
    progress : bool
        Show a progress bar on stderr.
    preload_from : path-like, optional
        Results folder of an earlier run of the same eye: start from its settled preload
        (``corneasim run --preload-from``; :mod:`corneasim.scenarios.preload_reuse`).
    overwrite : bool
        Replace an earlier run's files in ``out_dir`` (``corneasim run --overwrite``; refused without).

    Returns
    -------
    corneasim.scenarios.runner.Result
        ``history`` (dict of column name to ndarray; units in the names), ``summary`` (dict, as
        ``summary.json``), ``deletions`` (list of (time s, element, block)).
    """
    from corneasim.scenarios.registry import load_scenario, to_toml
    from corneasim.scenarios.runner import simulate

    scenario, resolved, base_dir = load_scenario(str(name_or_path), list(overrides))
    return simulate(scenario, out_dir=out_dir, base_dir=base_dir, progress=progress, preload_from=preload_from,
                    overwrite=overwrite, record=to_toml(resolved) if out_dir is not None else None)
