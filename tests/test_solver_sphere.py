"""Thick hollow sphere under internal pressure, settled quasi-statically, against Lame.

u_r(R) = p a^3 / (E (b^3 - a^3)) [(1 - 2 nu) R + (1 + nu) b^3 / (2 R^2)]
(Timoshenko & Goodier, Theory of Elasticity, 3rd ed., sec. 136). The pressure rises with a
smooth step and mass-proportional damping settles the sphere (the preload stage).
"""

import numpy as np

from corneasim.materials import KernelMaterial
from corneasim.solver import Pressure, SymmetryPlane, build_model, new_state, preload
from corneasim.solver._amplitudes import SmoothStep
from test_solver_meshes import sphere_octant_hex, sphere_quarter_quad

INNER, OUTER = 1.0, 2.0  # mm
YOUNGS, POISSON, DENSITY, PRESSURE = 1.0, 0.3, 1.0e-9, 1.0e-3  # MPa, -, tonne/mm^3, MPa
SHEAR = YOUNGS / (2 * (1 + POISSON))
BULK = YOUNGS / (3 * (1 - 2 * POISSON))
MATERIAL = KernelMaterial(density=DENSITY, c10=SHEAR / 2, d1=2 / BULK)


def lame_radial_displacement(R):
    factor = PRESSURE * INNER ** 3 / (YOUNGS * (OUTER ** 3 - INNER ** 3))
    return factor * ((1 - 2 * POISSON) * R + (1 + POISSON) * OUTER ** 3 / (2 * R ** 2))


def settle(model):
    """Ramp the pressure over 0.5 ms and settle with damping 5e4 1/s until 2 ms."""
    state = new_state(model)
    rows = [frame.history for frame in preload(model, state, 2e-3, damping=5e4, history_every=50)
            if frame.history]
    return state, rows


def check_against_lame(model, state, rows):
    mesh = model.mesh
    x = mesh.points
    radial = np.einsum("ni,ni->n", state.u, x) / np.linalg.norm(x, axis=1)
    for name, radius in (("inner", INNER), ("outer", OUTER)):
        nodes = mesh.node_sets[name]
        exact = lame_radial_displacement(radius)
        assert np.all(np.abs(radial[nodes] / exact - 1) < 0.02), (name, radial[nodes] / exact)
    last = rows[-1]
    assert last["kinetic_energy_mJ"] < 1e-6 * last["internal_energy_mJ"]  # settled
    assert abs(last["hourglass_energy_mJ"]) < 0.05 * last["internal_energy_mJ"]
    assert max(row["energy_balance_error"] for row in rows[1:]) < 0.01


def test_axisymmetric_quarter_sphere_matches_lame():
    mesh = sphere_quarter_quad(INNER, OUTER, 4, 20)
    model = build_model(mesh, {"shell": MATERIAL}, [SymmetryPlane("equator", "z")],
                        [Pressure("inner", PRESSURE, SmoothStep(0.0, 5e-4))])
    state, rows = settle(model)
    check_against_lame(model, state, rows)


def test_hexahedral_octant_sphere_matches_lame():
    mesh = sphere_octant_hex(INNER, OUTER, 4, 4)
    model = build_model(mesh, {"shell": MATERIAL},
                        [SymmetryPlane(f"{axis}0", axis) for axis in "xyz"],
                        [Pressure("inner", PRESSURE, SmoothStep(0.0, 5e-4))])
    state, rows = settle(model)
    check_against_lame(model, state, rows)
