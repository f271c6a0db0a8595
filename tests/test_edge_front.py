"""A trephine's edge on the front of a cohesive cut (contact._edge_front, fracture._edge_work).

Truths: the line stiffness alpha m / (dt^2 L) of a straight front segment integrated along
the edge (a closed form of the ring's geometry), the split's geometry (which nodes are on the
front, which faces are the cut's lip), and the toughness: G_c times the area of the cut
surface, measured on the ring's geometry.
"""

import math

import numpy as np
import pytest

from corneasim.contact import InstrumentContact
from corneasim.contact._edge import EdgeContact
from corneasim.contact._edge_law import EDGE_FORCE_Z, EDGE_POINTS, N_EDGE_OUTPUTS
from corneasim.contact._friction import Friction
from corneasim.contact._settings import ContactSettings
from corneasim.fracture import CohesiveTies, EdgeWork
from corneasim.fracture._edge_work import tie_lines
from corneasim.fracture._split import split_nodes
from corneasim.fracture._law import dissipated_density
from corneasim.fracture._ties import tie_areas
from corneasim.instruments._kinds import Trephine
from corneasim.instruments._motion import Motion
from corneasim.materials import KernelMaterial
from corneasim.solver import Fixed, build_model, new_state, run
from corneasim.solver._amplitudes import Fourier, Linear

from ring_helpers import ring_mesh

R = 3.75  # mm, the edge's radius and the split's
SECTORS = 24
SPACING = 0.05  # mm, between tie levels
LAYERS = SPACING * np.arange(-4.0, 0.5)  # mm
MASS, DT, ALPHA = 1e-9, 1e-5, 0.3


def split_ring():
    """A ring of tissue (node rings at 3.65-3.85 mm) split on r = R: (mesh, pairs, line_start, line_pairs)."""
    mesh = ring_mesh(np.array([3.65, R, 3.85]), SECTORS, LAYERS)
    radius = np.hypot(mesh.points[:, 0], mesh.points[:, 1])
    on_cylinder = np.flatnonzero(np.isclose(radius, R, rtol=0.0, atol=1e-9))
    outside = radius[mesh.cells].mean(axis=1) > R
    mesh, pairs = split_nodes(mesh, on_cylinder, outside)
    line_start, line_pairs = tie_lines(mesh.points, pairs)
    return mesh, pairs, line_start, line_pairs


def front_forces(z_edge, cut_rows):
    """Edge forces at rest at height ``z_edge`` (mm) with the top ``cut_rows[k]`` ties of line k cut."""
    mesh, pairs, line_start, line_pairs = split_ring()
    cut = np.zeros(len(pairs), np.uint8)
    for line, rows in enumerate(cut_rows):
        cut[line_pairs[line_start[line]:line_start[line] + rows]] = 1
    edge = EdgeContact(mesh.points, mesh.cells, R, 0.25, 1.0, 0.1, np.zeros(mesh.n_nodes, bool))
    edge.hold_by_fronts(pairs, line_start, line_pairs, cut)
    pose = np.zeros(8)
    pose[2] = z_edge
    alive = np.ones(mesh.n_elements, np.uint8)
    edge.refresh(mesh.points, alive, pose)
    f = np.zeros_like(mesh.points)
    out = edge.add_forces(mesh.points, np.zeros_like(mesh.points), np.full(mesh.n_nodes, MASS), pose, ALPHA, 0.0,
                          0.0, DT, f).copy()
    return mesh, pairs, line_start, line_pairs, edge, f, out


def test_the_edge_rests_on_the_front_not_on_the_lip_of_the_cut():
    """Top row of ties cut on every line: the edge 0.01 mm below the anterior surface is under
    the lip's faces (which a face contact would hold), above the front (0.05 mm down): no force.
    0.005 mm below the front, the front segments hold it as a line spring: F_z = alpha m d / dt^2
    x 2 pi R / L (L the segments' chord), all of it on the front pairs' nodes."""
    _, _, _, _, _, f, out = front_forces(-0.01, [1] * SECTORS)
    assert out[EDGE_POINTS] == 0 and not f.any()
    mesh, pairs, line_start, line_pairs, edge, f, out = front_forces(-SPACING - 0.005, [1] * SECTORS)
    chord = 2 * R * math.sin(math.pi / SECTORS)
    assert out[EDGE_POINTS] == edge.n_points
    assert out[EDGE_FORCE_Z] == pytest.approx(ALPHA * MASS * 0.005 / DT ** 2 * 2 * math.pi * R / chord, rel=1e-9)
    front = pairs[line_pairs[line_start[:-1] + 1]].ravel()
    loaded = np.flatnonzero(np.abs(f).sum(axis=1))
    assert set(loaded.tolist()) == set(front.tolist())
    assert -f[:, 2].sum() == pytest.approx(out[EDGE_FORCE_Z], rel=1e-12)
    # the lip's faces (a node on a cut tie) are out of the face contact
    lip = np.isin(edge.face_nodes, pairs[line_pairs[line_start[:-1]]]).any(axis=1)
    assert edge.cut_faces[lip].all()


def test_a_line_cut_through_leaves_its_segments_without_a_front():
    """Line 0 cut through: the two segments beside it hold nothing; the others hold their share."""
    mesh, pairs, line_start, line_pairs, edge, f, out = front_forces(-SPACING - 0.005, [LAYERS.size] + [1] * (SECTORS - 1))
    _, _, _, _, whole, _, reference = front_forces(-SPACING - 0.005, [1] * SECTORS)
    assert out[EDGE_FORCE_Z] == pytest.approx(reference[EDGE_FORCE_Z] * (SECTORS - 2) / SECTORS, rel=0.02)
    assert not f[pairs[line_pairs[line_start[0]:line_start[1]]].ravel()].any()


def turning_cut(fracture_energy=0.005, end=0.1):
    """The split ring tied by ties of toughness ``fracture_energy`` (N/mm), cut by a trephine
    that descends at 1 mm/s from 1 um above it while turning (+-0.3 rad at 20 rad/s), with
    Coulomb friction 0.3, to ``end`` (s): each history row with the height of the edge and, by
    line, the current height of its front pair (-inf: cut through); the ties; the lines."""
    mesh, pairs, line_start, line_pairs = split_ring()
    material = KernelMaterial(density=1e-9, c10=0.2, d1=0.02)  # nearly incompressible: stiff ties (k ~ K h)
    model = build_model(mesh, {"layer": material}, [Fixed("bottom", "xyz")], target_time_step=2e-5)
    ties = CohesiveTies(model, pairs, tie_areas(mesh, pairs), 1.0, fracture_energy, name="cut")
    motion = Motion(insertion=Linear(1.0), rotation=Fourier(cosine=(0.0,), sine=(0.3,), circular_frequency=20.0),
                    tip_position=(0.0, 0.0, 0.001))
    settings = ContactSettings(friction=Friction(law="coulomb", coefficient=0.3), penalty_fraction=0.3,
                               edge_contact=True)
    trephine = InstrumentContact(Trephine(diameter=2 * R, wall_thickness=0.1), motion, model, settings,
                                 name="trephine")
    work = EdgeWork(ties, trephine)
    trephine.edge.hold_by_fronts(pairs, work.line_start, work.line_pairs, ties.cut)
    rows = []
    for frame in run(model, new_state(model), end, history_every=20, hooks=[work.before, trephine, work, ties],
                     damping=200.0):
        if frame.history is None:
            continue
        x = mesh.points + frame.state.u
        fronts = np.full(line_start.size - 1, -np.inf)
        for line in range(line_start.size - 1):
            uncut = [i for i in line_pairs[line_start[line]:line_start[line + 1]] if not ties.cut[i]]
            if uncut:
                fronts[line] = 0.5 * (x[pairs[uncut[0], 0], 2] + x[pairs[uncut[0], 1], 2])
        rows.append(dict(frame.history, edge_z=float(trephine.pose[2]), fronts=fronts, cut=int(ties.cut.sum())))
    return rows, ties, mesh


def test_the_turning_edge_cuts_the_ties_at_its_front_as_it_descends():
    """The edge rests on the fronts and the front follows it down: at every row each line's
    front is at the edge (pressed by it, within 2 um) or below it, by less than two tie
    spacings (its tie above just cut, or the one above that too by the walls' work on the
    flanks: ``fracture._edge_work``); the ties are cut row after row, and what the cut ties
    took (the blade's work and their own opening) is G_c times the area of the cut, measured on
    the ring (chord x depth: the top tie stands for half a spacing), within 2 %."""
    rows, ties, mesh = turning_cut()
    for row in rows:
        fronts = row["fronts"][np.isfinite(row["fronts"])]
        assert np.all(fronts <= row["edge_z"] + 0.002)
        assert np.all(fronts > row["edge_z"] - 2 * SPACING)
    assert rows[-1]["cut"] >= 2 * SECTORS and rows[-1]["trephine_edge_contact_points"] > 0
    assert [row["cut"] for row in rows] == sorted(row["cut"] for row in rows)
    cut = ties.cut.astype(bool)
    z = mesh.points[ties.pairs[cut, 0], 2]
    rows_cut = np.round(-z / SPACING).astype(int)  # 0 for the top row
    assert rows_cut.max() < LAYERS.size - 1  # the fixed bottom row holds
    chord = 2 * R * math.sin(math.pi / SECTORS)
    area = np.sum(np.where(rows_cut == 0, 0.5, 1.0) * SPACING * chord)
    fracture = ties.supplied[cut].sum() + np.sum(
        [ties.area[i] * dissipated_density(ties.opening_max[i], ties.strength[i],
                                            ties.strength[i] * ties.area[i] / ties.stiffness[i], ties.separation[i])
         for i in np.flatnonzero(cut)])
    assert fracture == pytest.approx(0.005 * area, rel=0.02)


def test_the_split_meets_the_blade_on_its_cylinder():
    """The ring's split moved off the blade: each line's nodes meet the instrument moved radially
    by that line's front offset, so the front pairs lie on r = R (1e-12) and the cut flanks keep
    their distances from it; z is untouched; a line cut through keeps the offset it had."""
    mesh, pairs, line_start, line_pairs = split_ring()
    cut = np.zeros(len(pairs), np.uint8)
    cut[line_pairs[line_start[:-1]]] = 1  # top row cut on every line
    edge = EdgeContact(mesh.points, mesh.cells, R, 0.25, 1.0, 0.1, np.zeros(mesh.n_nodes, bool))
    edge.hold_by_fronts(pairs, line_start, line_pairs, cut)
    points = mesh.points
    angle = np.arctan2(points[:, 1], points[:, 0])
    radial = np.stack([np.cos(angle), np.sin(angle), np.zeros_like(angle)], axis=1)
    line = np.empty(len(pairs), np.int64)
    for k in range(line_start.size - 1):
        line[line_pairs[line_start[k]:line_start[k + 1]]] = k
    offset = 0.004 + 0.001 * np.arange(line_start.size - 1)  # mm, outwards, one per line
    u = np.zeros_like(points)
    for side in range(2):
        u[pairs[:, side]] = offset[line][:, None] * radial[pairs[:, side]]
    top = line_pairs[line_start[:-1]]
    u[pairs[top, 0]] -= 0.01 * radial[pairs[top, 0]]  # the cut flanks open: the disc's inwards
    u[pairs[top, 1]] += 0.02 * radial[pairs[top, 1]]  # and the rim's outwards
    pose = np.zeros(8)
    x = np.full_like(points, np.nan)
    edge.place_split(u, pose, x)
    radius = np.hypot(x[:, 0], x[:, 1])
    front = line_pairs[line_start[:-1] + 1]
    assert np.abs(radius[pairs[front]] - R).max() < 1e-12
    assert np.abs(radius[pairs[top, 0]] - (R - 0.01)).max() < 1e-12
    assert np.abs(radius[pairs[top, 1]] - (R + 0.02)).max() < 1e-12
    assert np.array_equal(x[pairs.ravel(), 2], points[pairs.ravel(), 2])
    assert np.allclose(np.arctan2(x[pairs.ravel(), 1], x[pairs.ravel(), 0]), angle[pairs.ravel()], atol=1e-12)
    assert np.isnan(x[np.setdiff1d(np.arange(mesh.n_nodes), pairs.ravel())]).all()
    cut[:] = 1  # every line cut through: the offsets stay, wherever the nodes go
    u[pairs.ravel()] += 0.05 * radial[pairs.ravel()]
    edge.place_split(u, pose, x)
    assert np.abs(np.hypot(x[pairs[front], 0], x[pairs[front], 1]) - (R + 0.05)).max() < 1e-12
