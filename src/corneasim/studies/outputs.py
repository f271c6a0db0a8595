"""Study outputs: entries of ``summary.json`` by dotted path, and history curves resampled.

A scalar output is a dotted path into the summary (``validation.rmse_N``; a list entry by
its index, ``punctures.0.depth_mm``). Before any case runs, every path is checked against
the entries that a scenario of its kind writes (:data:`SUMMARY_KEYS`), so a misspelt path
stops the study at once instead of giving a column of NaN. A path that exists for the kind
but is absent or null in one case's summary (no puncture happened, no fit could be made)
gives NaN in that case's row.

A curve output is a history column resampled by linear interpolation on the study's
abscissa values, NaN outside the range the case's history covers.
"""

from __future__ import annotations

import math

import numpy as np

from corneasim.errors import InputError
from corneasim.studies.spec import Abscissa, CurveOutput

ANY = "*"
"""In :data:`SUMMARY_KEYS`: any key or list index, with anything below it."""
LIST = "#"
"""In :data:`SUMMARY_KEYS`: a list; its entries by integer index."""

_FIT = {"a": LIST, "b": LIST, "c": LIST, "rmse_N": None}
_PLATFORM = ANY
_RUN = {name: None for name in (
    "elements", "nodes", "steps", "wall_s", "startup_s", "element_steps_per_s", "stable_time_step_s",
    "max_kinetic_to_internal",
    "max_kinetic_to_internal_before_cut_through", "hourglass_to_internal", "added_mass_fraction", "time_scaling",
    "energy_balance_error")}
_RUN.update(preload={"duration_s": None, "out_of_balance": None, "max_speed_mm_per_s": None},
            warnings=LIST, platform=_PLATFORM)
_NEEDLE_VALIDATION = {name: None for name in (
    "dataset", "column", "rmse_N", "max_abs_error_N", "n_points", "rmse_raw_N", "max_abs_error_raw_N")}
_NEEDLE_VALIDATION.update(fit_range=LIST, fit=_FIT)
_COMMON = {"scenario": None, "kind": None, "status": None, "error": None, "run": _RUN, "distortion": ANY}

SUMMARY_KEYS = {
    "needle": {**_COMMON, "peak_force_N": None, "punctures": (LIST, {"event": None, "time_s": None,
                                                                      "depth_mm": None, "force_N": None}),
               "force_drops": (LIST, {"depth_mm": None, "force_N": None, "drop_N": None}),
               "fit": _FIT, "validation": _NEEDLE_VALIDATION},
    "trephine": {**_COMMON, "peak_fz_N": None, "peak_fc_N": None, "rotation_period_s": None,
                 "punctures": (LIST, {"event": None, "time_s": None, "displacement_um": None, "fz_N": None}),
                 "puncture_force_N": None, "fit": _FIT, "energy": ANY, "validation": ANY},
    "general": {**_COMMON, "reactions": ANY},
}
"""The entries of ``summary.json`` by scenario kind (``docs/scenario-format.md``): a table of
keys, :data:`ANY` for entries whose keys depend on the scenario (a general scenario's
``reactions`` are named by its node sets), or (:data:`LIST`, entry) for a list of tables."""


def check_path(path: str, kind: str, where: str) -> None:
    """Raise :class:`InputError` unless ``path`` names an entry a ``kind`` scenario's summary has."""
    node = SUMMARY_KEYS.get(kind, SUMMARY_KEYS["general"])
    walked = []
    for part in path.split("."):
        if node == ANY:
            return
        if isinstance(node, tuple) or node == LIST:
            if not part.isdigit():
                raise InputError(f"{where}: {'.'.join(walked)} is a list: give an index, e.g. "
                                 f"{'.'.join(walked + ['0'])}")
            node = node[1] if isinstance(node, tuple) else None
        elif isinstance(node, dict) and part in node:
            node = node[part]
        else:
            known = ", ".join(sorted(node)) if isinstance(node, dict) else "nothing"
            at = ".".join(walked) or "the summary"
            raise InputError(f"{where}: {path!r} is not in a {kind} scenario's summary.json ({at} has {known})")
        walked.append(part)


def summary_value(summary: dict, path: str) -> float:
    """The summary entry at ``path`` as a float (NaN when absent, null or not a number)."""
    value = summary
    for part in path.split("."):
        if isinstance(value, dict) and part in value:
            value = value[part]
        elif isinstance(value, list) and part.isdigit() and int(part) < len(value):
            value = value[int(part)]
        else:
            return math.nan
    if isinstance(value, bool) or value is None:
        return math.nan if value is None else float(value)
    if isinstance(value, (int, float)):
        return float(value)
    return value if isinstance(value, str) else math.nan


def abscissa(curve: CurveOutput) -> np.ndarray:
    """The abscissa values of a curve output (unit of its x column)."""
    if isinstance(curve.at, Abscissa):
        return np.linspace(curve.at.low, curve.at.high, curve.at.steps)
    return np.asarray(curve.at, dtype=float)


def resample(history: dict, curve: CurveOutput, where: str) -> np.ndarray:
    """The curve's column interpolated on its abscissa, NaN outside the history's x range."""
    for column in (curve.x, curve.curve):
        if column not in history:
            raise InputError(f"{where}: history has no column {column!r} (it has {', '.join(history)})")
    x = np.asarray(history[curve.x], dtype=float)
    y = np.asarray(history[curve.curve], dtype=float)
    order = np.argsort(x, kind="stable")
    at = abscissa(curve)
    return np.interp(at, x[order], y[order], left=np.nan, right=np.nan) if x.size else np.full(at.shape, np.nan)


def collect(summary: dict, history: dict, outputs: dict) -> dict:
    """Every output of a case: name -> float, str or ndarray (curves)."""
    row = {}
    for name, output in outputs.items():
        if isinstance(output, CurveOutput):
            row[name] = resample(history, output, f"outputs.{name}") if history else np.full(
                abscissa(output).shape, np.nan)
        else:
            row[name] = summary_value(summary, output)
    return row
