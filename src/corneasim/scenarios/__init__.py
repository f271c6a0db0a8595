"""Scenario configuration schema and the built-in scenarios (needle, trephine).

The one call to run a scenario from Python::

    import corneasim
    result = corneasim.run_scenario("needle", ["mesh.preset=coarse"])
    result.history["force_N"], result.summary["peak_force_N"]

The modules are private; their public names are exported here and imported on first use
(so that ``import corneasim`` stays light): the file format (:class:`Scenario`), the
registry (``load_scenario``, ``scenario_text``, ``list_scenarios``, ``read_tables``,
``to_toml``), the build (``build``, :class:`Setup`, ``make_mesh``, ``material_source``),
the run (``simulate``, :class:`Result`) and the mesh comparison (``compare_meshes``).
"""

from __future__ import annotations

import importlib
from pathlib import Path

_EXPORTS = {
    "Scenario": "_format", "load_scenario": "_registry", "scenario_text": "_registry",
    "list_scenarios": "_registry", "read_tables": "_registry", "to_toml": "_registry", "build": "_build",
    "Setup": "_build", "make_mesh": "_build", "material_source": "_build", "simulate": "_runner",
    "Result": "_runner", "compare_meshes": "_compare", "table_markdown": "_compare", "spread_markdown": "_compare",
    "scenario_kind": "_kinds",
}
__all__ = ["run_scenario", *_EXPORTS]


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'corneasim.scenarios' has no attribute '{name}'")
    return getattr(importlib.import_module(f"corneasim.scenarios.{module}"), name)


def run_scenario(name_or_path: str, overrides: list[str] = (), *, unset: list[str] = (),
                 out_dir: str | Path | None = None, progress: bool = False,
                 preload_from: str | Path | None = None, overwrite: bool = False, plots: bool = True):
    """Run a built-in scenario or a scenario file and return its results.

    Parameters
    ----------
    name_or_path : str
        ``"needle"``, ``"trephine"`` or the path of a scenario TOML file.
    overrides : list of str
        ``KEY=VALUE`` overrides, as ``--set`` on the command line (``"instrument.motion.insertion.rate=5"``).
    unset : list of str
        Dotted keys removed after the overrides, so that each takes its default, as ``--unset``
        on the command line (``"instrument.contact.cutting_toughness"``).
    out_dir : path-like, optional
        Results folder to write (as ``corneasim run --out``); None writes nothing.
    progress : bool
        Show a progress bar on stderr.
    preload_from : path-like, optional
        Results folder of an earlier run of the same eye: start from its settled preload
        (``corneasim run --preload-from``; :mod:`corneasim.scenarios._preload_reuse`).
    overwrite : bool
        Replace an earlier run's files in ``out_dir`` (``corneasim run --overwrite``; refused without).
    plots : bool
        Write ``plots/`` and ``report.html`` into ``out_dir`` (``corneasim run --no-plots``: not).

    Returns
    -------
    corneasim.scenarios._runner.Result
        ``history`` (dict of column name to ndarray; units in the names), ``summary`` (dict, as
        ``summary.json``), ``deletions`` (list of (time s, element, block)).
    """
    from corneasim.scenarios._registry import load_scenario, to_toml
    from corneasim.scenarios._runner import simulate

    scenario, resolved, base_dir = load_scenario(str(name_or_path), list(overrides), list(unset))
    return simulate(scenario, out_dir=out_dir, base_dir=base_dir, progress=progress, preload_from=preload_from,
                    overwrite=overwrite, record=to_toml(resolved) if out_dir is not None else None, plots=plots)
