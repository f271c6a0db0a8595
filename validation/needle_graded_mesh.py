"""Needle scenario on eye meshes refined only near the needle path (an experiment, not a preset).

Mass scaling to the needle paper's target step (2e-5 s) gives an element of a 2D
axisymmetric mesh the scaled mass rho 2 pi r (dt* c / (s L))^2 A: for near-square elements
(A = L^2) it does not depend on the element size, so the artificial mass grows with the
number of small elements and their radius. The built-in ``default`` mesh keeps 72 element
layers (7.7 um thick) out to 2 mm from the axis, and that mass (about 1e-3 t within 1 mm of
the axis, 10^4 times the physical mass of the whole eye) is what oscillates under the needle
(docs/calibration.md, session 4). The variants below keep the default's 7.7 um elements
within ``fine_radius`` of the axis and coarsen sooner.

Writes ``OUT/NAME.inp`` and ``OUT/NAME.toml`` (the built-in needle scenario reading that
mesh); run it with ``corneasim run OUT/NAME.toml [--speed 5]``.

Usage::

    python validation/needle_graded_mesh.py --variant g1 --out results/graded-mesh
"""

from __future__ import annotations

import argparse
from pathlib import Path

from corneasim.mesh import axisymmetric
from corneasim.mesh._strip import Zone
from corneasim.mesh.io import write_mesh
from corneasim.scenarios.registry import scenario_text

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
}
"""Zones (end of zone as anterior plan radius in mm, column widths in mm, refinement level)
of the variants; the default preset's are in ``corneasim.mesh.axisymmetric``."""


def write_variant(name: str, out: Path) -> Path:
    """Write the mesh and the scenario of variant ``name`` into ``out``; return the scenario path."""
    out.mkdir(parents=True, exist_ok=True)
    presets = axisymmetric.AXISYMMETRIC_PRESETS
    presets[name] = VARIANTS[name]
    try:
        mesh = axisymmetric.mesh_axisymmetric(preset=name)
    finally:
        del presets[name]
    mesh_path = write_mesh(mesh, out / f"{name}.inp")
    text = scenario_text("needle")
    start, end = text.index("[mesh]"), text.index("[materials]")
    scenario = out / f"{name}.toml"
    scenario.write_text(text[:start] + f'[mesh]\nfile = "{mesh_path.resolve()}"\n\n' + text[end:])
    print(f"{name}: {mesh.n_elements} elements -> {scenario}")
    return scenario


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", choices=sorted(VARIANTS), default="g1")
    parser.add_argument("--out", type=Path, default=Path("results/graded-mesh"))
    arguments = parser.parse_args()
    write_variant(arguments.variant, arguments.out)


if __name__ == "__main__":
    main()
