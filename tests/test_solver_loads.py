"""Follower pressure against closed-form resultants; boundary-condition packing and input errors."""

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.materials import KernelMaterial
from corneasim.solver import Fixed, Prescribed, Pressure, SymmetryPlane, build_model, new_state
from corneasim.solver._pressure import eval_pressure_forces
from corneasim.solver._amplitudes import Linear
from test_solver_meshes import box_hex, box_quad

MATERIAL = KernelMaterial(density=1e-9, c10=0.2, d1=2.0)


def pressure_force(model, u, t=0.0, alive=None):
    f = np.zeros_like(model.mesh.points)
    alive = np.ones(model.n_elements, np.uint8) if alive is None else alive
    eval_pressure_forces(model.mesh.points, u, model.pressure_face_nodes, model.pressure_face_element,
                         model.pressure_value, model.pressure_amplitude,
                         model.pressure_amplitude_table, alive, t, f)
    return f


def test_hex_face_pressure_resultant_is_minus_p_area_normal():
    mesh = box_hex(2, 3, 2, 2.0, 3.0, 2.0)
    model = build_model(mesh, {"solid": MATERIAL}, [], [Pressure("x1", 0.5)])
    f = pressure_force(model, np.zeros_like(mesh.points))
    np.testing.assert_allclose(f.sum(axis=0), [-0.5 * 6.0, 0.0, 0.0], atol=1e-14)
    # interior face nodes carry a quarter of each adjacent face's load: p * 1 * 1 / 4 * 4
    centre = np.flatnonzero(np.all(np.isclose(mesh.points, [2.0, 1.0, 1.0]), axis=1))[0]
    assert np.isclose(f[centre, 0], -0.5)


def test_pressure_on_a_closed_deformed_surface_has_zero_resultant():
    mesh = box_hex(2, 2, 2, 1.0, 1.0, 1.0)
    model = build_model(mesh, {"solid": MATERIAL}, [],
                        [Pressure(name, 0.3) for name in ("x0", "x1", "y0", "y1", "z0", "z1")])
    u = 0.05 * np.random.default_rng(1).standard_normal(mesh.points.shape)
    np.testing.assert_allclose(pressure_force(model, u).sum(axis=0), 0.0, atol=1e-14)


def test_hex_face_nodal_forces_match_quadrature_on_a_warped_face():
    """Each node's share -p int N_a (x_xi x x_eta) on a warped, stretched bilinear face,
    against 5 x 5 Gauss-Legendre quadrature (exact for this integrand, cubic per direction)."""
    mesh = box_hex(1, 1, 1, 1.3, 0.8, 1.0)
    model = build_model(mesh, {"solid": MATERIAL}, [], [Pressure("z1", 0.7)])
    u = 0.2 * np.random.default_rng(3).standard_normal(mesh.points.shape)
    f = pressure_force(model, u)
    (face,) = model.pressure_face_nodes
    x = (mesh.points + u)[face]  # (4, 3), nodes at (xi, eta) = (s_a, t_a)
    s, t = np.array([-1.0, 1.0, 1.0, -1.0]), np.array([-1.0, -1.0, 1.0, 1.0])
    nodes, weights = np.polynomial.legendre.leggauss(5)
    expected = np.zeros((4, 3))
    for xi, w_xi in zip(nodes, weights):
        for eta, w_eta in zip(nodes, weights):
            shape = (1 + s * xi) * (1 + t * eta) / 4
            x_xi = ((s * (1 + t * eta) / 4)[:, None] * x).sum(axis=0)
            x_eta = ((t * (1 + s * xi) / 4)[:, None] * x).sum(axis=0)
            expected += -0.7 * w_xi * w_eta * shape[:, None] * np.cross(x_xi, x_eta)[None, :]
    np.testing.assert_allclose(f[face], expected, rtol=1e-12, atol=1e-14)


def test_pressure_follows_a_rigid_rotation():
    mesh = box_hex(1, 1, 1, 1.0, 2.0, 1.0)
    model = build_model(mesh, {"solid": MATERIAL}, [], [Pressure("x1", 1.0)])
    rotation = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # 90 deg about z
    u = mesh.points @ rotation.T - mesh.points
    np.testing.assert_allclose(pressure_force(model, u).sum(axis=0), [0.0, -2.0, 0.0], atol=1e-13)


def test_axisymmetric_disk_and_cylinder_resultants():
    mesh = box_quad(4, 2, 0.0, 2.0, 0.0, 1.0)
    model = build_model(mesh, {"solid": MATERIAL}, [], [Pressure("z1", 0.1), Pressure("r1", 0.2)])
    f = pressure_force(model, np.zeros_like(mesh.points))
    top = mesh.node_sets["z1"]
    side = mesh.node_sets["r1"]
    # top disk, radius 2: -p pi R^2 along z; side: radial ring load p 2 pi R H
    assert np.isclose(f[top, 1].sum(), -0.1 * np.pi * 4.0)
    assert np.isclose(f[side, 0].sum(), -0.2 * 2 * np.pi * 2.0 * 1.0)
    assert np.isclose(f[:, 1].sum(), -0.1 * np.pi * 4.0)


def test_dead_elements_and_amplitudes_scale_the_pressure():
    mesh = box_hex(2, 1, 1, 2.0, 1.0, 1.0)
    model = build_model(mesh, {"solid": MATERIAL}, [], [Pressure("z1", 1.0, Linear(rate=10.0))])
    u = np.zeros_like(mesh.points)
    assert np.isclose(pressure_force(model, u, t=0.1)[:, 2].sum(), -2.0)
    alive = np.array([1, 0], np.uint8)
    assert np.isclose(pressure_force(model, u, t=0.1, alive=alive)[:, 2].sum(), -1.0)


def test_constraint_table_and_automatic_axis():
    mesh = box_quad(2, 2, 0.0, 1.0, 0.0, 1.0)
    model = build_model(mesh, {"solid": MATERIAL},
                        [SymmetryPlane("z0", "z"), Prescribed("z1", "z", "velocity", -1.0)])
    axis = mesh.node_sets["r0"]
    fixed = set(model.constraint_dof[model.constraint_kind == 0])
    assert fixed == set(axis * 2) | set(mesh.node_sets["z0"] * 2 + 1)
    assert set(model.constraint_dof[model.constraint_kind == 2]) == set(mesh.node_sets["z1"] * 2 + 1)
    assert model.dof_constrained.sum() == len(model.constraint_dof)


def test_prescribed_velocity_moves_the_nodes_exactly():
    from corneasim.solver import run
    mesh = box_hex(1, 1, 1, 1.0, 1.0, 1.0)
    model = build_model(mesh, {"solid": MATERIAL},
                        [Fixed("z0", "xyz"), Prescribed("z1", "z", "displacement", 1e-3, Linear(1.0))])
    state = new_state(model)
    for _ in run(model, state, 0.02, history_every=1000):
        pass
    np.testing.assert_allclose(state.u[mesh.node_sets["z1"], 2], 1e-3 * 0.02, rtol=1e-12)
    np.testing.assert_array_equal(state.u[mesh.node_sets["z0"]], 0.0)


@pytest.mark.parametrize("conditions, pressures, fragment", [
    ([Fixed("nowhere", "x")], [], "node set 'nowhere' does not exist"),
    ([Fixed("x0", "w")], [], "component 'w'"),
    ([Prescribed("x0", "x", "velocity", 1.0), Prescribed("x0", "x", "displacement", 1.0)], [],
     "already constrained by node set 'x0'"),
    ([Prescribed("x0", "x", "acceleration", 1.0)], [], "kind 'acceleration'"),
    ([], [Pressure("nowhere", 1.0)], "surface set 'nowhere' does not exist"),
])
def test_bad_loads_are_one_line_input_errors(conditions, pressures, fragment):
    with pytest.raises(InputError, match=fragment) as error:
        build_model(box_hex(1, 1, 1, 1.0, 1.0, 1.0), {"solid": MATERIAL}, conditions, pressures)
    assert "\n" not in str(error.value)


def test_missing_material_and_unstable_fixed_step_are_input_errors():
    mesh = box_hex(1, 1, 1, 1.0, 1.0, 1.0)
    with pytest.raises(InputError, match="no material for block 'solid'"):
        build_model(mesh, {"cornea": MATERIAL})
    stable = build_model(mesh, {"solid": MATERIAL}).stable_time_step()[0]
    with pytest.raises(InputError, match="exceeds the stable time step .*element 0, block 'solid'"):
        build_model(mesh, {"solid": MATERIAL}, time_step=1.01 * stable)
    assert build_model(mesh, {"solid": MATERIAL}, time_step=0.99 * stable).time_step == 0.99 * stable
