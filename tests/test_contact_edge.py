"""Edge contact of a trephine's circular edge with hexahedral faces (contact._edge).

Truths: the geometry of a cube (outward face normals, shared faces), the line stiffness
alpha m / (dt^2 h) integrated along the part of the edge inside a face, equilibrium between
the tissue and the instrument, and, in the solver, the reaction of the support.
"""

import math

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.materials import KernelMaterial
from corneasim.solver import Fixed, build_model, load_checkpoint, new_state, run, save_checkpoint
from corneasim.solver._amplitudes import SmoothStep
from corneasim.contact._settings import ContactSettings
from corneasim.contact._edge_law import (
    EDGE_FORCE_Z, EDGE_FRICTION_POWER, EDGE_NORMAL, EDGE_POINTS, EDGE_TORQUE_Z, N_EDGE_OUTPUTS,
    eval_edge_contact)
from corneasim.contact._edge_faces import edge_directions, edge_face_lists, face_slots
from corneasim.contact._friction import Friction
from corneasim.instruments._kinds import Needle, Trephine
from corneasim.contact import InstrumentContact
from corneasim.contact._cutting import CUT_AVERAGING_STEPS
from corneasim.mesh._surface import face_table
from corneasim.instruments._motion import Motion

from ring_helpers import ring_mesh

H = 0.2  # cube side, mm
MASS, DT, ALPHA = 1e-9, 1e-5, 0.3


def load_buffers(n_elements):
    """The per-element point counters of ``eval_edge_contact`` and its list of loaded
    elements (at most one entry per element)."""
    return np.zeros(n_elements, np.int64), np.zeros(n_elements, np.int64)


def cubes(n_up):
    """A column of n_up cubes of side H, bottom at z = 0 (VTK order)."""
    layer = np.array([[0, 0], [H, 0], [H, H], [0, H]], float)
    points = np.vstack([np.column_stack([layer, np.full(4, k * H)]) for k in range(n_up + 1)])
    cells = np.array([[4 * k + a for a in range(4)] + [4 * (k + 1) + a for a in range(4)]
                      for k in range(n_up)], np.int64)
    return points, cells


def face_index(faces, n_faces, n_points):
    """What ``eval_edge_contact`` takes besides the lists: (slots, listed, boxes, directions)."""
    listed, slots = np.empty(faces.size, np.int64), np.empty(faces.size, np.int64)
    n = face_slots(faces, np.full(n_faces, -1, np.int64), listed, slots)
    return slots, listed[:n], np.empty((n, 4)), edge_directions(n_points)


def test_face_slots_list_each_face_once_in_order_of_first_appearance():
    faces = np.array([7, 3, 7, 9, 3, 3, 0, 9])
    face_slot = np.full(12, -1, np.int64)
    listed, slots = np.empty(faces.size, np.int64), np.empty(faces.size, np.int64)
    n = face_slots(faces, face_slot, listed, slots)
    distinct, first = np.unique(faces, return_index=True)
    assert listed[:n].tolist() == distinct[np.argsort(first)].tolist() == [7, 3, 9, 0]
    assert (listed[slots] == faces).all()
    assert (face_slot == -1).all()  # left as found, for the next lists


def edge_forces(points, cells, alive, z_edge, radius=10.0, spacing=0.005):
    """Edge of a large circle crossing the top faces along x = H/2 (nearly straight), at z_edge."""
    face_nodes, owner, neighbour = face_table(points, cells)
    center = np.array([0.5 * H - radius, 0.5 * H, 0.0])
    n_points = int(round(2 * math.pi * radius / spacing))
    start, faces = edge_face_lists(points, face_nodes, owner, neighbour, np.arange(len(owner)), alive,
                                   center, radius, z_edge, 0.05, n_points)
    f = np.zeros_like(points)
    out = np.zeros(N_EDGE_OUTPUTS)
    eval_edge_contact(points, np.zeros_like(points), face_nodes, owner, start, faces,
                      *face_index(faces, len(owner), len(start) - 1), np.full(len(points), MASS),
                      center, np.zeros(3), 0.0, radius, z_edge, ALPHA, 0.0,
                      0.0, DT, f, *load_buffers(len(cells)), np.zeros(n_points), out)
    return f, out, 2 * math.pi * radius / n_points


def test_face_table_orients_faces_outwards_and_pairs_the_shared_face():
    points, cells = cubes(2)
    points[[4, 6], 2] += 0.02  # a slightly warped middle layer
    cells[1] = cells[1][[1, 2, 3, 0, 5, 6, 7, 4]]  # same cube, nodes renumbered
    face_nodes, owner, neighbour = face_table(points, cells)
    corners = points[face_nodes]
    normal = np.cross(corners[:, 2] - corners[:, 0], corners[:, 3] - corners[:, 1])
    outward = corners.mean(axis=1) - points[cells].mean(axis=1)[owner]
    assert np.all(np.einsum("fi,fi->f", normal, outward) > 0)
    shared = np.flatnonzero(neighbour >= 0)
    assert len(shared) == 2 and set(owner[shared]) == {0, 1} and set(neighbour[shared]) == {0, 1}
    assert set(map(tuple, np.sort(face_nodes[shared], axis=1))) == {(4, 5, 6, 7)}


def test_a_straight_edge_across_a_face_is_a_line_spring_shared_by_its_nodes():
    points, cells = cubes(1)
    depth = 0.002
    f, out, spacing = edge_forces(points, cells, np.ones(1, np.uint8), H - depth)
    line_stiffness = ALPHA * MASS / DT**2 / H  # N/mm per mm of edge
    inside = np.count_nonzero(f[:, 2])  # only the top face's four nodes are pushed
    assert inside == 4 and np.all(f[4:, 2] < 0) and np.all(f[:, :2] == 0)
    assert -f[:, 2].sum() == pytest.approx(line_stiffness * depth * H, abs=line_stiffness * depth * spacing)
    np.testing.assert_allclose(f[4:, 2], f[4:, 2].mean(), rtol=0.03)  # the edge crosses the middle
    assert out[EDGE_FORCE_Z] == pytest.approx(-f[:, 2].sum(), rel=1e-12)  # equilibrium
    assert out[EDGE_POINTS] == pytest.approx(H / spacing, abs=1)


def test_an_edge_above_the_face_or_deeper_than_half_an_element_is_not_caught():
    points, cells = cubes(1)
    f, out, _ = edge_forces(points, cells, np.ones(1, np.uint8), H + 0.001)
    assert not f.any() and out[EDGE_POINTS] == 0
    # more than half an element deep the top face lets go, and the side faces do not face
    # the instrument
    points, cells = cubes(2)
    f, out, _ = edge_forces(points, cells, np.ones(2, np.uint8), 2 * H - 0.51 * H)
    assert not f.any() and out[EDGE_POINTS] == 0


def test_deleting_the_top_layer_exposes_the_faces_below_to_the_edge():
    mesh = ring_mesh(np.array([3.6, 3.7, 3.8, 3.9]), 120, np.array([-0.2, -0.1, 0.0]))
    face_nodes, owner, neighbour = face_table(mesh.points, mesh.cells)
    top_layer = mesh.points[mesh.cells].mean(axis=1)[:, 2] > -0.1

    def push(alive, z_edge):
        start, faces = edge_face_lists(mesh.points, face_nodes, owner, neighbour, np.arange(len(owner)),
                                       alive, np.zeros(3), 3.75, z_edge, 0.05, 2400)
        f = np.zeros_like(mesh.points)
        out = np.zeros(N_EDGE_OUTPUTS)
        buffers = load_buffers(len(mesh.cells))
        n_loaded = eval_edge_contact(mesh.points, np.zeros_like(mesh.points), face_nodes, owner, start,
                                     faces, *face_index(faces, len(owner), len(start) - 1),
                                     np.full(len(mesh.points), MASS), np.zeros(3), np.zeros(3), 0.0,
                                     3.75, z_edge, ALPHA, 0.0, 0.0, DT, f, *buffers, np.zeros(2400), out)
        return f, out, buffers[0], buffers[1][:n_loaded]

    z_edge = -0.102  # just under the faces between the layers
    alive = np.ones(len(mesh.cells), np.uint8)
    f, out, _, loaded = push(alive, z_edge)
    assert out[EDGE_POINTS] == 0 and not f.any() and loaded.size == 0
    alive[top_layer] = 0
    f, out, points_per_element, loaded = push(alive, z_edge)
    middle = np.isclose(mesh.points[:, 2], -0.1)
    assert out[EDGE_POINTS] == 2400
    # the loaded elements are the lower layer's ring between r = 3.7 and 3.8 mm, each listed once
    centre = mesh.points[mesh.cells].mean(axis=1)
    ring = ~top_layer & (np.abs(np.hypot(centre[:, 0], centre[:, 1]) - 3.75) < 0.05)
    assert np.array_equal(np.sort(loaded), np.flatnonzero(ring))
    assert points_per_element[loaded].sum() == 2400
    under_edge = middle & (np.abs(np.hypot(*mesh.points[:, :2].T) - 3.75) < 0.06)
    assert np.all(f[~middle] == 0) and np.all(f[under_edge, 2] < 0)
    assert out[EDGE_FORCE_Z] == pytest.approx(-f[:, 2].sum(), rel=1e-12)


def test_the_instrument_feels_the_torque_the_faces_receive():
    """The weights are barycentric in the plan view, so the nodal forces have the moment of the
    point force about the axis (the force direction is common, the arm's plan-view position is
    reproduced): the torques agree exactly. A top face sloping along the edge's direction gives
    a tangential force component, hence a torque."""
    points, cells = cubes(1)
    top = points[:, 2] == H
    points[top, 2] += 0.3 * points[top, 1]  # slopes up along y, the edge's direction
    radius = 10.0
    center = np.array([0.5 * H - radius, 0.5 * H, 0.0])
    face_nodes, owner, neighbour = face_table(points, cells)
    n_points = int(2 * math.pi * radius / 0.005)
    z_edge = H + 0.3 * 0.5 * H - 0.002
    start, faces = edge_face_lists(points, face_nodes, owner, neighbour, np.arange(6), np.ones(1, np.uint8),
                                   center, radius, z_edge, 0.05, n_points)
    f = np.zeros_like(points)
    out = np.zeros(N_EDGE_OUTPUTS)
    eval_edge_contact(points, np.zeros_like(points), face_nodes, owner, start, faces,
                      *face_index(faces, len(owner), len(start) - 1), np.full(8, MASS),
                      center, np.zeros(3), 0.0, radius, z_edge, ALPHA, 0.0, 0.0, DT, f,
                      *load_buffers(len(cells)), np.zeros(n_points), out)
    on_tissue = np.sum((points[:, 0] - center[0]) * f[:, 1] - (points[:, 1] - center[1]) * f[:, 0])
    assert out[EDGE_POINTS] > 0 and abs(out[EDGE_TORQUE_Z]) > 1e-4
    assert out[EDGE_TORQUE_Z] == pytest.approx(-on_tissue, rel=1e-9)


def test_a_turning_edge_rubs_the_faces_with_coulomb_friction():
    """The edge pressed into a still flat ring while turning at omega: every point slides at
    omega R, so the faces are dragged along the rotation with mu times their normal force and
    the instrument feels M_z = -sgn(omega) mu N R; the friction power is mu N omega R."""
    mesh = ring_mesh(np.array([3.6, 3.7, 3.8, 3.9]), 120, np.array([-0.2, 0.0]))
    face_nodes, owner, neighbour = face_table(mesh.points, mesh.cells)
    z_edge, mu, omega, n_points = -0.002, 0.2, 3.0, 2400
    start, faces = edge_face_lists(mesh.points, face_nodes, owner, neighbour, np.arange(len(owner)),
                                   np.ones(len(mesh.cells), np.uint8), np.zeros(3), 3.75, z_edge, 0.05,
                                   n_points)
    f = np.zeros_like(mesh.points)
    out = np.zeros(N_EDGE_OUTPUTS)
    eval_edge_contact(mesh.points, np.zeros_like(mesh.points), face_nodes, owner, start, faces,
                      *face_index(faces, len(owner), len(start) - 1), np.full(len(mesh.points), MASS),
                      np.zeros(3), np.zeros(3), omega, 3.75, z_edge,
                      ALPHA, 0.0, mu, DT, f, *load_buffers(len(mesh.cells)), np.zeros(n_points), out)
    normal = out[EDGE_NORMAL]
    assert out[EDGE_POINTS] == n_points and normal > 0
    assert out[EDGE_FORCE_Z] == pytest.approx(normal, rel=1e-12)  # flat faces: normal = z
    assert out[EDGE_TORQUE_Z] == pytest.approx(-mu * normal * 3.75, rel=1e-9)
    assert out[EDGE_FRICTION_POWER] == pytest.approx(mu * normal * omega * 3.75, rel=1e-9)
    tangential = -mesh.points[:, 1] * f[:, 0] + mesh.points[:, 0] * f[:, 1]  # r x f on the tissue
    assert tangential.sum() == pytest.approx(mu * normal * 3.75, rel=1e-9)  # dragged along omega > 0


def pressed_ring():
    """The ring of tissue of :func:`ring_press`: node rings at 3.5-4.0 mm, 120 sectors, 0.2 mm deep."""
    return ring_mesh(np.array([3.5, 3.6, 3.7, 3.8, 3.9, 4.0]), 120, np.array([-0.2, -0.1, 0.0]))


BUMP_SECTORS = 10
"""Sectors (of 120) whose top is raised by ``ring_press``'s ``bump``."""


def ring_press(edge_contact, cutting_toughness=None, bump=0.0):
    """A trephine edge (radius 3.75 mm) pressed 0.02 mm into a ring of tissue between its node
    rings at 3.7 and 3.8 mm (the bevel does not reach the 3.8 mm ring) over 400 steps, then
    held: the model, a maker of the trephine's hook, the end time (s) and the damping (1/s).
    ``bump`` (mm) lowers the top of all but the first ``BUMP_SECTORS`` sectors, so that the
    edge touches those first."""
    material = KernelMaterial(density=1e-9, c10=0.2, d1=0.2)
    mesh = pressed_ring()
    angle = np.mod(np.arctan2(mesh.points[:, 1], mesh.points[:, 0]), 2 * np.pi)
    lowered = (mesh.points[:, 2] == 0.0) & (angle > 2 * np.pi * BUMP_SECTORS / 120 + 1e-9)
    mesh.points[lowered, 2] -= bump
    probe = build_model(mesh, {"layer": material}, [Fixed("bottom", "xyz")])
    model = build_model(mesh, {"layer": material}, [Fixed("bottom", "xyz")],
                        target_time_step=0.9 * probe.element_time_step.max())
    dt = model.stable_time_step()[0]
    press = 400 * dt

    def hook():
        motion = Motion(insertion=SmoothStep(0.0, press, -0.001, 0.02))
        settings = ContactSettings(friction=Friction(law="none"), penalty_fraction=0.3,
                                   edge_contact=edge_contact, cutting_toughness=cutting_toughness)
        return InstrumentContact(Trephine(diameter=7.5, wall_thickness=0.1), motion, model, settings,
                                 name="trephine")

    return model, hook, 2.5 * press, 2 * math.pi / (40 * dt)


def press_edge_between_rings(edge_contact, cutting_toughness=None, history_every=50, **options):
    """History rows of :func:`ring_press`, with the elements deleted since the last row."""
    model, hook, end, damping = ring_press(edge_contact, cutting_toughness, **options)
    return [dict(frame.history, deleted=[element for _, element, _ in frame.deletions])
            for frame in run(model, new_state(model), end, history_every=history_every, hooks=[hook()],
                             damping=damping)
            if frame.history is not None]


def test_an_edge_between_node_rings_is_held_only_by_the_edge_contact():
    without = press_edge_between_rings(False)
    assert max(row["trephine_force_z_N"] for row in without) == 0.0
    rows = press_edge_between_rings(True)
    last = rows[-1]
    assert last["trephine_edge_contact_points"] > 100
    assert last["trephine_force_z_N"] > 0
    # quasi-static at the end: the support carries what the edge pushes
    assert last["reaction_bottom_z_N"] == pytest.approx(last["trephine_force_z_N"], rel=0.02)


def test_the_edge_cuts_when_its_averaged_line_load_reaches_the_toughness():
    """Sharp-blade cutting: the elements under the edge are deleted when the force per unit
    length of edge, F_z / (2 pi R) on this full ring, averaged over N = CUT_AVERAGING_STEPS
    steps (q_avg <- q_avg (1 - 1/N) + q / N), reaches the toughness; only elements under the
    edge go."""
    uncut = press_edge_between_rings(True)[-1]["trephine_force_z_N"] / (2 * math.pi * 3.75)
    toughness = 0.5 * uncut
    rows = press_edge_between_rings(True, cutting_toughness=toughness, history_every=1)
    first = next(i for i, row in enumerate(rows) if row["deleted"])
    average = 0.0
    for row in rows[:first + 1]:
        average += (row["trephine_force_z_N"] / (2 * math.pi * 3.75) - average) / CUT_AVERAGING_STEPS
    # the rule counts the springs of the points of each element, F_z adds their small
    # dashpot and the average over all of them (1%)
    assert average == pytest.approx(toughness, rel=0.01)
    assert rows[first]["trephine_force_z_N"] / (2 * math.pi * 3.75) > 1.2 * toughness  # the lag
    mesh = pressed_ring()
    deleted = [element for row in rows for element in row["deleted"]]
    centres = mesh.points[mesh.cells[deleted]].mean(axis=1)
    assert np.all(np.abs(np.hypot(centres[:, 0], centres[:, 1]) - 3.75) < 0.05)  # only under the edge


def test_where_the_edge_touches_first_the_ring_rule_waits_for_the_whole_edge():
    """A bump of 10 um on 10 of the 120 sectors takes the first touch. The ring rule cuts
    when the average of the push per unit length of the whole edge, F_z / (2 pi R), reaches
    the toughness (1%), not when the few points on the bump press hard."""
    uncut = press_edge_between_rings(True)[-1]["trephine_force_z_N"] / (2 * math.pi * 3.75)
    toughness = 0.5 * uncut
    rows = press_edge_between_rings(True, cutting_toughness=toughness, history_every=1, bump=0.01)
    first = next(i for i, row in enumerate(rows) if row["deleted"])
    average = 0.0
    for row in rows[:first + 1]:
        average += (row["trephine_force_z_N"] / (2 * math.pi * 3.75) - average) / CUT_AVERAGING_STEPS
    assert average == pytest.approx(toughness, rel=0.01)


def test_a_cutting_run_resumed_from_a_checkpoint_continues_bit_for_bit(tmp_path):
    """The averaged line loads of the cutting rule are saved with the hook: a run stopped
    while the edge loads the ring and resumed with a new hook deletes the same elements at the
    same steps and ends in the same state."""
    uncut = press_edge_between_rings(True)[-1]["trephine_force_z_N"] / (2 * math.pi * 3.75)
    model, hook, end, damping = ring_press(True, cutting_toughness=0.5 * uncut)
    straight = new_state(model)
    straight_deletions = [d for frame in run(model, straight, end, hooks=[hook()], damping=damping)
                          for d in frame.deletions]
    state, first = new_state(model), hook()
    for frame in run(model, state, end, hooks=[first], damping=damping, checkpoint_every=150):
        if frame.checkpoint_due:
            save_checkpoint(tmp_path / "c.npz", model, frame.state, [first])
            break
    assert 0 < first.cutting.load.max() and not state.deleted_element.size  # loaded, not yet cut
    second = hook()
    resumed = load_checkpoint(tmp_path / "c.npz", model, [second])
    deletions = [d for frame in run(model, resumed, end, hooks=[second], damping=damping)
                 for d in frame.deletions]
    assert deletions == straight_deletions and len(deletions) > 0
    np.testing.assert_array_equal(resumed.u, straight.u)


@pytest.mark.parametrize("every", [153, 157])
def test_a_run_resumed_between_two_face_lists_continues_bit_for_bit(tmp_path, every):
    """The candidate and face lists are saved with their age: a checkpoint taken between two
    lists (every 10 steps, here at steps 153 or 157) resumes to the uninterrupted run. Rebuilding
    the lists at once on restoring gave a different force from the next step on (the umbrella
    trephine at 62 s, docs/solver.md)."""
    model, hook, end, damping = ring_press(True)
    straight = new_state(model)
    forces = [frame.history["trephine_force_z_N"] for frame in
              run(model, straight, end, hooks=[hook()], damping=damping, history_every=1)]
    state, first = new_state(model), hook()
    for frame in run(model, state, end, hooks=[first], damping=damping, checkpoint_every=every):
        if frame.checkpoint_due:
            save_checkpoint(tmp_path / "c.npz", model, frame.state, [first])
            break
    second = hook()
    resumed = load_checkpoint(tmp_path / "c.npz", model, [second])
    assert resumed.step == every and second.steps_since_candidates == first.steps_since_candidates != 0
    after = [frame.history["trephine_force_z_N"] for frame in
             run(model, resumed, end, hooks=[second], damping=damping, history_every=1)]
    assert after == forces[every + 1:]
    np.testing.assert_array_equal(resumed.u, straight.u)


def test_edge_contact_needs_a_trephine_on_hexahedra_and_a_stable_penalty():
    mesh = ring_mesh(np.array([3.6, 3.8, 4.0]), 24, np.array([-0.1, 0.0]))
    material = KernelMaterial(density=1e-9, c10=0.2, d1=0.2)
    model = build_model(mesh, {"layer": material}, [Fixed("bottom", "xyz")])
    with pytest.raises(InputError, match="edge_contact"):
        InstrumentContact(Needle(), Motion(), model, ContactSettings(edge_contact=True))
    with pytest.raises(ValueError, match="cutting_toughness needs edge_contact"):
        ContactSettings(cutting_toughness=0.002)
    with pytest.raises(InputError, match="penalty_fraction"):
        InstrumentContact(Trephine(diameter=7.5, wall_thickness=0.1), Motion(), model,
                          ContactSettings(edge_contact=True, penalty_fraction=0.5))


def test_faces_on_the_models_cuts_do_not_hold_the_edge():
    """A face whose nodes all lie on a cut of the model (a symmetry plane, a support) bounds
    the model, not the tissue: it does not hold the edge."""
    from corneasim.contact._edge import EdgeContact

    points, cells = cubes(1)
    radius = 10.0
    pose = np.zeros(8)
    pose[:3] = 0.5 * H - radius, 0.5 * H, H - 0.002
    top = points[:, 2] == H
    for cut, held in ((np.zeros(8, bool), True), (top, False)):
        edge = EdgeContact(points, cells, radius, 0.025, 1.0, 0.05, cut)
        edge.refresh(points, np.ones(1, np.uint8), pose)
        f = np.zeros_like(points)
        edge.add_forces(points, np.zeros_like(points), np.full(8, MASS), pose, ALPHA, 0.0, 0.0, DT, f)
        assert bool(np.any(f[top, 2] < 0)) == held


def test_face_list_nodes_are_the_distinct_nodes_of_the_listed_faces():
    from corneasim.contact._edge_faces import face_list_nodes

    face_nodes = np.array([[0, 1, 2, 3], [2, 3, 4, 5], [9, 8, 1, 0], [6, 7, 8, 9]], np.int64)
    mark = np.zeros(10, np.uint8)
    nodes = face_list_nodes(face_nodes, np.array([1, 2, 1], np.int64), mark)
    assert nodes.tolist() == [2, 3, 4, 5, 9, 8, 1, 0]  # first appearance, each once
    assert sorted(nodes) == np.unique(face_nodes[[1, 2]]).tolist()
    assert not mark.any()  # left as found, for the next lists


def test_holding_faces_reports_the_face_and_depth_the_forces_use():
    """The public search of the points' holding faces (a diagnostic) finds the top face of a
    cube for the points of an edge 2 um below it, at that depth, and add_forces pushes with
    as many points."""
    from corneasim.contact._edge_law import HOLD_DEPTH, HOLD_NORMAL
    from corneasim.contact._edge import EdgeContact

    points, cells = cubes(1)
    radius, depth = 10.0, 0.002
    pose = np.zeros(8)
    pose[:3] = 0.5 * H - radius, 0.5 * H, H - depth
    edge = EdgeContact(points, cells, radius, 0.025, 1.0, 0.05, np.zeros(8, bool))
    edge.refresh(points, np.ones(1, np.uint8), pose)
    held, contact = edge.holding_faces(points, pose)
    top = np.flatnonzero((points[edge.face_nodes, 2] == H).all(axis=1))
    assert held.size == edge.n_points and set(held[held >= 0]) == {top[0]}
    np.testing.assert_allclose(contact[held >= 0, HOLD_DEPTH], depth, rtol=1e-9)
    np.testing.assert_allclose(contact[held >= 0, HOLD_NORMAL + 2], 1.0)
    out = edge.add_forces(points, np.zeros_like(points), np.full(8, MASS), pose, ALPHA, 0.0, 0.0, DT, np.zeros_like(points))
    assert out[EDGE_POINTS] == np.count_nonzero(held >= 0) > 0


def sunk_edge(depth):
    """An edge contact on a cube whose edge has sunk under the top face, 2 um a step, to
    ``depth`` (mm); returns (contact, pose, forces on the nodes, outputs of the last step)."""
    from corneasim.contact._edge import EdgeContact

    points, cells = cubes(1)
    radius = 10.0
    pose = np.zeros(8)
    pose[:3] = 0.5 * H - radius, 0.5 * H, H + 0.001
    sinking = EdgeContact(points, cells, radius, 0.025, 1.0, 0.05, np.zeros(8, bool))
    sinking.refresh(points, np.ones(1, np.uint8), pose)
    for z_edge in np.linspace(H + 0.001, H - depth, int(round((depth + 0.001) / 0.002)) + 1):
        pose[2] = z_edge
        f = np.zeros_like(points)
        out = sinking.add_forces(points, np.zeros_like(points), np.full(8, MASS), pose, ALPHA, 0.0, 0.0, DT, f)
    return sinking, pose, f, out


def test_a_point_takes_a_face_no_deeper_than_it_could_have_sunk_in_one_step():
    """An edge 0.3 h under a cube's top face (inside the h/2 window) is held by it when it got
    there by sinking in step by step, and pushed with the penalty spring k d of that depth; the
    same edge found there without having touched the face a step before (the face carried over
    it) is not held (``ACQUIRE_DEPTH`` = 0.2)."""
    from corneasim.contact._edge_law import ACQUIRE_DEPTH
    from corneasim.contact._edge import EdgeContact

    depth = 0.3 * H
    assert ACQUIRE_DEPTH * H < depth < 0.5 * H
    sinking, pose, f, out = sunk_edge(depth)
    points, cells = cubes(1)
    spacing = sinking.point_spacing
    line_stiffness = ALPHA * MASS / DT**2 * min(spacing / H, 1.0) / spacing  # k per mm of edge
    assert out[EDGE_POINTS] == pytest.approx(H / spacing, abs=1)
    assert -f[:, 2].sum() == pytest.approx(line_stiffness * depth * H, abs=line_stiffness * depth * spacing)
    fresh = EdgeContact(points, cells, sinking.radius, 0.025, 1.0, 0.05, np.zeros(8, bool))
    fresh.refresh(points, np.ones(1, np.uint8), pose)
    f = np.zeros_like(points)
    out = fresh.add_forces(points, np.zeros_like(points), np.full(8, MASS), pose, ALPHA, 0.0, 0.0, DT, f)
    assert out[EDGE_POINTS] == 0 and not f.any()
    # from a depth 0.1 h shallower it is taken again: the point may sink 0.2 h in a step
    fresh.depth_before[:] = depth - 0.1 * H
    out = fresh.add_forces(points, np.zeros_like(points), np.full(8, MASS), pose, ALPHA, 0.0, 0.0, DT, np.zeros_like(points))
    assert out[EDGE_POINTS] == pytest.approx(H / spacing, abs=1)


def test_a_restored_edge_contact_remembers_how_deep_its_points_were():
    """The points' depths go with the checkpoint: an edge that sank 0.3 h under a face is still
    held by it after a restore into a new contact, as in the run that was not interrupted."""
    from corneasim.contact._edge import EdgeContact

    sinking, pose, f, out = sunk_edge(0.3 * H)
    points, cells = cubes(1)
    restored = EdgeContact(points, cells, 10.0, 0.025, 1.0, 0.05, np.zeros(8, bool))
    restored.restore(sinking.checkpoint())
    g = np.zeros_like(points)
    again = restored.add_forces(points, np.zeros_like(points), np.full(8, MASS), pose, ALPHA, 0.0, 0.0, DT, g)
    assert again[EDGE_POINTS] == out[EDGE_POINTS] > 0
    np.testing.assert_array_equal(g, f)
