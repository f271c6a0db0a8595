"""Cyclic symmetry of order 2 about z for half models: the full model is the truth.

A body invariant under the rotation R = diag(-1, -1, 1) (a tube, a box centred on the axis)
under a load with the same invariance is solved once whole and once as its half y >= 0 with
the cut plane y = 0 coupled by ``CyclicSymmetry``: the displacements must agree to round-off.
The same half with a mirror plane (u_y = 0) must not, under a torsional load, and must not
let the half tube spin freely.
"""

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.materials import KernelMaterial
from corneasim.mesh import Mesh, mesh_3d, write_mesh
from corneasim.solver import (
    CyclicSymmetry, Fixed, SymmetryPlane, build_model, load_checkpoint, new_state, run, save_checkpoint)
from corneasim.solver._cyclic import couple_pairs
from cli_helpers import corneasim_here
from test_solver_meshes import box_hex, box_quad

MATERIAL = KernelMaterial(density=1e-9, c10=0.2, d1=2.0)


def tube(sectors: int, half: bool, inner=1.0, outer=1.5, height=0.6, n_radial=2, n_axial=2) -> Mesh:
    """Hexahedral tube about z: ``sectors`` over 360 degrees (periodic) or ``sectors // 2`` over y >= 0.

    Node sets ``bottom`` (z = 0) and ``cut`` (y = 0).
    """
    n_angles = sectors // 2 + 1 if half else sectors
    j = np.arange(n_angles)
    c, s = np.cos(2 * np.pi * j / sectors), np.sin(2 * np.pi * j / sectors)
    c[2 * j == sectors], s[2 * j == sectors], s[j == 0] = -1.0, 0.0, 0.0  # y = 0 exactly at 0 and pi
    r, z = np.linspace(inner, outer, n_radial + 1), np.linspace(0.0, height, n_axial + 1)
    R, C, Z = np.meshgrid(r, c, z, indexing="ij")
    _, S, _ = np.meshgrid(r, s, z, indexing="ij")
    points = np.column_stack([(R * C).ravel(), (R * S).ravel(), Z.ravel()])
    index = np.arange(len(points)).reshape(n_radial + 1, n_angles, n_axial + 1)
    i, k, m = (a.ravel() for a in np.meshgrid(np.arange(n_radial), np.arange(n_angles - 1 if half else sectors),
                                              np.arange(n_axial), indexing="ij"))
    k1 = (k + 1) % n_angles
    cells = np.column_stack([index[i, k, m], index[i + 1, k, m], index[i + 1, k1, m], index[i, k1, m],
                             index[i, k, m + 1], index[i + 1, k, m + 1], index[i + 1, k1, m + 1],
                             index[i, k1, m + 1]]).astype(np.int64)
    sets = {"bottom": np.flatnonzero(points[:, 2] == 0.0), "cut": np.flatnonzero(points[:, 1] == 0.0)}
    return Mesh(points, cells, "hexahedron", np.zeros(len(cells), np.int64), ["solid"], False, sets, {}, {})


def centred_box(half: bool) -> Mesh:
    """[-1, 1] x [-1, 1] x [0, 1] (or its half y >= 0) in 0.5 mm hexahedra, a node column on the axis."""
    mesh = box_hex(4, 2 if half else 4, 2, 2.0, 1.0 if half else 2.0, 1.0)
    mesh.points[:, 0] -= 1.0
    if not half:
        mesh.points[:, 1] -= 1.0
    mesh.node_sets["bottom"], mesh.node_sets["cut"] = mesh.node_sets["z0"], mesh.node_sets["y0"]
    return mesh


class BodyForce:
    """External-force hook: f = m b(X), b = beta (-y, x, 0) + gamma (x, y, 0) + delta e_z (N/tonne).

    The field is invariant under R: b(R X) = R b(X); its first term twists the body about z.
    """

    name = "body_force"

    def __init__(self, points, beta=4e6, gamma=1e6, delta=2e6):
        x, y = points[:, 0], points[:, 1]
        self.b = np.column_stack([-beta * y + gamma * x, beta * x + gamma * y, np.full(len(x), delta)])

    def add_forces(self, model, state, time, time_step, f_ext):
        f_ext += model.mass[:, None] * self.b

    def outputs(self):
        return {}


def simulate(mesh, conditions, steps=300, time_step=1e-6, velocity=None, hooks=None):
    model = build_model(mesh, {"solid": MATERIAL}, conditions, time_step=time_step, safety_factor=0.5)
    state = new_state(model, velocity)
    hooks = (BodyForce(mesh.points),) if hooks is None else hooks
    rows = [frame.history for frame in run(model, state, steps * time_step, history_every=50, hooks=hooks)
            if frame.history]
    return model, state, rows


def same_points(half: Mesh, full: Mesh) -> np.ndarray:
    """Index of the full mesh's node at each half-mesh node's coordinates."""
    key = {tuple(np.round(p, 9)): n for n, p in enumerate(full.points)}
    return np.array([key[tuple(np.round(p, 9))] for p in half.points])


@pytest.mark.parametrize("make", [lambda half: tube(12, half), centred_box], ids=["tube", "box"])
def test_half_model_with_cyclic_symmetry_reproduces_the_full_model(make):
    full_mesh, half_mesh = make(False), make(True)
    _, full, full_rows = simulate(full_mesh, [Fixed("bottom", "xyz")])
    half_model, half, half_rows = simulate(half_mesh, [Fixed("bottom", "xyz"), CyclicSymmetry("cut")])
    assert half_model.cyclic_master.size > 0
    expected = full.u[same_points(half_mesh, full_mesh)]
    scale = np.abs(full.u).max()
    assert scale > 1e-3  # the load deformed the body (mm)
    np.testing.assert_allclose(half.u, expected, rtol=0, atol=1e-9 * scale)
    # the half model carries half of everything: base reaction, energies
    for key in ("reaction_bottom_z_N", "internal_energy_mJ", "kinetic_energy_mJ", "external_work_mJ"):
        assert half_rows[-1][key] == pytest.approx(0.5 * full_rows[-1][key], rel=1e-7)
    assert max(row["energy_balance_error"] for row in half_rows) < 1e-9


def test_a_mirror_plane_is_wrong_under_torsion():
    full_mesh, half_mesh = tube(12, False), tube(12, True)
    _, full, _ = simulate(full_mesh, [Fixed("bottom", "xyz")])
    _, mirror, _ = simulate(half_mesh, [Fixed("bottom", "xyz"), SymmetryPlane("cut", "y")])
    expected = full.u[same_points(half_mesh, full_mesh)]
    error = np.abs(mirror.u - expected).max()
    assert error > 0.3 * np.abs(expected).max()


def test_axis_nodes_stay_on_the_axis_and_pairs_move_as_images():
    mesh = centred_box(True)
    model, state, rows = simulate(mesh, [Fixed("bottom", "xyz"), CyclicSymmetry("cut")])
    axis = np.flatnonzero(np.hypot(mesh.points[:, 0], mesh.points[:, 1]) < 1e-12)
    assert axis.size == 3 and np.all(state.u[axis, :2] == 0.0) and np.abs(state.u[axis, 2]).max() > 1e-4
    a, b = model.cyclic_master, model.cyclic_slave
    np.testing.assert_array_equal(mesh.points[b], mesh.points[a] * [-1.0, 1.0, 1.0])
    np.testing.assert_array_equal(state.u[b], state.u[a] * [-1.0, -1.0, 1.0])
    assert "reaction_cut_x_N" in rows[-1] and "reaction_cut_y_N" in rows[-1]


def test_a_free_half_tube_spins_as_a_rigid_body_only_with_cyclic_symmetry():
    """v0 = omega e_z x X: a rigid spin, which cyclic symmetry allows and a mirror plane forbids.

    The only internal force is the centripetal one: strain ~ rho omega^2 R^2 / E ~ 1e-4.
    """
    mesh = tube(12, True)
    omega, steps, dt = 100.0, 2000, 1e-6
    velocity = omega * np.column_stack([-mesh.points[:, 1], mesh.points[:, 0], np.zeros(mesh.n_nodes)])
    angle = omega * steps * dt
    rotation = np.array([[np.cos(angle), -np.sin(angle), 0.0], [np.sin(angle), np.cos(angle), 0.0], [0, 0, 1]])
    rigid = mesh.points @ rotation.T - mesh.points
    _, spun, rows = simulate(mesh, [CyclicSymmetry("cut")], steps, dt, velocity, hooks=())
    assert np.abs(spun.u - rigid).max() < 2e-3 * np.abs(rigid).max()
    assert rows[-1]["internal_energy_mJ"] < 1e-3 * rows[-1]["kinetic_energy_mJ"]
    assert abs(rows[-1]["damping_energy_mJ"]) < 1e-12 * rows[-1]["kinetic_energy_mJ"]  # v0 met the constraint
    _, held, rows = simulate(mesh, [SymmetryPlane("cut", "y")], steps, dt, velocity, hooks=())
    assert rows[-1]["internal_energy_mJ"] > 0.05 * rows[0]["kinetic_energy_mJ"]


def test_pair_average_is_the_momentum_conserving_merge():
    """Hand-computed: m = (1, 3), x_a = (1, 2, 3), x_b = (5, 6, 7).

    x = (1 x_a + 3 R^T x_b) / 4 = ((1 - 15) / 4, (2 - 18) / 4, (3 + 21) / 4) = (-3.5, -4, 6);
    lost = (1 * 14 + 3 * 110 - 4 * 64.25) / 2 = 43.5.
    """
    x = np.array([[1.0, 2.0, 3.0], [5.0, 6.0, 7.0]])
    lost = couple_pairs(x, np.array([1.0, 3.0]), np.array([0]), np.array([1]), np.zeros((1, 3), np.uint8))
    np.testing.assert_allclose(x, [[-3.5, -4.0, 6.0], [3.5, 4.0, 6.0]])
    assert lost == pytest.approx(43.5)
    held = np.array([[0, 0, 1]], np.uint8)
    assert couple_pairs(x, np.array([1.0, 3.0]), np.array([0]), np.array([1]), held) == pytest.approx(0.5 * 4 * 36)
    np.testing.assert_allclose(x, [[-3.5, -4.0, 0.0], [3.5, 4.0, 0.0]])


def test_restart_with_cyclic_symmetry_continues_bit_for_bit(tmp_path):
    mesh = tube(12, True)
    conditions = [Fixed("bottom", "xyz"), CyclicSymmetry("cut")]
    hooks = (BodyForce(mesh.points),)
    model = build_model(mesh, {"solid": MATERIAL}, conditions, safety_factor=0.5, time_step_every=7)
    straight = new_state(model)
    for _ in run(model, straight, 1e-4, hooks=hooks):
        pass
    state = new_state(model)
    for frame in run(model, state, 1e-4, hooks=hooks, checkpoint_every=20):
        if frame.checkpoint_due:
            save_checkpoint(tmp_path / "c.npz", model, frame.state)
            break
    resumed = load_checkpoint(tmp_path / "c.npz", model)
    for _ in run(model, resumed, 1e-4, hooks=hooks):
        pass
    np.testing.assert_array_equal(resumed.u, straight.u)


@pytest.mark.parametrize("strategy", ["umbrella", "vertical", "horizontal"])
def test_every_node_of_the_eye_symmetry_plane_has_its_image(strategy):
    mesh = mesh_3d(None, strategy, "coarse")
    model = build_model(mesh, {name: MATERIAL for name in mesh.block_names},
                        [Fixed("lower_hemisphere", "xyz"), CyclicSymmetry("symmetry_plane")])
    plane = mesh.node_sets["symmetry_plane"]
    axis = plane[np.hypot(mesh.points[plane, 0], mesh.points[plane, 1]) == 0.0]
    assert 2 * model.cyclic_master.size + axis.size == plane.size
    np.testing.assert_allclose(mesh.points[model.cyclic_slave], mesh.points[model.cyclic_master] * [-1, 1, 1],
                               atol=1e-12)


def perturbed_box() -> tuple[Mesh, int]:
    """The half box with one cut-plane node moved 0.05 mm along x: it has no image."""
    mesh = centred_box(True)
    node = int(mesh.node_sets["cut"][np.argmax(mesh.points[mesh.node_sets["cut"], 0])])
    mesh.points[node, 0] += 0.05
    return mesh, node


def test_unmatched_or_off_plane_nodes_and_unequal_constraints_are_input_errors():
    mesh, node = perturbed_box()
    with pytest.raises(InputError, match=rf"node {node} at \(1.05, 0, 0\) has no image"):
        build_model(mesh, {"solid": MATERIAL}, [CyclicSymmetry("cut")])
    mesh = centred_box(True)
    with pytest.raises(InputError, match="is not on the cut plane y = 0"):
        build_model(mesh, {"solid": MATERIAL}, [CyclicSymmetry("x1")])
    with pytest.raises(InputError, match="constrained differently"):
        build_model(mesh, {"solid": MATERIAL}, [CyclicSymmetry("cut"), Fixed("x1", "z")])
    with pytest.raises(InputError, match="z axis of a 3D mesh"):
        build_model(box_quad(2, 2, 0.0, 1.0, 0.0, 1.0), {"solid": MATERIAL}, [CyclicSymmetry("z0")])


def test_cli_reports_an_unmatched_node_in_one_line_with_exit_2(tmp_path):
    mesh, node = perturbed_box()
    mesh_file = write_mesh(mesh, tmp_path / "box.inp")
    scenario = tmp_path / "box.toml"
    scenario.write_text(f'''name = "box"
[mesh]
file = "{mesh_file}"
[materials]
solid = {{ material = "sclera" }}
[[constraints]]
node_set = "cut"
cyclic = "z"
[solver]
end_time = 1.0e-5
''')
    result = corneasim_here("run", str(scenario), "--out", str(tmp_path / "out"), "--no-progress")
    assert result.returncode == 2, result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    assert f"node {node} at (1.05, 0, 0) has no image" in result.stderr


def test_the_builtin_trephine_couples_its_cut_plane_cyclically():
    from corneasim.scenarios._build import build
    from corneasim.scenarios._registry import load_scenario

    scenario, _, base_dir = load_scenario("trephine", ["mesh.preset=coarse"])
    assert [c.cyclic for c in scenario.constraints if c.node_set == "symmetry_plane"] == ["z"]
    model = build(scenario, base_dir).model
    plane = model.mesh.node_sets["symmetry_plane"]
    assert 0 < 2 * model.cyclic_master.size < plane.size
    # the lower hemisphere's pairs are held in x and y on both copies; z is on the support
    held = np.isin(model.cyclic_master, model.mesh.node_sets["lower_hemisphere"])
    assert held.any() and np.all(model.cyclic_held[held, :2] == 1) and np.all(model.cyclic_held[held, 2] == 0)
    assert np.all(model.cyclic_held[~held] == 0)


def test_a_node_released_by_deletion_keeps_moving_with_its_image():
    """Element 13 (outer, top, at theta = 0) fails; its corner (1.5, 0, 0.6) loses its only
    element but is one node of the full model with its live image at (-1.5, 0, 0.6)."""
    from corneasim.materials._kernel_form import FAILURE_VON_MISES

    base = tube(12, True)
    block = np.zeros(base.n_elements, np.int64)
    block[13] = 1
    mesh = Mesh(base.points, base.cells, "hexahedron", block, ["solid", "weak"], False, base.node_sets, {}, {})
    weak = KernelMaterial(density=1e-9, c10=0.2, d1=2.0, failure_criterion=FAILURE_VON_MISES, failure_limit=2e-3)
    model = build_model(mesh, {"solid": MATERIAL, "weak": weak}, [Fixed("bottom", "xyz"), CyclicSymmetry("cut")],
                        time_step=1e-6, safety_factor=0.5)
    state = new_state(model)
    rows = [frame.history for frame in run(model, state, 3e-4, history_every=20, hooks=(BodyForce(mesh.points),))
            if frame.history]
    assert state.deleted_element.tolist() == [13]
    corner = int(np.flatnonzero(np.all(np.isclose(mesh.points, [1.5, 0.0, 0.6]), axis=1))[0])
    image = int(model.cyclic_slave[model.cyclic_master == corner][0])
    assert state.node_active[corner] == 0 and state.node_active[image] == 1
    np.testing.assert_array_equal(state.u[model.cyclic_slave], state.u[model.cyclic_master] * [-1.0, -1.0, 1.0])
    assert np.abs(state.u[corner]).max() > 1e-3
    assert max(row["energy_balance_error"] for row in rows[1:]) < 0.01


def test_whole_eye_sideways_force_vanishes_under_cyclic_symmetry():
    """Doubling a half model's forces: F_z and torque double, while the cyclic image's sideways
    force is minus the half's, so the whole eye has F_x = F_y = 0 (a mirror half doubles them)."""
    import dataclasses

    from corneasim.scenarios._build import build
    from corneasim.scenarios._registry import load_scenario
    from corneasim.contact._node import FORCE_X, FORCE_Y, FORCE_Z, TORQUE_Z
    from corneasim.contact._instrument_contact import InstrumentContact

    scenario, _, base_dir = load_scenario("trephine", ["mesh.preset=coarse"])
    setup = build(scenario, base_dir)
    contact = setup.instrument
    half = {FORCE_X: 0.3, FORCE_Y: -0.2, FORCE_Z: 0.5, TORQUE_Z: 0.7}
    for index, value in half.items():
        contact.out[index] = value
    outputs = contact.outputs()
    assert outputs["instrument_force_x_N"] == 0.0 and outputs["instrument_force_y_N"] == 0.0
    assert outputs["instrument_force_z_N"] == pytest.approx(1.0)
    assert outputs["instrument_torque_z_Nmm"] == pytest.approx(1.4)
    no_pairs = dataclasses.replace(setup.model, cyclic_master=np.zeros(0, np.int64),
                                   cyclic_slave=np.zeros(0, np.int64))
    mirrored = InstrumentContact(contact.instrument, contact.motion, no_pairs, contact.settings,
                                 symmetry_factor=2.0)
    for index, value in half.items():
        mirrored.out[index] = value
    assert mirrored.outputs()["instrument_force_x_N"] == pytest.approx(0.6)
