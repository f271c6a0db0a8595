"""Material presets shipped as TOML package data, and loading of user material files.

``load_material("cornea")`` reads ``materials/presets/cornea.toml``;
``load_material("path/to/file.toml")`` reads a user file (anything that ends in
``.toml`` or contains a path separator is a path). Every load checks stability
(:func:`~corneasim.materials.check_stability`) and prints a one-line warning on
stderr naming the unstable ranges of an unstable law (``seed-paper``).
"""

from __future__ import annotations

import sys
import tomllib
from importlib import resources
from pathlib import Path

from corneasim.errors import InputError
from corneasim.materials._spec import MaterialSpec
from corneasim.materials._stability import StabilityReport, check_stability
from corneasim.schema import load_toml, validate

DEFAULT_MATERIAL = "cornea"
"""The default (stable) corneal stroma preset."""


def _preset_files() -> dict[str, object]:
    folder = resources.files("corneasim.materials") / "presets"
    return {entry.name[: -len(".toml")]: entry for entry in folder.iterdir() if entry.name.endswith(".toml")}


def list_presets() -> list[str]:
    """Names of the shipped material presets, sorted."""
    return sorted(_preset_files())


def _is_path(name_or_path: str | Path) -> bool:
    text = str(name_or_path)
    return isinstance(name_or_path, Path) or text.endswith(".toml") or "/" in text or "\\" in text


def material_from_dict(data: dict, source: str) -> MaterialSpec:
    """Validate a material table (as read from TOML); errors name ``source`` and the key."""
    return validate(MaterialSpec, data, source)


def stability_of(material: MaterialSpec) -> StabilityReport:
    """Stability report of a material's hyperelastic law (incompressible, stretch 0.1-10)."""
    return check_stability(material.model, material.parameters())


def load_material(name_or_path: str | Path, warn: bool = True) -> MaterialSpec:
    """Load a preset by name or a material TOML file by path.

    Parameters
    ----------
    name_or_path : str or pathlib.Path
        Preset name (see :func:`list_presets`) or path to a ``.toml`` file.
    warn : bool
        Print a warning on stderr if the law is not stable.

    Returns
    -------
    MaterialSpec

    Raises
    ------
    corneasim.errors.InputError
        Unknown preset, unreadable file, invalid TOML or invalid content.
    """
    if _is_path(name_or_path):
        data = load_toml(name_or_path)
        material = material_from_dict(data, str(name_or_path))
    else:
        files = _preset_files()
        if name_or_path not in files:
            raise InputError(
                f"unknown material {name_or_path!r}; expected a preset ({', '.join(sorted(files))}) "
                "or a path to a .toml file"
            )
        data = tomllib.loads(files[name_or_path].read_text(encoding="utf-8"))
        material = material_from_dict(data, f"preset {name_or_path}")
    if warn:
        report = stability_of(material)
        if not report.stable:
            print(
                f"corneasim: warning: material {material.name!r} is UNSTABLE: "
                f"{report.unstable_ranges_text()} (run 'corneasim material check {name_or_path}')",
                file=sys.stderr,
            )
    return material
