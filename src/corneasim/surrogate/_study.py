"""Read a study's completed cases as training data: inputs, force curves and puncture abscissae.

A study folder holds ``study.toml`` (its ``[parameters]`` are the inputs), ``results.parquet``
or ``results.csv`` (a row per case with the parameter values and its ``status``) and
``cases/<case>/`` results folders (``scenario.toml``, ``history.csv``, ``summary.json``).
Only completed cases are used. The needle's curve is ``force_N`` against ``depth_mm``; the
trephine's are ``fz_N`` and ``fc_N`` against ``time_s``. The puncture events are those of
``summary.json`` (``depth_mm`` for the needle, ``time_s`` for the trephine): by default those found
in every case; asked for by name, a case without one of them (a whole cornea not punctured by the
run's end, say) is left out of the training set and listed with its reason, since its curve has
no landmark for that event to be registered on.
"""

from __future__ import annotations

import json
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from corneasim.errors import InputError

EVENT_ORDER = ("epithelium", "stroma", "cornea")
CURVES = {"needle": ("depth_mm", "mm", ("force_N",)), "trephine": ("time_s", "s", ("fz_N", "fc_N"))}
"""Per scenario kind: the abscissa column, its unit and the force channels (N)."""
UNITS = (("rotation.rate", "rad/s"), ("rate", "mm/s"), ("diameter", "mm"), ("thickness", "mm"),
         ("radius", "mm"), ("gap", "mm"), ("pressure", "MPa"), ("failure_limit", "MPa"),
         ("fracture_energy", "N/mm"), ("end_time", "s"))
"""Unit of an input by the end of its dotted key (first match); others: the scenario format's."""


@dataclass
class Case:
    """One completed case: its id, input vector, curve samples and puncture abscissae."""

    name: str
    inputs: np.ndarray             # (D,) in the inputs' units
    abscissa: np.ndarray           # (n,) mm or s, strictly increasing
    forces: dict                   # channel -> (n,) N
    events: dict                   # event -> abscissa (mm or s)


@dataclass
class TrainingSet:
    """The completed cases of a study and what they share."""

    kind: str
    inputs: list                   # [{"name", "alias", "unit", "low", "high"}]
    abscissa: dict                 # {"name", "unit", "max"}
    channels: list                 # [{"name", "unit"}]
    events: list                   # event names modelled, in order
    cases: list                    # [Case]
    scenario: dict                 # {"scenario", "overrides"} of the study
    left_out: list                 # [{"case", "reason"}]: completed cases without an event asked for
    partial_events: dict           # event -> names of the cases without it, for events some cases lack


def unit_of(key: str) -> str:
    """The unit of a dotted scenario key, from its ending (:data:`UNITS`).

    >>> unit_of("instrument.motion.insertion.rate"), unit_of("mesh.geometry.central_thickness")
    ('mm/s', 'mm')
    """
    for ending, unit in UNITS:
        if key.endswith(ending):
            return unit
    return "scenario unit (docs/scenario-format.md)"


def aliases(keys: list[str]) -> list[str]:
    """Short names for dotted keys: the last part, or more parts joined by ``_`` when they clash.

    >>> aliases(["instrument.motion.insertion.rate", "instrument.shape.diameter"])
    ['rate', 'diameter']
    >>> aliases(["materials.stroma.failure_limit", "materials.epithelium.failure_limit"])
    ['stroma_failure_limit', 'epithelium_failure_limit']
    """
    parts = [key.split(".") for key in keys]
    for count in range(1, max(len(p) for p in parts) + 1):
        names = ["_".join(p[-count:]) for p in parts]
        if len(set(names)) == len(names):
            return names
    return [key.replace(".", "_") for key in keys]


def read_study(directories, events=None) -> TrainingSet:
    """The completed cases of the study in ``directories`` (see the module docstring).

    ``directories``: one study folder, or several studies of the same scenario, fixed
    overrides and parameters (a first design and the cases added where it was too sparse, say),
    whose cases are then named ``<folder>/<case>``. ``events``: the puncture events to model
    (names of :data:`EVENT_ORDER`); None: those of every completed case.
    """
    folders = study_folders(directories)
    spec, keys, rows = _completed(folders)
    where = ", ".join(map(str, folders))
    if len(rows) < 3:
        raise InputError(f"{where}: {len(rows)} completed case(s); a surrogate needs at least 3")
    kind = _kind(rows[0][0] / "cases" / str(rows[0][1]["case"]))
    abscissa_name, abscissa_unit, channels = CURVES[kind]
    cases = [_case(folder / "cases" / str(row["case"]), np.array([float(row[key]) for key in keys]), kind)
             for folder, row in rows]
    if len(folders) > 1:
        for case, (folder, _) in zip(cases, rows):
            case.name = f"{folder.name}/{case.name}"
    lacking = {e: [case.name for case in cases if e not in case.events] for e in EVENT_ORDER}
    partial = {e: names for e, names in lacking.items() if 0 < len(names) < len(cases)}
    if events is None:
        events = [e for e in EVENT_ORDER if not lacking[e]]
    else:
        unknown = [e for e in events if e not in EVENT_ORDER]
        if unknown:
            raise InputError(f"events: unknown event {unknown[0]!r}; expected some of {', '.join(EVENT_ORDER)}")
        events = [e for e in EVENT_ORDER if e in events]
    left_out = [{"case": case.name, "reason": "no " + ", ".join(e for e in events if e not in case.events)
                 + f" puncture by {abscissa_name} {case.abscissa[-1]:.4g}"}
                for case in cases if any(e not in case.events for e in events)]
    cases = [case for case in cases if all(e in case.events for e in events)]
    if len(cases) < 3:
        raise InputError(f"{where}: {len(cases)} completed case(s) with a puncture of each of "
                         f"{', '.join(events)}; a surrogate needs at least 3")
    values = np.array([case.inputs for case in cases])
    varied = [k for k in range(len(keys)) if np.ptp(values[:, k]) > 0.0]
    if not varied:
        raise InputError(f"{where}: no parameter varies across the completed cases")
    for case in cases:
        case.inputs = case.inputs[varied]
    names = [keys[k] for k in varied]
    return TrainingSet(
        kind=kind,
        inputs=[{"name": name, "alias": alias, "unit": unit_of(name),
                 "low": float(values[:, k].min()), "high": float(values[:, k].max())}
                for name, alias, k in zip(names, aliases(names), varied)],
        abscissa={"name": abscissa_name, "unit": abscissa_unit,
                  "max": float(min(case.abscissa[-1] for case in cases))},
        channels=[{"name": name, "unit": "N"} for name in channels],
        events=events, cases=cases,
        scenario={"scenario": spec.get("scenario"), "overrides": spec.get("overrides", {})},
        left_out=left_out, partial_events=partial,
    )


def study_folders(directories) -> list[Path]:
    """One study folder or several, as a list of paths.

    >>> study_folders("results/speed"), study_folders(["a", "b"])
    ([PosixPath('results/speed')], [PosixPath('a'), PosixPath('b')])
    """
    return [Path(directories)] if isinstance(directories, (str, Path)) else [Path(d) for d in directories]


def _completed(folders: list) -> tuple[dict, list, list]:
    """The first study's spec, its parameter keys and the (folder, row) of every completed case;
    the studies must share the scenario, the fixed overrides and the parameters."""
    specs = [_spec(folder) for folder in folders]
    spec, keys = specs[0], list(specs[0].get("parameters", {}))
    for folder, other in zip(folders[1:], specs[1:]):
        for part, a, b in (("scenario", spec.get("scenario"), other.get("scenario")),
                           ("overrides", spec.get("overrides", {}), other.get("overrides", {})),
                           ("parameters", sorted(keys), sorted(other.get("parameters", {})))):
            if a != b:
                raise InputError(f"{folder}: its study's {part} ({b}) differ from {folders[0]}'s ({a}); "
                                 "one surrogate learns studies of one scenario over the same inputs")
    rows = []
    for folder in folders:
        table = _table(folder)
        missing = [key for key in keys + ["case", "status"] if key not in table]
        if missing:
            raise InputError(f"{folder}: results table has no column {missing[0]!r}")
        rows += [(folder, row) for row in table.to_dict("records") if row["status"] == "completed"]
    return spec, keys, rows


def _spec(directory: Path) -> dict:
    spec_path = directory / "study.toml"
    if not spec_path.is_file():
        raise InputError(f"{directory}: no study.toml (not a study folder)")
    with open(spec_path, "rb") as handle:
        return tomllib.load(handle)


def _table(directory: Path):
    import pandas as pd

    for name, reader in (("results.parquet", pd.read_parquet), ("results.csv", pd.read_csv)):
        if (directory / name).is_file():
            return reader(directory / name)
    raise InputError(f"{directory}: no results.parquet or results.csv (run the study first)")


def _kind(case: Path) -> str:
    path = case / "scenario.toml"
    try:
        with open(path, "rb") as handle:
            kind = tomllib.load(handle).get("kind")
    except OSError:
        raise InputError(f"{path}: missing (a completed case without its scenario)") from None
    if kind not in CURVES:
        raise InputError(f"{path}: kind {kind!r}; a surrogate learns needle or trephine cases")
    return kind


def _case(folder: Path, inputs: np.ndarray, kind: str) -> Case:
    abscissa_name, _, channels = CURVES[kind]
    try:
        history = np.genfromtxt(folder / "history.csv", delimiter=",", names=True)
        with open(folder / "summary.json") as handle:
            summary = json.load(handle)
    except OSError as error:
        raise InputError(f"{folder}: unreadable case ({error.strerror}: {error.filename})") from None
    for column in (abscissa_name, *channels):
        if column not in (history.dtype.names or ()):
            raise InputError(f"{folder / 'history.csv'}: no column {column!r}")
    a = np.asarray(history[abscissa_name], dtype=float)
    keep = a > np.maximum.accumulate(np.concatenate(([-np.inf], a[:-1])))  # strictly increasing samples
    events = {p["event"]: float(p[abscissa_name]) for p in summary.get("punctures", [])}
    return Case(folder.name, inputs, a[keep], {c: np.asarray(history[c], dtype=float)[keep] for c in channels},
                events)
