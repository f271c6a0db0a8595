"""Published ranges of the eye models' constants, and the check of a material or scenario against them.

The ranges live in ``materials/published_ranges.toml`` (one ``[[range]]`` per constant: key
``tissue.quantity``, unit, low, high, species, tissue, cite, source, verified, notes; docs/materials.md,
"Published ranges"). A range without ``low``/``high`` names its source but no readable number
(``verified = false``): constants checked against it are reported, never flagged.

* :func:`published_ranges` reads and validates the file;
* :func:`material_constants` gives the constants of a material preset used as a tissue, under
  the keys of the file (moduli at small strain, failure limit, density, Prony fraction);
* :func:`check_constants` compares a ``{key: value}`` mapping (a material's, a scenario's
  fracture constants, or any synthetic one) with the ranges; :func:`out_of_range` keeps the
  constants that lie outside.

Units: those of each range (MPa, N/mm, tonne/mm^3, degrees; dimensionless otherwise).
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from collections.abc import Mapping
from functools import cache
from importlib import resources
from pathlib import Path

from corneasim.errors import InputError

RANGES_FILE = "published_ranges.toml"
TISSUES = ("stroma", "epithelium", "sclera")
SECANT_STRETCH = 1.01
"""Stretch of the small-strain in-plane secant modulus P(1.01) / 0.01 (key ``*.in_plane_modulus``)."""

_FIELDS = ("key", "unit", "species", "tissue", "cite", "source", "verified", "notes")


@dataclasses.dataclass(frozen=True)
class PublishedRange:
    """One constant's published range (units: ``unit``); ``low``/``high`` are None when not verified.

    ``cite`` is a short citation for one-line reports, ``source`` the full one.
    """

    key: str
    unit: str
    low: float | None
    high: float | None
    species: str
    tissue: str
    cite: str
    source: str
    verified: bool
    notes: str = ""

    @property
    def bounded(self) -> bool:
        """True when the range has numbers to check against."""
        return self.low is not None and self.high is not None


@dataclasses.dataclass(frozen=True)
class RangeCheck:
    """A constant against its range: ``status`` is inside, below, above, or unverified (no numbers)."""

    key: str
    value: float
    range: PublishedRange
    status: str

    @property
    def outside(self) -> bool:
        """True when the value lies below or above a verified range."""
        return self.status in ("below", "above")

    def format(self) -> str:
        """One line: key, value, range and unit, status, short citation."""
        r = self.range
        span = f"{r.low:.4g} .. {r.high:.4g}" if r.bounded else "no verified range"
        return f"{self.key:32s} {self.value:11.4g}  {span:>22s} {r.unit:10s} {self.status:10s} {r.cite}"


def _parse(entry: dict, index: int) -> PublishedRange:
    where = f"{RANGES_FILE}: range[{index}]"
    missing = [name for name in _FIELDS if name not in entry and name != "notes"]
    if missing:
        raise InputError(f"{where}: missing key '{missing[0]}'")
    unknown = sorted(set(entry) - set(_FIELDS) - {"low", "high"})
    if unknown:
        raise InputError(f"{where}: unknown key '{unknown[0]}'")
    low, high = entry.get("low"), entry.get("high")
    if (low is None) != (high is None):
        raise InputError(f"{where} ({entry['key']}): give both low and high, or neither")
    if low is not None and not float(low) <= float(high):
        raise InputError(f"{where} ({entry['key']}): expected low <= high, got {low} > {high}")
    if low is None and entry["verified"]:
        raise InputError(f"{where} ({entry['key']}): a range without numbers must have verified = false")
    if not str(entry["source"]).strip():
        raise InputError(f"{where} ({entry['key']}): empty source")
    return PublishedRange(key=entry["key"], unit=entry["unit"],
                          low=None if low is None else float(low), high=None if high is None else float(high),
                          species=entry["species"], tissue=entry["tissue"], cite=entry["cite"],
                          source=entry["source"],
                          verified=bool(entry["verified"]), notes=entry.get("notes", ""))


def parse_ranges(text: str) -> dict[str, PublishedRange]:
    """Ranges from the TOML text of a ranges file, by key (validated: one-line InputError)."""
    try:
        entries = tomllib.loads(text).get("range", [])
    except tomllib.TOMLDecodeError as error:
        raise InputError(f"{RANGES_FILE}: {error}") from None
    ranges = {}
    for index, entry in enumerate(entries):
        item = _parse(entry, index)
        if item.key in ranges:
            raise InputError(f"{RANGES_FILE}: range[{index}]: duplicate key '{item.key}'")
        ranges[item.key] = item
    return ranges


@cache
def published_ranges() -> dict[str, PublishedRange]:
    """The shipped ranges (``materials/published_ranges.toml``), by key."""
    return parse_ranges(resources.files("corneasim.materials").joinpath(RANGES_FILE).read_text())


def check_constants(values: Mapping[str, float],
                    ranges: Mapping[str, PublishedRange] | None = None) -> list[RangeCheck]:
    """Each constant of ``values`` that has a range, against it (in the order of ``values``).

    Parameters
    ----------
    values : mapping of str to float
        Constants by range key (``tissue.quantity``), in the range's unit.
    ranges : mapping, optional
        Ranges by key (default: :func:`published_ranges`).
    """
    ranges = published_ranges() if ranges is None else ranges
    checks = []
    for key, value in values.items():
        if key not in ranges:
            continue
        r = ranges[key]
        if not r.bounded:
            status = "unverified"
        elif value < r.low:
            status = "below"
        elif value > r.high:
            status = "above"
        else:
            status = "inside"
        checks.append(RangeCheck(key=key, value=float(value), range=r, status=status))
    return checks


def out_of_range(values: Mapping[str, float],
                 ranges: Mapping[str, PublishedRange] | None = None) -> list[RangeCheck]:
    """The constants of ``values`` outside their verified ranges (see :func:`check_constants`)."""
    return [check for check in check_constants(values, ranges) if check.outside]


def in_plane_modulus(spec) -> float:
    """Small-strain in-plane secant modulus P(1.01) / 0.01 of a material in its softest in-plane direction, MPa.

    P is the incompressible uniaxial nominal stress; a fibre law is loaded along the bisector of
    its families, along one family and across it (``_fibre_homogeneous.directional_cauchy_stress``)
    and the smallest of the three is returned. Porcine strips cut in different directions differ
    by a few per cent only (docs/materials.md, "Published ranges"), so every in-plane direction
    must meet the measured modulus; for orthogonal families the bisector is the softest, and it
    is the meridian of the axisymmetric eye when the families lie at +-45 degrees from it.
    """
    from corneasim.materials._fibre_homogeneous import directional_cauchy_stress
    from corneasim.materials._laws import fibre_constants

    fibres = fibre_constants(spec.model, spec.parameters()) is not None
    directions = ("bisector", "along", "across") if fibres else ("bisector",)
    cauchy = min(float(directional_cauchy_stress(spec.model, spec.parameters(), "uniaxial", [SECANT_STRETCH],
                                                 direction)[0]) for direction in directions)
    return cauchy / SECANT_STRETCH / (SECANT_STRETCH - 1.0)


def material_constants(spec, tissue: str) -> dict[str, float]:
    """The constants of material ``spec`` used as ``tissue``, by range key.

    Parameters
    ----------
    spec : MaterialSpec
        A loaded material (``load_material``).
    tissue : str
        ``stroma``, ``epithelium`` or ``sclera``.

    Returns
    -------
    dict
        ``density`` (tonne/mm^3), ``ground_shear_modulus`` mu0 (MPa), ``in_plane_modulus`` (MPa, the
        softest in-plane direction, :func:`in_plane_modulus`), ``youngs_modulus`` (MPa) and ``poisson_ratio`` at small
        strain, ``tensile_strength`` (the failure limit, MPa, when a criterion is set),
        ``prony_long_term_fraction`` (with a Prony series) and, for a fibre law, ``fibre_k1``
        (MPa), ``fibre_k2``, ``fibre_dispersion``, ``fibre_angle`` (degrees).
    """
    from corneasim.materials._laws import fibre_constants

    if tissue not in TISSUES:
        raise InputError(f"tissue: expected one of {', '.join(TISSUES)}, got {tissue!r}")
    values = {
        "density": spec.density,
        "ground_shear_modulus": spec.initial_shear_modulus,
        "in_plane_modulus": in_plane_modulus(spec),
        "youngs_modulus": spec.youngs_modulus,
        "poisson_ratio": spec.poisson_ratio,
    }
    if spec.failure.criterion != "none":
        values["tensile_strength"] = spec.failure.limit
    if spec.viscoelastic is not None:
        values["prony_long_term_fraction"] = 1.0 - float(sum(spec.viscoelastic.weights()))
    fibres = fibre_constants(spec.model, spec.parameters())
    if fibres is not None:
        k1, k2, kappa, angle = fibres  # MPa, 1, 1, radians
        values.update(fibre_k1=k1, fibre_k2=k2, fibre_dispersion=kappa, fibre_angle=math.degrees(angle))
    return {f"{tissue}.{name}": float(value) for name, value in values.items()}


def scenario_constants(scenario, base_dir: Path = Path(".")) -> dict[str, float]:
    """The constitutive and fracture constants of a validated scenario, by range key.

    For each block named like a tissue (``stroma``, ``epithelium``, ``sclera``): the
    :func:`material_constants` of its material (without its tensile strength where the block
    has ``failure = false``), its ``failure_limit`` (MPa) as the tensile strength and a positive
    ``fracture_energy`` (N/mm) as the toughness; a ``[cohesive_cut]``'s
    strength and fracture energy for each of its blocks, and a ``[cut]``'s per block; the instrument's Coulomb friction
    coefficient (the lumped ``karnopp`` law has none) and a ``cutting_toughness`` (N/mm) as the
    toughness of stroma and epithelium.

    Parameters
    ----------
    scenario : Scenario
        As returned by ``corneasim.scenarios.load_scenario``.
    base_dir : Path
        Folder that the scenario's material file paths are relative to.
    """
    from corneasim.materials._presets import load_material
    from corneasim.scenarios._build import material_source

    values = {}
    for block, assignment in scenario.materials.items():
        if block not in TISSUES:
            continue
        values.update(material_constants(load_material(material_source(assignment.material, base_dir), warn=False),
                                         block))
        if not assignment.failure:  # the material's criterion does not act in this scenario
            values.pop(f"{block}.tensile_strength", None)
        if assignment.failure_limit is not None:
            values[f"{block}.tensile_strength"] = float(assignment.failure_limit)
        if assignment.fracture_energy > 0.0:
            values[f"{block}.toughness"] = float(assignment.fracture_energy)
    cut = scenario.cohesive_cut
    if cut is not None:
        for block in cut.blocks:
            values[f"{block}.tensile_strength"] = float(cut.strength)
            values[f"{block}.toughness"] = float(cut.fracture_energy)
    if scenario.cut is not None:  # radial cracks: a strength and a toughness per block
        for block, constants in scenario.cut.blocks.items():
            values[f"{block}.tensile_strength"] = float(constants.strength)
            values[f"{block}.toughness"] = float(constants.fracture_energy)
    if scenario.instrument is not None:
        contact = scenario.instrument.contact
        if contact.friction.law == "coulomb":
            values["contact.friction_coefficient"] = float(contact.friction.coefficient)
        if contact.cutting_toughness is not None:
            values["stroma.toughness"] = values["epithelium.toughness"] = float(contact.cutting_toughness)
    return values


def check_material(spec, tissue: str) -> list[RangeCheck]:
    """:func:`check_constants` of :func:`material_constants` (``spec`` used as ``tissue``)."""
    return check_constants(material_constants(spec, tissue))
