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
    BROKEN, DISSIPATED, STORED, CohesiveTies, cohesive_forces, tie_areas)
from corneasim.fracture._law import dissipated_density
from test_solver_meshes import box_hex, box_quad

pytestmark = pytest.mark.slow  # the cohesive cut: not used by the built-in scenarios

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
    opening_max = np.zeros(1)
    path = np.concatenate([np.linspace(0, 0.15, 3001), np.linspace(0.15, 0.05, 1001)[1:],
                           np.linspace(0.05, 0.4, 7001)[1:]])
    work, previous_force, previous = 0.0, 0.0, 0.0
    for opening in path:
        u = np.zeros((2, 3))
        u[1] = opening * direction
        f = np.zeros((2, 3))
        out = np.zeros(4)
        cohesive_forces(points, u, pairs, np.array([area]), np.array([stiffness]), np.array([strength]),
                        np.array([separation]), opening_max, f, out)
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
