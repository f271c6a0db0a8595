"""``corneasim material``: Material laws: stability checks, curves, fitting, presets.

Sub-commands (units: MPa, 1/MPa, s, tonne/mm^3; see docs/materials.md):

* ``list``: the shipped presets;
* ``report``: a summary of every preset (constants, moduli, stability, stresses);
* ``check NAME|FILE [--ranges [--tissue T]]``: Drucker stability report (and each constant
  against its published range); exit 0 if stable (and inside), 1 otherwise;
* ``curve NAME|FILE --test T --stretch MIN:MAX:N --out FILE.csv [--plot PNG] [--direction D]``:
  incompressible homogeneous-test curve, columns
  ``stretch,nominal_stress_MPa,cauchy_stress_MPa``; a fibre-reinforced law is loaded along
  ``--direction`` (default the bisector of its fibre families, in the lamellar plane);
* ``test NAME|FILE --history H --strain TABLE|ramp-hold:... --out FILE.csv``: the
  material-point driver (``materials/_point_driver.py``), Prony relaxation included;
* ``fit DATA.csv --model M [--equibiaxial FILE]``: prints a material TOML block.

Bad input is one line on stderr and exit code 2.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from corneasim.errors import InputError

HELP = "Material laws: stability checks, curves, fitting, presets."
DATA_COLUMNS = ("stretch", "nominal_stress_MPa")
TISSUES = ("stroma", "epithelium", "sclera")
"""Tissues of the published ranges (``materials._ranges.TISSUES``; kept here so that building the
parser does not import the materials package)."""
DIRECTIONS = ("bisector", "along", "across", "through")
"""Loading directions of a fibre law (``materials._fibre_homogeneous.DIRECTIONS``; kept here
so that building the parser does not import Numba)."""


def register(commands: argparse._SubParsersAction) -> None:
    """Add the ``material`` command group and its sub-commands."""
    group = commands.add_parser("material", help=HELP, description=HELP)
    sub = group.add_subparsers(dest="material_command", metavar="COMMAND", required=True)

    parser = sub.add_parser("list", help="List the material presets.", description="List the material presets.",
                           epilog="example: corneasim material list")
    parser.set_defaults(handler=list_command)

    parser = sub.add_parser("report", help="Summary of every preset: constants, moduli, stability, stresses.",
                           description="Summary of every preset: constants, moduli, stability, stresses.",
                           epilog="example: corneasim material report")
    parser.set_defaults(handler=report_command)

    parser = sub.add_parser("check", help="Drucker stability report (exit 0 stable, 1 unstable).",
                           description="Drucker stability report; --ranges: constants against published ranges.",
                           epilog="example: corneasim material check cornea-needle --ranges --tissue stroma")
    parser.add_argument("material", metavar="NAME|FILE", help="Preset name or material TOML file.")
    parser.add_argument("--ranges", action="store_true",
                        help="Print each constant against its published range, one line each "
                             "(materials/published_ranges.toml, docs/materials.md 'Published ranges'); "
                             "exit 1 also when one lies outside.")
    parser.add_argument("--tissue", choices=TISSUES, default="stroma",
                        help="Tissue the material stands for, which selects the ranges (default: stroma).")
    parser.set_defaults(handler=check_command)

    parser = sub.add_parser("curve", help="Write a homogeneous-test stress-stretch curve as CSV.",
                           description="Write a homogeneous-test stress-stretch curve as CSV (stresses in MPa).",
                           epilog="example: corneasim material curve cornea --test uniaxial --stretch 1:1.3:31 "
                                  "--out curve.csv",
                           formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("material", metavar="NAME|FILE", help="Preset name or material TOML file.")
    parser.add_argument("--test", choices=("uniaxial", "equibiaxial", "planar"), default="uniaxial")
    parser.add_argument("--stretch", default="0.8:1.3:51", metavar="MIN:MAX:N",
                        help="Stretch range (dimensionless) and number of points (default 0.8:1.3:51).")
    parser.add_argument("--out", required=True, metavar="FILE.csv", help="Output CSV file.")
    parser.add_argument("--plot", metavar="PNG", help="Also write a plot of the curve.")
    parser.add_argument("--direction", choices=DIRECTIONS, default="bisector",
                        help="Loading direction of a fibre-reinforced law: bisector of the families (default), "
                             "along the first family, across it in the lamellar plane, through the thickness; "
                             "no effect on an isotropic law.")
    parser.set_defaults(handler=curve_command)

    parser = sub.add_parser("test", help="Integrate a material through a strain history at one point; write CSV.",
                           description="Integrate a material through a strain history at one point; write CSV.\n\n"
                           "A homogeneous test (uniaxial, equibiaxial or simple shear) in time, with the Prony "
                           "relaxation and the free stresses held at zero, no dynamics. Columns: time_s, strain, "
                           "the diagonal of F and F_12, Cauchy stresses and the nominal stress (MPa).",
                           epilog="example: corneasim material test cornea --history uniaxial "
                                  "--strain ramp-hold:0.05,1,10000 --out relaxation.csv",
                           formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("material", metavar="NAME|FILE", help="Preset name or material TOML file.")
    parser.add_argument("--history", required=True, choices=("uniaxial", "equibiaxial", "shear"),
                        help="Homogeneous test: strain lambda - 1 (uniaxial, equibiaxial) or gamma (shear).")
    parser.add_argument("--strain", required=True, metavar="TABLE|ramp-hold:STRAIN,RAMP_S,HOLD_S",
                        help="CSV file with columns time_s,strain, or a ramp to STRAIN over RAMP_S seconds held "
                        "HOLD_S seconds (optionally ,RAMP_STEPS,HOLD_STEPS; default 100, 200 growing steps).")
    parser.add_argument("--out", required=True, metavar="FILE.csv", help="Output CSV file.")
    parser.set_defaults(handler=test_command)

    parser = sub.add_parser("fit", help="Fit a stable law to stress-stretch data; print a material TOML block.",
                           description="Fit a stable law to stress-stretch data; print a material TOML block.",
                           epilog="example: corneasim material fit data.csv --model yeoh")
    parser.add_argument("data", metavar="DATA.csv", help="Uniaxial data, columns stretch,nominal_stress_MPa.")
    parser.add_argument("--model", required=True, choices=("yeoh", "mooney-rivlin", "neo-hooke"))
    parser.add_argument("--equibiaxial", metavar="FILE", help="Equibiaxial data, same columns.")
    parser.add_argument("--bulk-modulus", type=float, default=30.0,
                        help="Bulk modulus K in MPa for D1 = 2/K (default 30: E = 1.8 MPa, nu = 0.49).")
    parser.add_argument("--density", type=float, default=1.062e-9, help="Density, tonne/mm^3 (default 1.062e-9).")
    parser.add_argument("--name", default="fitted", help="Material name in the TOML block.")
    parser.set_defaults(handler=fit_command)


def list_command(arguments: argparse.Namespace) -> int:
    """Print preset names and descriptions."""
    from corneasim.materials import list_presets, load_material

    for name in list_presets():
        print(f"{name:<15} {load_material(name, warn=False).description}")
    return 0


def report_command(arguments: argparse.Namespace) -> int:
    """Print the summary of every preset."""
    from corneasim.materials import DEFAULT_MATERIAL, list_presets, load_material, stability_of
    from corneasim.materials._report import material_summary

    print("corneasim material presets (units: MPa, 1/MPa, s, tonne/mm^3, mm/s); "
          f"default cornea: {DEFAULT_MATERIAL!r}\n")
    for name in list_presets():
        material = load_material(name, warn=False)
        print(material_summary(material, stability_of(material)) + "\n")
    return 0


def check_command(arguments: argparse.Namespace) -> int:
    """Print the stability report (and the range checks); exit status 1 when unstable or out of range."""
    from corneasim.materials import check_material, load_material, stability_of

    material = load_material(arguments.material, warn=False)
    report = stability_of(material)
    print(report.format(f"{material.name!r} ({material.hyperelastic.model})"))
    outside = False
    if arguments.ranges:
        checks = check_material(material, arguments.tissue)
        print(f"\n{material.name!r} as {arguments.tissue}: constants against published ranges")
        for check in checks:
            print(check.format())
        outside = any(check.outside for check in checks)
    return 0 if report.stable and not outside else 1


def parse_stretch_range(text: str) -> np.ndarray:
    """Parse ``MIN:MAX:N`` into N evenly spaced stretches (0 < MIN < MAX, N >= 2)."""
    parts = text.split(":")
    try:
        low, high, count = float(parts[0]), float(parts[1]), int(parts[2])
        if len(parts) != 3:
            raise ValueError
    except (ValueError, IndexError):
        raise InputError(f"--stretch: expected MIN:MAX:N (for example 0.8:1.3:51), got {text!r}") from None
    if not (0.0 < low < high) or count < 2:
        raise InputError(f"--stretch: expected 0 < MIN < MAX and N >= 2, got {text!r}")
    return np.linspace(low, high, count)


def curve_command(arguments: argparse.Namespace) -> int:
    """Write the incompressible test curve to CSV (and a PNG when asked)."""
    from corneasim.materials import homogeneous_cauchy_stress, load_material
    from corneasim.output import atomic_write_text

    stretch = parse_stretch_range(arguments.stretch)
    material = load_material(arguments.material)
    from corneasim.materials._laws import fibre_constants

    if fibre_constants(material.model, material.parameters()) is not None:
        from corneasim.materials._fibre_homogeneous import directional_cauchy_stress

        cauchy = directional_cauchy_stress(material.model, material.parameters(), arguments.test, stretch,
                                           arguments.direction)
    else:
        cauchy = homogeneous_cauchy_stress(material.model, material.parameters(), arguments.test, stretch)
    nominal = cauchy / stretch
    lines = ["stretch,nominal_stress_MPa,cauchy_stress_MPa"]
    lines += [f"{s:.8g},{p:.8g},{c:.8g}" for s, p, c in zip(stretch, nominal, cauchy)]
    atomic_write_text(arguments.out, "\n".join(lines) + "\n")
    print(f"wrote {arguments.out} ({stretch.size} points)")
    if arguments.plot:
        _plot(stretch, nominal, cauchy, f"{material.name}: {arguments.test}, {arguments.direction}", arguments.plot)
        print(f"wrote {arguments.plot}")
    return 0


def _plot(stretch, nominal, cauchy, title: str, path: str) -> None:
    from matplotlib.figure import Figure

    figure = Figure(figsize=(5, 3.6), dpi=120)
    axes = figure.subplots()
    axes.plot(stretch, nominal, label="nominal")
    axes.plot(stretch, cauchy, "--", label="Cauchy")
    axes.axhline(0.0, color="0.7", lw=0.8)
    axes.set(xlabel="stretch", ylabel="stress (MPa)", title=title)
    axes.legend()
    figure.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path)


def test_command(arguments: argparse.Namespace) -> int:
    """Run the material-point driver and write its CSV; say how a Prony series is read."""
    import sys

    from corneasim.materials import load_material
    from corneasim.materials._point_driver import material_point_test, parse_strain_history, prony_reading, to_csv
    from corneasim.output import atomic_write_text

    material = load_material(arguments.material)
    times, strains = parse_strain_history(arguments.strain)
    note = prony_reading(material)
    if note:
        print(f"corneasim: note: {note}", file=sys.stderr)
    columns = material_point_test(material, arguments.history, times, strains)
    atomic_write_text(arguments.out, to_csv(columns))
    print(f"wrote {arguments.out} ({times.size} points, {arguments.history}, t = 0..{times[-1]:g} s)")
    return 0


def fit_command(arguments: argparse.Namespace) -> int:
    """Fit the law and print a material TOML block."""
    from corneasim.data import read_table
    from corneasim.materials import fit_hyperelastic
    from corneasim.materials._report import fit_to_toml

    if arguments.bulk_modulus <= 0.0:
        raise InputError(f"--bulk-modulus: expected a positive value in MPa, got {arguments.bulk_modulus:g}")
    if arguments.density <= 0.0:
        raise InputError(f"--density: expected a positive value in tonne/mm^3, got {arguments.density:g}")
    datasets = []
    for path in (arguments.data, arguments.equibiaxial):
        if path is None:
            datasets.append(None)
            continue
        table = read_table(path, required=DATA_COLUMNS)
        if np.any(table["stretch"] <= 0.0):
            raise InputError(f"{path}: column stretch must be > 0")
        datasets.append((table["stretch"], table["nominal_stress_MPa"]))
    result = fit_hyperelastic(arguments.model, datasets[0], datasets[1])
    source = Path(arguments.data).name + (f" and {Path(arguments.equibiaxial).name}" if arguments.equibiaxial else "")
    print(fit_to_toml(result, arguments.name, 2.0 / arguments.bulk_modulus, arguments.density, source), end="")
    return 0
