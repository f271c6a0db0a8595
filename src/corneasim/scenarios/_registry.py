"""Built-in scenarios and scenario files: find, read, override, validate, print.

``load_scenario("needle")`` reads the shipped ``builtin/needle.toml``; any other argument
is a path to a TOML file of the same format. Overrides (``--set KEY=VALUE``) are applied
to the raw tables before validation, so a wrong key or value is reported with its full
dotted name.
"""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path

import tomli_w

from corneasim.errors import InputError
from corneasim.scenarios._overrides import UNSET, apply_overrides, apply_settings, check_known, remove_keys
from corneasim.scenarios._format import Scenario
from corneasim.schema import load_toml, validate

BUILTIN = resources.files("corneasim.scenarios") / "builtin"


def list_scenarios() -> list[str]:
    """Names of the built-in scenarios."""
    return sorted(entry.name.removesuffix(".toml") for entry in BUILTIN.iterdir() if entry.name.endswith(".toml"))


def scenario_text(name_or_path: str) -> str:
    """The TOML text of a built-in scenario (with its comments) or of a file."""
    location = _locate(name_or_path)
    try:
        return location.read_bytes().decode("utf-8")
    except UnicodeDecodeError as error:
        raise InputError(f"{location}: not a TOML text file (not UTF-8 at byte {error.start})") from None


def _locate(name_or_path: str):
    if name_or_path in list_scenarios():
        return BUILTIN / f"{name_or_path}.toml"
    path = Path(name_or_path)
    if path.suffix == ".toml" or path.exists():
        if not path.exists():
            raise InputError(f"{path}: scenario file not found")
        return path
    raise InputError(f"unknown scenario '{name_or_path}' (built-in: {', '.join(list_scenarios())}; or a .toml file)")


def read_tables(name_or_path: str) -> tuple[dict, Path, str]:
    """The raw tables of a scenario (not validated), the folder its paths refer to, and its name.

    A TOML syntax error is an :class:`InputError` naming the file and line.
    """
    location = _locate(name_or_path)
    if name_or_path in list_scenarios():
        return tomllib.loads(location.read_text()), Path.cwd(), f"{name_or_path} (built-in)"
    return load_toml(location), location.resolve().parent, str(location)


def load_scenario(name_or_path: str, overrides: list[str] = (), unset: list[str] = (), *,
                  resolved: bool = False) -> tuple[Scenario, dict, Path]:
    """Read, override and validate a scenario.

    The presets' settings and removals apply first, then the ``overrides`` (``KEY=VALUE``), then
    the removal of the dotted keys ``unset`` (``--unset KEY``: the key takes its default).
    ``resolved``: the file is a run's resolved ``scenario.toml`` (:func:`resolved_tables`),
    whose variant's and mesh preset's settings are in its tables already and which has no
    ``presets`` table: no preset applies (its ``variant`` is the record of the one that ran).

    Returns
    -------
    scenario : Scenario
        The validated scenario.
    resolved : dict
        The fully resolved tables (defaults filled in), for ``scenario.toml`` of a run.
    base_dir : Path
        Folder that relative paths in the scenario refer to.
    """
    data, base_dir, source = read_tables(name_or_path)
    data, removed = (data, []) if resolved else with_preset(data, apply_overrides(data, list(overrides)))
    data = apply_overrides(data, list(overrides))
    data = remove_keys(data, list(unset), "--unset")
    scenario = validate(Scenario, data, source)
    for origin, key in [*removed, *(("--unset", key) for key in unset)]:
        check_known(scenario, [key], origin)
    return scenario, resolved_tables(scenario), base_dir


def with_preset(data: dict, overridden: dict) -> tuple[dict, list[tuple[str, str]]]:
    """``data`` with the settings of its ``presets`` tables for the variant and mesh preset that run.

    The variant is ``variant`` and the mesh preset ``mesh.preset`` after the overrides
    (``overridden``). The variant's settings apply first, then the mesh preset's; both go under
    the overrides, so a ``--set`` of the same key still wins. A table's ``unset = [KEY, ...]``
    removes those keys after its settings.

    Returns
    -------
    data : dict
        The tables with the presets' settings and removals.
    removed : list of (str, str)
        ``(origin, key)`` of each key a preset removed, to be checked against the validated
        scenario (:func:`~corneasim.scenarios._overrides.check_known`).
    """
    presets = overridden.get("presets")
    presets = presets if isinstance(presets, dict) else {}
    variant = overridden.get("variant")
    if variant is not None and (not isinstance(variant, str) or variant not in presets):
        names = ", ".join(sorted(presets)) or "none"
        raise InputError(f"variant: expected the name of one of the scenario's presets tables ({names}), "
                         f"got {variant!r}")
    mesh = overridden.get("mesh")
    mesh_preset = mesh.get("preset") if isinstance(mesh, dict) else None
    removed = []
    for name in (variant, mesh_preset):
        if not isinstance(name, str) or name not in presets:
            continue
        settings = presets[name]
        if not isinstance(settings, dict):
            raise InputError(f"presets.{name}: expected a table of settings, e.g. \"solver.target_time_step\" = 2e-5")
        keys = settings.get(UNSET, [])
        if not isinstance(keys, list) or not all(isinstance(key, str) for key in keys):
            raise InputError(f"presets.{name}.{UNSET}: expected a list of dotted keys, "
                             "e.g. [\"instrument.contact.cutting_toughness\"]")
        settings = {key: value for key, value in settings.items() if key != UNSET}
        data = remove_keys(apply_settings(data, settings, f"presets.{name}"), keys, f"presets.{name}.{UNSET}")
        removed.extend((f"presets.{name}.{UNSET}", key) for key in keys)
    return data, removed


def resolved_tables(scenario: Scenario) -> dict:
    """The scenario as plain TOML-ready tables, every default filled in, None values left out.

    The ``presets`` table is left out: its settings for the preset that ran are in the other
    tables already (a resumed run must not apply them over its own overrides again).
    """
    return scenario.model_dump(mode="json", exclude_none=True, exclude={"presets"})


def to_toml(tables: dict) -> str:
    """TOML text of resolved tables."""
    return tomli_w.dumps(tables)
