"""Split meshes and cohesive ties, against the traction-separation law and energy balance."""

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.materials import KernelMaterial
from corneasim.fracture._split import split_nodes
from corneasim.solver import Fixed, Prescribed, build_model, load_checkpoint, new_state, run, save_checkpoint
from corneasim.solver._integrate import ENERGY_DAMPING, ENERGY_INTERNAL, ENERGY_REACTION
from corneasim.solver._amplitudes import Constant
from corneasim.fracture._ties import (
    BROKEN, DISSIPATED, STORED, CohesiveTies, cohesive_forces, tie_areas, tie_normals)
from corneasim.fracture._law import dissipated_density
from corneasim.fracture._edge_work import edge_power, tie_lines
from test_solver_meshes import box_hex, box_quad

MATERIAL = KernelMaterial(density=1e-9, c10=0.2, d1=2.0)


def split_bar():
    """Two unit hexahedra along x, split on the plane x = 1: (mesh, pairs)."""
    mesh = box_hex(2, 1, 1, 2.0, 1.0, 1.0)
    centre_x = mesh.points[mesh.cells].mean(axis=1)[:, 0]
    plane = np.flatnonzero(np.isclose(mesh.points[:, 0], 1.0))
    return split_nodes(mesh, plane, centre_x > 1.0)


def test_split_duplicates_only_the_shared_surface_nodes():
    mesh = box_hex(2, 1, 1, 2.0, 1.0, 1.0)
    centre_x = mesh.points[mesh.cells].mean(axis=1)[:, 0]
    plane = np.flatnonzero(np.isclose(mesh.points[:, 0], 1.0))
    end = np.flatnonzero(np.isclose(mesh.points[:, 0], 2.0))  # used by the moved element only
    split, pairs = split_nodes(mesh, np.concatenate([plane, end]), centre_x > 1.0)
    assert split.n_nodes == mesh.n_nodes + 4 and np.array_equal(np.sort(pairs[:, 0]), plane)
    np.testing.assert_array_equal(split.points[pairs[:, 1]], split.points[pairs[:, 0]])
    # the same body: every element's corners are where they were
    np.testing.assert_array_equal(split.points[split.cells], mesh.points[mesh.cells])
    left, right = (set(split.cells[e]) for e in np.argsort(centre_x))
    assert not left & right  # the two elements no longer share a node
    assert set(pairs[:, 1]) <= right and set(pairs[:, 0]) <= left
    # node sets follow: the y0 face set holds the copies of its split nodes too
    y0 = set(mesh.node_sets["y0"])
    assert set(split.node_sets["y0"]) == y0 | {c for o, c in pairs if o in y0}


def test_tie_areas_sum_to_the_split_surface():
    mesh, pairs = split_bar()
    area = tie_areas(mesh, pairs)
    np.testing.assert_allclose(area, 0.25, rtol=1e-14)
    # axisymmetric: a cylinder r = 1.5 split through a height of 2 has the area 2 pi 1.5 * 2
    quads = box_quad(3, 2, 1.0, 2.5, 0.0, 2.0)
    centre_r = quads.points[quads.cells].mean(axis=1)[:, 0]
    surface = np.flatnonzero(np.isclose(quads.points[:, 0], 1.5))
    split, ring_pairs = split_nodes(quads, surface, centre_r > 1.5)
    ring = tie_areas(split, ring_pairs)
    assert ring.sum() == pytest.approx(2 * np.pi * 1.5 * 2.0, rel=1e-14)


def test_one_tie_follows_the_bilinear_law_and_its_energy():
    """Open one tie along a path out, back, and out again past delta_f: the force is the
    bilinear law's (secant on unloading), the work done on it equals its stored plus
    dissipated energy at every point, and a full opening dissipates G_c A."""
    area, strength, toughness, stiffness = 0.5, 2.0, 0.3, 40.0
    peak = strength * area / stiffness  # 0.025 mm
    separation = 2 * toughness / strength  # 0.3 mm
    points = np.zeros((2, 3))
    pairs = np.array([[0, 1]])
    direction = np.array([0.6, 0.0, 0.8])
    normal = np.array([[0.8, 0.0, -0.6]])  # opening and sliding together: delta_n = 0
    opening_max = np.zeros(1)
    path = np.concatenate([np.linspace(0, 0.15, 3001), np.linspace(0.15, 0.05, 1001)[1:],
                           np.linspace(0.05, 0.4, 7001)[1:]])
    work, previous_force, previous = 0.0, 0.0, 0.0
    for opening in path:
        u = np.zeros((2, 3))
        u[1] = opening * direction
        f = np.zeros((2, 3))
        out = np.zeros(5)
        cohesive_forces(points, u, pairs, normal, np.array([area]), np.array([stiffness]),
                        np.array([strength]), np.array([separation]), opening_max, np.zeros(1),
                        np.zeros(1, np.uint8), f, out)
        np.testing.assert_allclose(f[0], -f[1], atol=1e-15)
        force = -f[1] @ direction  # the tie pulls b back towards a
        reached = max(opening_max[0], opening)
        if reached <= peak:
            expected = stiffness * opening
        elif reached < separation:
            envelope = strength * area * (separation - reached) / (separation - peak)
            expected = envelope * opening / reached
        else:
            expected = 0.0
        assert force == pytest.approx(expected, rel=1e-12, abs=1e-15)
        work += 0.5 * (force + previous_force) * (opening - previous)
        previous_force, previous = force, opening
        assert work == pytest.approx(out[STORED] + out[DISSIPATED], abs=2e-6 * toughness * area)
    assert out[BROKEN] == 1.0
    assert out[DISSIPATED] == pytest.approx(toughness * area, rel=1e-12)
    assert dissipated_density(0.02, strength, peak, separation) == 0.0


def test_a_closing_pair_is_pushed_apart_whatever_its_damage():
    """The faces of a cut in contact: a pair pressed together along n (delta_n < 0) feels the
    elastic branch's penalty k delta_n n, also once broken, while its sliding part follows the
    law; a broken pair that slides carries nothing."""
    area, strength, toughness, stiffness = 0.5, 2.0, 0.3, 40.0
    points, pairs = np.zeros((2, 3)), np.array([[0, 1]])
    normal = np.array([[0.0, 0.0, 1.0]])
    for damage in (0.0, 1.0):  # intact; opened beyond delta_f = 0.3 mm
        opening_max = np.array([damage])
        u = np.zeros((2, 3))
        u[1] = [0.01, 0.0, -0.02]  # slides by 0.01 mm, closes by 0.02 mm
        f, out = np.zeros((2, 3)), np.zeros(5)
        cohesive_forces(points, u, pairs, normal, np.array([area]), np.array([stiffness]),
                        np.array([strength]), np.array([separation := 2 * toughness / strength]),
                        opening_max, np.zeros(1), np.zeros(1, np.uint8), f, out)
        sliding = stiffness * 0.01 if damage == 0.0 else 0.0
        np.testing.assert_allclose(-f[1], [sliding, 0.0, -stiffness * 0.02], rtol=1e-14, atol=1e-18)
        assert out[STORED] == pytest.approx(0.5 * sliding * 0.01 + 0.5 * stiffness * 0.02 ** 2, rel=1e-14)
        assert opening_max[0] == pytest.approx(max(damage, 0.01), rel=1e-14)
    assert separation < 1.0


def test_tie_normals_point_from_the_originals_to_the_copies():
    mesh, pairs = split_bar()
    np.testing.assert_allclose(tie_normals(mesh, pairs), np.tile([1.0, 0.0, 0.0], (4, 1)), atol=1e-15)
    # axisymmetric: the cylinder r = 1.5 split with the copies outside: n = e_r
    quads = box_quad(3, 2, 1.0, 2.5, 0.0, 2.0)
    centre_r = quads.points[quads.cells].mean(axis=1)[:, 0]
    surface = np.flatnonzero(np.isclose(quads.points[:, 0], 1.5))
    split, ring_pairs = split_nodes(quads, surface, centre_r < 1.5)
    np.testing.assert_allclose(tie_normals(split, ring_pairs), np.tile([-1.0, 0.0], (3, 1)), atol=1e-15)


def pulled_bar(speed, strength, toughness):
    """The split bar held at x = 0 and pulled at x = 2 by ``speed`` (mm/s) until the ties break."""
    mesh, pairs = split_bar()
    conditions = [Fixed("x0", "xyz"), Fixed("x1", "yz"), Prescribed("x1", "x", "velocity", speed, Constant(1.0))]
    probe = build_model(mesh, {"solid": MATERIAL}, conditions)
    model = build_model(mesh, {"solid": MATERIAL}, conditions, target_time_step=probe.element_time_step.max())
    ties = CohesiveTies(model, pairs, tie_areas(mesh, pairs), strength, toughness)
    return model, ties


def test_a_pulled_split_bar_breaks_at_its_strength_and_pays_its_toughness():
    """Quasi-static tension of the split bar: the pull peaks at sigma_c A, every tie breaks,
    the ties dissipate G_c A, and the work of the pulling reaction equals it plus what is
    left in the bar (internal, kinetic and damping energies)."""
    strength, toughness = 0.05, 0.05  # MPa, N/mm; A = 1 mm^2
    model, ties = pulled_bar(2.0, strength, toughness)
    state = new_state(model)
    peak = 0.0
    for frame in run(model, state, 1.5, history_every=20, hooks=[ties], damping=200.0):
        if frame.history is not None:
            peak = max(peak, frame.history["reaction_x1_x_N"])
    row = frame.history
    assert row["cut_broken_ties"] == 4.0
    assert row["cut_dissipated_energy_mJ"] == pytest.approx(toughness * 1.0, rel=1e-12)
    assert peak == pytest.approx(strength * 1.0, rel=0.01)
    energies = state.energies
    left = energies[ENERGY_INTERNAL] + row["kinetic_energy_mJ"] + energies[ENERGY_DAMPING]
    assert energies[ENERGY_REACTION] == pytest.approx(left + toughness, rel=1e-3)


def test_ties_restore_their_damage_and_reject_bad_input():
    model, ties = pulled_bar(2.0, 0.05, 0.05)
    state = new_state(model)
    for _ in run(model, state, 0.3, history_every=10**6, hooks=[ties]):
        pass
    saved = ties.checkpoint()
    assert saved["opening_max"].max() > 0.0
    _, other = pulled_bar(2.0, 0.05, 0.05)
    other.restore(saved)
    np.testing.assert_array_equal(other.opening_max, ties.opening_max)
    mesh, pairs = split_bar()
    with pytest.raises(InputError, match="strength"):
        CohesiveTies(model, pairs, np.ones(4), -1.0, 0.1)
    with pytest.raises(InputError, match="penalty_fraction"):
        CohesiveTies(model, pairs, np.ones(4), 1.0, 0.1, penalty_fraction=1.0)
    with pytest.warns(UserWarning, match="break at their peak"):
        CohesiveTies(model, pairs, np.ones(4), 1.0, 1e-9)


def test_a_resumed_split_bar_replays_the_ties_damage(tmp_path):
    """Checkpoint in the middle of the softening, resume with fresh ties: the same history."""
    model, ties = pulled_bar(2.0, 0.05, 0.05)
    straight = [frame.history for frame in run(model, new_state(model), 0.6, history_every=200, hooks=[ties])
                if frame.history]
    assert 0.0 < straight[-1]["cut_dissipated_energy_mJ"] < 0.05  # the checkpoint falls mid-way
    model, ties = pulled_bar(2.0, 0.05, 0.05)
    checkpoint = tmp_path / "checkpoint.npz"
    before = []
    for frame in run(model, new_state(model), 0.6, history_every=200, checkpoint_every=10000, hooks=[ties]):
        if frame.history:
            before.append(frame.history)
        if frame.checkpoint_due:
            save_checkpoint(checkpoint, model, frame.state, [ties])
            saved = frame.step
            break
    model, fresh = pulled_bar(2.0, 0.05, 0.05)
    state = load_checkpoint(checkpoint, model, [fresh])
    resumed = [frame.history for frame in run(model, state, 0.6, history_every=200, hooks=[fresh])
               if frame.history]
    rows = [row for row in before if row["step"] <= saved] + [row for row in resumed if row["step"] > saved]
    assert [row["step"] for row in rows] == [row["step"] for row in straight]
    for got, expected in zip(rows, straight):
        assert got == expected


def test_the_energy_an_edge_supplies_cuts_a_tie_at_its_toughness():
    """An intact tie (opened within its elastic branch) is cut once the supplied energy reaches
    G_c A: it then carries no tension, while a closing opening is still resisted."""
    area, strength, toughness, stiffness = 0.5, 2.0, 0.3, 40.0
    points, pairs = np.zeros((2, 3)), np.array([[0, 1]])
    normal = np.array([[0.0, 0.0, 1.0]])
    arrays = (np.array([area]), np.array([stiffness]), np.array([strength]), np.array([2 * toughness / strength]))
    opening_max, cut = np.zeros(1), np.zeros(1, np.uint8)
    u = np.zeros((2, 3))
    u[1, 2] = 0.01  # open by 0.01 mm, below delta_0 = 0.025 mm
    for supplied, pull in ((0.999 * toughness * area, stiffness * 0.01), (toughness * area, 0.0)):
        f, out = np.zeros((2, 3)), np.zeros(5)
        cohesive_forces(points, u, pairs, normal, *arrays, opening_max, np.array([supplied]), cut, f, out)
        assert -f[1, 2] == pytest.approx(pull, rel=1e-14)
    assert cut[0] == 1 and out[BROKEN] == 1.0 and out[DISSIPATED] == 0.0
    u[1, 2] = -0.01
    f = np.zeros((2, 3))
    cohesive_forces(points, u, pairs, normal, *arrays, opening_max, np.zeros(1), cut, f, np.zeros(5))
    assert -f[1, 2] == pytest.approx(-stiffness * 0.01, rel=1e-14)


def test_the_blade_power_on_a_line_of_ties_goes_to_its_front():
    """P = f . (z' e_z + theta' e_z x (x - c)) at the nodes of a line of ties, summed, times dt,
    goes to the line's first tie from the top not yet cut; negative power supplies nothing."""
    points = np.array([[3.0, 4.0, 0.0], [3.0, 4.0, 0.0], [3.0, 4.0, -0.1], [3.0, 4.0, -0.1]])
    u = np.zeros((4, 3))
    pairs = np.array([[2, 3], [0, 1]])  # the lower tie first
    line_start, line_pairs = tie_lines(points, pairs)
    np.testing.assert_array_equal(line_start, [0, 2])
    np.testing.assert_array_equal(line_pairs, [1, 0])  # from the top down
    f_before = np.zeros((2, 2, 3))
    f_ext = np.array([[0.0, 0.0, -0.2], [-0.08, 0.06, -0.1], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    pose = np.zeros(8)
    pose[6], pose[7] = -0.02, 2.0  # v_z (mm/s), omega (rad/s); axis at the origin
    blade = np.array([-2.0 * 4.0, 2.0 * 3.0, -0.02])
    work = 1e-3 * (f_ext[0] @ blade + f_ext[1] @ blade)
    supplied, cut = np.zeros(2), np.zeros(2, np.uint8)
    edge_power(points, u, pairs, line_start, line_pairs, cut, f_ext, f_before, pose, 1e-3, supplied)
    np.testing.assert_allclose(supplied, [0.0, work], rtol=1e-14)  # the top tie is the front
    cut[1] = 1
    edge_power(points, u, pairs, line_start, line_pairs, cut, f_ext, f_before, pose, 1e-3, supplied)
    np.testing.assert_allclose(supplied, [work, work], rtol=1e-14)  # the front moved down
    edge_power(points, u, pairs, line_start, line_pairs, cut, -f_ext, f_before, pose, 1e-3, supplied)
    np.testing.assert_allclose(supplied, [work, work], rtol=1e-14)
