"""Needle scenario on eye meshes refined only near the needle path (an experiment, not a preset).

Mass scaling to the needle paper's target step (2e-5 s) gives an element of a 2D
axisymmetric mesh the scaled mass rho 2 pi r (dt* c / (s L_min))^2 A: the scaled density
grows as 1 / L_min^2 (L_min the element's smallest dimension) and the ring's mass with r,
so the artificial mass of a region is rho (dt* c / s)^2 times the integral of 2 pi r / L_min^2
over its section, whatever the element count. The built-in ``default`` mesh keeps 72
element layers (7.7 um thick) out to 2 mm from the axis, and that mass (about 1e-3 t within
1 mm of the axis, 10^4 times the physical mass of the whole eye) is what oscillates under
the needle (docs/calibration.md, "Mass scaling"). The variants below keep the default's
7.7 um elements only within ``fine_radius`` of the axis and coarsen sooner: ``g1``, ``g2``
keep three epithelium layers (22 um) out to the pole; the ``p*`` variants
also merge the epithelium to one layer and coarsen the sclera a third time.

Writes ``OUT/NAME.inp`` and ``OUT/NAME.toml`` (the built-in needle scenario reading that
mesh) and prints the element count, the smallest element dimension near the axis and the
scaled mass at ``--target`` within 1 mm of the axis and in total; run the scenario with
``corneasim run OUT/NAME.toml [--speed 5] [--set solver.target_time_step=2e-5]``.

Usage::

    python validation/needle_graded_mesh.py --variant p17 --out results/graded-mesh
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import corneasim.materials
from corneasim.mesh import axisymmetric
from corneasim.mesh._strip import Zone
from corneasim.mesh import write_mesh
from corneasim.mesh._quality import characteristic_lengths, corner_jacobians
from corneasim.scenarios import build
from corneasim.solver import elements as element_kernels
from corneasim.scenarios import load_scenario, scenario_text

PRESETS = Path(corneasim.materials.__file__).resolve().parent / "presets"

def _needle_path_family(fine_radius: float, transition_end: float) -> axisymmetric.StripPreset:
    """The t-variants: the default's 7.7 um columns out to ``fine_radius`` (mm of anterior plan
    radius), 23-35 um columns to ``transition_end`` (mm), then 70-120 um to the limbus (one
    epithelium layer) and 0.25-0.3 mm in the sclera; t25 = (0.25, 0.7) is the zones of the
    ``needle-path`` preset."""
    return axisymmetric.StripPreset(9, 63, (
        Zone(fine_radius, 0.0077, 0.0077, 0, True),
        Zone(transition_end, 0.023, 0.035, 1),
        Zone("limbus", 0.07, 0.12, 2),
        Zone("pole", 0.25, 0.3, 3),
    ), epithelium_levels=2)


VARIANTS = {
    "g1": axisymmetric.StripPreset(9, 63, (
        Zone(0.3, 0.0077, 0.0077, 0, True),
        Zone(0.6, 0.0077, 0.023, 0, True),
        Zone(1.5, 0.025, 0.05, 1),
        Zone(4.2, 0.05, 0.1, 2),
        Zone("limbus", 0.1, 0.1, 2),
        Zone("pole", 0.1, 0.1, 2),
    )),
    "g2": axisymmetric.StripPreset(9, 63, (
        Zone(0.25, 0.0077, 0.0077, 0, True),
        Zone(0.5, 0.0077, 0.02, 0, True),
        Zone(1.2, 0.025, 0.06, 1),
        Zone(4.2, 0.07, 0.1, 2),
        Zone("limbus", 0.1, 0.1, 2),
        Zone("pole", 0.1, 0.1, 2),
    )),
    # p variants: the epithelium merges to one layer at level 2, the sclera is level 3
    "p9": axisymmetric.StripPreset(9, 63, (
        Zone(0.3, 0.0077, 0.0077, 0, True),
        Zone(0.6, 0.0077, 0.023, 0, True),
        Zone(1.5, 0.023, 0.06, 1),
        Zone("limbus", 0.07, 0.12, 2),
        Zone("pole", 0.25, 0.3, 3),
    ), epithelium_levels=2),
    # t25 is the zones of the preset ``needle-path`` (a file mesh: round-off differs from the preset)
    "t25": _needle_path_family(0.25, 0.7),
    "t20": _needle_path_family(0.2, 0.7),
    "t30": _needle_path_family(0.3, 0.75),
    "t25b": _needle_path_family(0.25, 1.0),
    "t35": _needle_path_family(0.35, 0.8),
    "t25w": axisymmetric.StripPreset(9, 63, (
        Zone(0.25, 0.0077, 0.0077, 0, True),
        Zone(2.0, 0.023, 0.023, 1),
        Zone("limbus", 0.07, 0.1, 2),
        Zone("pole", 0.1, 0.1, 2),
    ), epithelium_levels=2),
    "t25x": axisymmetric.StripPreset(9, 63, (
        Zone(0.25, 0.0077, 0.0077, 0, True),
        Zone(2.5, 0.023, 0.023, 1),
        Zone("limbus", 0.023, 0.05, 1),
        Zone("pole", 0.05, 0.05, 2),
    ), epithelium_levels=2),
    "p17": axisymmetric.StripPreset(9, 63, (
        Zone(0.9, 0.0077, 0.0077, 0, True),
        Zone(1.4, 0.0077, 0.023, 0, True),
        Zone(2.5, 0.023, 0.06, 1),
        Zone("limbus", 0.07, 0.12, 2),
        Zone("pole", 0.25, 0.3, 3),
    ), epithelium_levels=2),
    "n17": axisymmetric.StripPreset(9, 63, (
        Zone(1.5, 0.0077, 0.0077, 0, True),
        Zone(1.9, 0.0077, 0.023, 0, True),
        Zone(3.0, 0.023, 0.06, 1),
        Zone("limbus", 0.07, 0.12, 2),
        Zone("pole", 0.25, 0.3, 3),
    ), epithelium_levels=2),
    "p17f": axisymmetric.StripPreset(12, 87, (
        Zone(0.45, 0.0056, 0.0056, 0, True),
        Zone(0.8, 0.0056, 0.017, 0, True),
        Zone(1.8, 0.017, 0.05, 1),
        Zone("limbus", 0.06, 0.12, 2),
        Zone("pole", 0.25, 0.3, 3),
    ), epithelium_levels=2),
}
"""Zones (end of zone as anterior plan radius in mm, column widths in mm, refinement level)
of the variants; the default preset's are in ``corneasim.mesh._axisymmetric``."""


def mesh_of(name: str):
    """The mesh of variant ``name`` (or of a built-in preset)."""
    presets = axisymmetric.AXISYMMETRIC_PRESETS
    if name in presets:
        return axisymmetric.mesh_axisymmetric(preset=name)
    presets[name] = VARIANTS[name]
    try:
        return axisymmetric.mesh_axisymmetric(preset=name)
    finally:
        del presets[name]


def stroma_material(c10: float, c20: float, out: Path) -> Path:
    """Write the ``cornea-needle`` stroma with Yeoh C10, C20 (MPa) replaced into ``out``; return its path."""
    lines = [f"# The cornea-needle preset with C10 = {c10:g}, C20 = {c20:g} MPa (validation/needle_graded_mesh.py)."]
    for line in (PRESETS / "cornea-needle.toml").read_text().splitlines():
        key = line.split("=")[0].strip()
        if line.startswith("#"):
            continue
        if key == "name":
            line = f'name = "cornea-needle-{c10:g}-{c20:g}"'
        elif key == "description":
            line = f'description = "cornea-needle with Yeoh C10 = {c10:g}, C20 = {c20:g} MPa (a calibration variant)"'
        elif key in ("c10", "c20"):
            line = f"{key} = {c10 if key == 'c10' else c20!r}"
        lines.append(line)
    path = out.resolve() / f"stroma-yeoh-{c10:g}-{c20:g}.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def write_variant(name: str, out: Path, stroma_yeoh: tuple[float, float] | None = None) -> Path:
    """Write the mesh (variants only) and the scenario of ``name`` into ``out``; return the scenario path.

    A built-in preset is named in the scenario (``[mesh] preset``), a variant is written as
    ``OUT/NAME.inp``. ``stroma_yeoh`` = (C10, C20) in MPa replaces the stroma's Yeoh constants.
    """
    out.mkdir(parents=True, exist_ok=True)
    mesh = mesh_of(name)
    if name in axisymmetric.AXISYMMETRIC_PRESETS:
        source = f'[mesh]\ngenerator = "eye-axisymmetric"\npreset = "{name}"\n\n'
    else:
        source = f'[mesh]\nfile = "{write_mesh(mesh, out / f"{name}.inp").resolve()}"\n\n'
    text = scenario_text("needle")
    start, end = text.index("[mesh]"), text.index("[materials]")
    text = text[:start] + source + text[end:]
    stem = name
    if stroma_yeoh is not None:
        material = stroma_material(*stroma_yeoh, out)
        assert 'material = "cornea-needle"' in text
        text = text.replace('material = "cornea-needle"', f'material = "{material}"')
        stem = f"{name}-yeoh-{stroma_yeoh[0]:g}-{stroma_yeoh[1]:g}"
    scenario = out / f"{stem}.toml"
    scenario.write_text(text)
    print(f"{name}: {mesh.n_elements} elements ({mesh.element_sets['refined'].size} refined) -> {scenario}")
    return scenario


def mass_report(scenario: Path, target: float) -> dict:
    """Scaled and physical masses (tonne) of the scenario's model at target step ``target`` (s).

    ``near``: nodes within 1 mm of the axis and 1.5 mm of the apex height (the cornea under
    the needle, not the posterior pole); ``total``: all nodes. Also the element count, the
    smallest corner Jacobian and the smallest element dimension within 0.1 mm of the axis.
    """
    setup = build(load_scenario(str(scenario), [f"solver.target_time_step={target}"])[0],
                  scenario.parent)
    mesh, model = setup.mesh, setup.model
    r, z = mesh.points[:, 0], mesh.points[:, 1]
    near = (r <= 1.0) & (z >= z.max() - 1.5)
    physical = element_kernels.lumped_masses(model.elements, np.ones(mesh.n_elements))
    centre = mesh.points[mesh.cells].mean(axis=1)
    axis = (centre[:, 0] <= 0.1) & (centre[:, 1] >= z.max() - 0.6)
    return {
        "elements": mesh.n_elements,
        "min_jacobian": float(corner_jacobians(mesh).min()),
        "axis_length_mm": float(characteristic_lengths(mesh)[axis].min()),
        "near_scaled_t": float(model.mass[near].sum()),
        "total_scaled_t": float(model.mass.sum()),
        "total_physical_t": float(physical.sum()),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", choices=sorted(VARIANTS) + sorted(axisymmetric.AXISYMMETRIC_PRESETS),
                        default="t25")
    parser.add_argument("--out", type=Path, default=Path("results/graded-mesh"))
    parser.add_argument("--target", type=float, default=2e-5,
                        help="target step for the mass report, s (default 2e-5)")
    parser.add_argument("--stroma-yeoh", metavar="C10,C20",
                        help="replace the stroma's Yeoh constants (MPa), e.g. 1.1,1200")
    arguments = parser.parse_args()
    yeoh = tuple(float(v) for v in arguments.stroma_yeoh.split(",")) if arguments.stroma_yeoh else None
    scenario = write_variant(arguments.variant, arguments.out, yeoh)
    report = mass_report(scenario, arguments.target)
    print(f"{arguments.variant}: elements {report['elements']}, min corner Jacobian "
          f"{report['min_jacobian']:.3f}, L_min at the axis {1e3 * report['axis_length_mm']:.2f} um, "
          f"scaled mass at {arguments.target:g} s: {report['near_scaled_t']:.3g} t within r = 1 mm, "
          f"{report['total_scaled_t']:.3g} t in total (physical {report['total_physical_t']:.3g} t)")


if __name__ == "__main__":
    main()
