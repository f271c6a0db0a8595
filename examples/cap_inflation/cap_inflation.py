"""Inflation of a thick hemispherical cap, checked against Lame's thick-sphere solution.

A spherical shell of inner radius a and outer radius b (linear elastic, E, nu) under an
internal pressure p displaces radially by (Lame; Timoshenko & Goodier, *Theory of
Elasticity*, 1970, sec. 141)

    u(rho) = p a^3 / (E (b^3 - a^3)) [(1 - 2 nu) rho + (1 + nu) b^3 / (2 rho^2)].

The model (``make_cap_mesh.py``, ``cap_inflation.toml``): the shell's upper half, the equator
held by symmetry, meshed with 4 x 24 axisymmetric quads, the pressure on the inner surface
ramped by the quasi-static recipe, the displacements at the outer equator and at the outer
and inner poles as history requests. At p = 0.1 kPa the strains are 1.4e-4: the follower
pressure on the grown inner surface and the finite-strain law then differ from Lame's linear
problem by about 0.05% (at 1 kPa the equator moves 0.6% more than Lame's, mesh-converged).

Run: ``python examples/cap_inflation/cap_inflation.py [default|tiny]``; it prints the three
displacements against Lame's. Measured errors (equator u_r, outer pole u_z, inner pole u_z):
tiny (2 x 12 quads) -0.31%, +4.0%, +3.7%; 4 x 24: -0.03%, +1.05%, +0.98%; default (4 x 48)
+0.02%, +0.28%, +0.26%. The poles converge at second order in the angular element size
(the error falls about 4x per halving).
"""

from __future__ import annotations

import sys
from pathlib import Path

import corneasim

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from make_cap_mesh import cap_mesh  # noqa: E402  (the sibling script)

SCENARIO = HERE / "cap_inflation.toml"
INNER, OUTER = 5.0, 6.0
"""a and b, mm."""
PRESSURE = 1.0e-4
"""p, MPa (the scenario's pressure)."""
SHELL = (1.0, 0.3)
"""E (MPa) and nu of ``materials/shell.toml``."""
SIZES = {"default": dict(radial=4, angular=48), "tiny": dict(radial=2, angular=12)}
"""Mesh divisions per size (through the thickness, around the quarter)."""


def lame_displacement(rho: float, a: float = INNER, b: float = OUTER, p: float = PRESSURE,
                      youngs_modulus: float = SHELL[0], poisson_ratio: float = SHELL[1]) -> float:
    """Radial displacement (mm) at radius ``rho`` of a thick sphere under internal pressure p (MPa)."""
    nu = poisson_ratio
    return p * a ** 3 / (youngs_modulus * (b ** 3 - a ** 3)) * ((1 - 2 * nu) * rho + (1 + nu) * b ** 3 / (2 * rho ** 2))


def main(size: str = "default", work_dir: str | Path | None = None) -> dict:
    """Mesh, run, print and return the displacements (mm) with Lame's and their relative errors."""
    if size not in SIZES:
        raise SystemExit(f"size must be one of {', '.join(SIZES)}")
    work = Path(work_dir) if work_dir is not None else HERE
    mesh = corneasim.mesh.write_mesh(cap_mesh(INNER, OUTER, **SIZES[size]),
                                     work / ("cap.inp" if size == "default" else f"cap-{size}.inp"))
    result = corneasim.run_scenario(SCENARIO, [f"mesh.file={mesh.resolve()}"])
    rows = {"outer_equator_r_mm": lame_displacement(OUTER), "outer_pole_z_mm": lame_displacement(OUTER),
            "inner_pole_z_mm": lame_displacement(INNER)}
    errors = {}
    for column, exact in rows.items():
        value = float(result.history[column][-1])
        errors[column] = value / exact - 1.0
        print(f"{column}: {value:.6g} mm, Lame {exact:.6g} mm, error {100 * errors[column]:+.2f}%")
    quasi = result.summary["quasi_static"]
    print(f"lowest period {quasi['lowest_period_s']:.3g} s (scaled {quasi['lowest_period_scaled_s']:.3g} s), "
          f"max KE/IE {quasi['max_kinetic_to_internal']:.2g}, {result.summary['run']['steps']} steps")
    return {"errors": errors, "result": result}


if __name__ == "__main__":
    main(*sys.argv[1:2])
