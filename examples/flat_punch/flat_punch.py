"""Flat-punch indentation of a two-layer disc: the general scenario path, checked against Sneddon.

A rigid, frictionless, flat-ended cylindrical punch of radius a pressed a depth delta into an
elastic half-space (Young's modulus E, Poisson's ratio nu) needs the force (Sneddon 1965,
Int. J. Eng. Sci. 3:47; Johnson, *Contact Mechanics*, 1985, ch. 3)

    F = 2 a E* delta,    E* = E / (1 - nu^2),

so its small-depth stiffness is K = dF/d(delta) = 2 a E / (1 - nu^2), whatever the depth, as
long as strains are small. The contact pressure is p(r) = F / (2 pi a sqrt(a^2 - r^2)):
singular at the punch edge, which is what the mesh must resolve.

The model (files next to this script):

* ``make_mesh.py`` writes ``disc.inp``: an axisymmetric disc of radius 50 a and thickness
  50 a meshed with structured quads, fine (a / 10.5) under the punch and growing by 1.2
  outward, with two blocks (``top_layer``, 0.5 a thick, and ``substrate``) and the node
  sets ``bottom`` (bonded to a rigid base) and ``axis``. The node spacing puts the punch edge
  half-way between two nodes, so the contact nodes' tributary area is exactly pi a^2.
* ``flat_punch.toml`` is the scenario: the mesh file, one material file per block
  (``materials/*.toml``, linear elastic at small strain), the fixed bottom, a rigid flat
  needle of diameter 2a as the instrument moving at 0.5 mm/s (linear amplitude), frictionless
  penalty contact, and a history column ``base_force_N`` (the reaction of the base).

Why the numbers are what they are (and why it is "quasi-static"): the disc's P-wave speed
is sqrt(M / rho) = 37 m/s (M = E (1 - nu) / ((1 + nu)(1 - 2 nu)) = 1.35 MPa), so a wave crosses
the 25 mm disc in 0.7 ms; the punch takes 11 ms, about 15 crossings, and the kinetic energy
stays below 0.1% of the strain energy once the punch bears. The half-space is truncated at
50 a: a base at depth h makes the stiffness larger by about (3 - 2 nu) a / (pi (1 - nu) h)
(the half-space displacement under a point load at depth h), +2% here, while the free rim
makes it slightly softer. The penalty contact adds a spring in series (the punch penetrates
the surface a little); its stiffness k = alpha m / dt^2 per node scales with the time step,
so the scenario runs at a safety factor 0.6 with alpha = 2 (stable for alpha < 4 (1 - 0.6^2)).

Run: ``python examples/flat_punch/flat_punch.py [default|tiny]``; it runs the homogeneous
check (both blocks ``substrate``) and then the layered disc, and prints

* the homogeneous stiffness against Sneddon's 2 a E / (1 - nu^2) = 1.099 N/mm (measured:
  1.057 N/mm, ratio 0.962; 0.986 with the mesh twice as fine: the error is first order in
  the element size, from the edge singularity, plus about 1% for the penalty spring);
* the layered stiffness, between Sneddon's values for the substrate and for the top layer.

The layered disc (a 10x stiffer top layer of thickness a/2): under a punch much narrower
than the layer, the punch would see only the layer (K -> 2 a E_1 / (1 - nu^2)); much wider,
the substrate. At a/t = 2 the stress bulb under the punch (depth ~ a) reaches well into the
substrate, which carries most of the compliance: the stiffness is 1.55 times the substrate's
and only 0.15 times the layer's. The stiff layer acts as a plate that spreads the punch load
over a wider patch of the soft substrate. A heuristic (not a closed form): a plate of bending
stiffness D = E_1 t^3 / (12 (1 - nu^2)) on an elastic half-space bends over the length
l = (2 D (1 - nu^2) / E_2)^(1/3) = t (E_1 / (6 E_2))^(1/3) = 0.30 mm, and a punch of radius a + l
on the bare substrate has K = 2 (a + l) E_2 / (1 - nu^2) = 1.75 N/mm, close to the 1.70 N/mm
computed (:func:`spread_stiffness`). First-order weight-function models of coated half-spaces
(Gao, Chiu & Lee 1992) assume a small modulus mismatch and overestimate this case (3.8 N/mm).

The same command line run: ``corneasim run examples/flat_punch/flat_punch.toml --out
results/flat_punch`` (``disc.inp`` is shipped; ``make_mesh.py`` rewrites it); add ``--set
materials.top_layer.material=materials/substrate.toml`` for the homogeneous disc.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import corneasim

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from make_mesh import disc_mesh  # noqa: E402  (the sibling script)

SCENARIO = HERE / "flat_punch.toml"
PUNCH_RADIUS = 0.5
"""a, mm (the scenario's needle diameter is 2a)."""
START_GAP = 0.0005
"""Gap between the punch and the surface at t = 0, mm (the scenario's instrument.start_gap)."""
SUBSTRATE = (1.0, 0.3)
"""E (MPa) and nu of ``materials/substrate.toml``."""
TOP_LAYER = (10.0, 0.3)
"""E (MPa) and nu of ``materials/top_layer.toml``."""
LAYER_THICKNESS = 0.25
"""t, mm."""
SIZES = {
    "default": dict(elements_under_punch=10, radius=25.0, thickness=25.0, growth=1.2),
    "tiny": dict(elements_under_punch=6, radius=15.0, thickness=15.0, growth=1.3),
}
"""Mesh parameters of :func:`make_mesh.disc_mesh` per size (mm)."""


def sneddon_stiffness(punch_radius: float, youngs_modulus: float, poisson_ratio: float) -> float:
    """K = 2 a E / (1 - nu^2), N/mm: flat rigid punch on an elastic half-space (Sneddon 1965)."""
    return 2.0 * punch_radius * youngs_modulus / (1.0 - poisson_ratio ** 2)


def spread_stiffness(punch_radius: float, layer_thickness: float, layer_modulus: float,
                     substrate_modulus: float, poisson_ratio: float) -> float:
    """Heuristic stiffness of a punch on a stiff plate over a soft half-space, N/mm.

    K = 2 (a + l) E_2 / (1 - nu^2) with the plate's bending length on the half-space
    l = (2 D (1 - nu^2) / E_2)^(1/3) = t (E_1 / (6 E_2))^(1/3), D = E_1 t^3 / (12 (1 - nu^2)):
    the punch acts as if widened by the distance over which the plate spreads its load.
    """
    bending_length = layer_thickness * (layer_modulus / (6.0 * substrate_modulus)) ** (1.0 / 3.0)
    return sneddon_stiffness(punch_radius + bending_length, substrate_modulus, poisson_ratio)


def indentation_stiffness(history: dict, start_gap: float = START_GAP, fit_from: float = 0.3) -> float:
    """Least-squares slope dF/d(delta) of the punch force against the indentation, N/mm.

    delta = punch travel - ``start_gap``; the fit uses the rows with delta >= ``fit_from`` times
    the final indentation (after the first contact transient).
    """
    indentation = history["depth_mm"] - start_gap
    force = history["force_N"]
    rows = indentation >= fit_from * indentation[-1]
    return float(np.polyfit(indentation[rows], force[rows], 1)[0])


def run_case(mesh_file: Path, layered: bool, overrides: list[str] = (), out_dir: Path | None = None):
    """Run the scenario on ``mesh_file``: layered, or with the substrate material in both blocks."""
    settings = [f"mesh.file={mesh_file.resolve()}"]
    if not layered:
        settings.append("materials.top_layer.material=materials/substrate.toml")
    return corneasim.run_scenario(SCENARIO, settings + list(overrides), out_dir=out_dir)


def main(size: str = "default", work_dir: str | Path | None = None, overrides: list[str] = ()) -> dict:
    """Mesh, run the homogeneous and the layered disc, print and return the stiffnesses (N/mm)."""
    if size not in SIZES:
        raise SystemExit(f"size must be one of {', '.join(SIZES)}")
    work = Path(work_dir) if work_dir is not None else HERE
    mesh_file = corneasim.mesh.write_mesh(
        disc_mesh(PUNCH_RADIUS, layer_thickness=LAYER_THICKNESS, **SIZES[size]),
        work / ("disc.inp" if size == "default" else f"disc-{size}.inp"))
    reference = sneddon_stiffness(PUNCH_RADIUS, *SUBSTRATE)
    homogeneous = run_case(mesh_file, layered=False, overrides=overrides)
    stiffness = indentation_stiffness(homogeneous.history)
    print(f"homogeneous disc: K = {stiffness:.4f} N/mm, Sneddon 2aE/(1-nu^2) = {reference:.4f} N/mm, "
          f"ratio {stiffness / reference:.3f}")
    layered = run_case(mesh_file, layered=True, overrides=overrides)
    layered_stiffness = indentation_stiffness(layered.history)
    layer_reference = sneddon_stiffness(PUNCH_RADIUS, *TOP_LAYER)
    spread = spread_stiffness(PUNCH_RADIUS, LAYER_THICKNESS, TOP_LAYER[0], SUBSTRATE[0], SUBSTRATE[1])
    print(f"layered disc:     K = {layered_stiffness:.4f} N/mm = {layered_stiffness / reference:.2f} x the "
          f"substrate's, {layered_stiffness / layer_reference:.2f} x the top layer's Sneddon stiffness "
          f"(plate-spreading heuristic {spread:.3f} N/mm)")
    return {"reference": reference, "homogeneous": stiffness, "layered": layered_stiffness,
            "layer_reference": layer_reference, "spread": spread,
            "results": {"homogeneous": homogeneous, "layered": layered}}


if __name__ == "__main__":
    main(*sys.argv[1:2])
