"""Contact of an instrument's sharp circular edge with the boundary faces of a hexahedral mesh.

The node-to-surface contact of :mod:`corneasim.contact._node` tests the tissue's *nodes*
against the rigid instrument. A trephine's edge is far sharper than the elements, so once
the ring of nodes it rests on slides off (the edge is an unstable support), the edge goes
down *between* two node rings and nothing resists it: a cut that costs no energy
(``docs/trephination.md``, "What the collapse is"). Edge contact adds the converse test.
Points p_j sampled along the edge circle (radius R about the instrument axis, which is
parallel to z, at the tip height) are tested against the triangles (a, b, c) into which the
tissue's boundary faces are split, c the face centroid. The instrument moves along its
axis, so a point is tested along it: against the triangles that face the instrument
(n_z > ``surface.UPWARD``) and whose vertical projection contains the point,

.. math::

    d = (p - a)\\cdot n, \\qquad f = \\max\\left(-k\\,d + c_d\\,(v_f - v_t)\\cdot n,\\ 0\\right),

    k = \\alpha\\,\\frac{m}{\\Delta t^2}\\,\\min\\left(\\frac{\\Delta s}{h}, 1\\right), \\qquad
    c_d = 2 \\zeta \\sqrt{k m},

with n the triangle's outward unit normal, d < 0 when the edge point is inside the tissue
(less than half the face size h = sqrt(area) deep, and no more than ``ACQUIRE_DEPTH`` h deeper
than the point was below its face in the step before), v_f the face velocity at the point and
v_t the instrument's, m the smallest mass of the face's nodes, Delta s the spacing of the edge
points and alpha, zeta the contact's penalty fraction and damping ratio. Projecting along the
axis instead of along each face's normal leaves no blind spot where the tissue folds into a
V around the edge: there, a point just under the fold lies outside both faces' normal
projections but under exactly one of them seen from above. The face is pushed inwards,
f_a = -f w_a n on its node a with w_a the barycentric weight of the projection (the
centroid's weight shared equally by the four nodes), and the instrument feels +f n. Along
the edge the springs add up to a line stiffness alpha m / (Delta t^2 h) per unit length, so a
node takes at most about alpha m / Delta t^2 from the edge, as from the node contact: with both
a node can see 2 alpha (``InstrumentContact`` checks 2 alpha against the stability limit).

A face is on the boundary when its element is alive and the element across it is absent or
dead, so faces exposed by element deletion join at once and the edge cuts on through the next
layer. The edge rubs the face with Coulomb friction, a force mu f opposing the face's sliding
velocity relative to the instrument (its tangential part), regularised (made viscous) below the
slip speed mu f Delta t / m so that it cannot reverse a node's motion in one step; the turning
trephine drags the tissue under its edge and feels the torque. Each point keeps the nearest
face above it; the faces that may reach a point are listed by :func:`edge_face_lists` every few
steps and after deletions.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from corneasim.contact._edge_faces import face_boxes
from corneasim.mesh import point_over_face

(EDGE_FORCE_X, EDGE_FORCE_Y, EDGE_FORCE_Z, EDGE_TORQUE_Z, EDGE_POINTS, EDGE_PENETRATION, EDGE_NORMAL,
 EDGE_FRICTION_POWER) = range(8)
N_EDGE_OUTPUTS = 8
"""Entries of the ``out`` array of :func:`eval_edge_contact`: force (N) and torque about the
instrument axis (N mm) of the tissue on the instrument, the number of edge points in contact,
their largest penetration (mm), the sum of their normal force magnitudes (N) and the power
dissipated by their friction (mJ/s)."""


@njit(cache=True, inline="always")
def _face_weights(t, l0, l1, l2):
    """Weights of a face's four nodes for a point of its triangle t (corners t, t + 1 and the
    centroid) with barycentric coordinates (l0, l1, l2)."""
    w = (0.25 * l2 + (l0 if t == 0 else 0.0) + (l1 if t == 3 else 0.0),
         0.25 * l2 + (l0 if t == 1 else 0.0) + (l1 if t == 0 else 0.0),
         0.25 * l2 + (l0 if t == 2 else 0.0) + (l1 if t == 1 else 0.0),
         0.25 * l2 + (l0 if t == 3 else 0.0) + (l1 if t == 2 else 0.0))
    return w


ACQUIRE_DEPTH = 0.2
"""How much deeper (as a fraction of the face size h) an edge point may be below the face that
holds it than it was below its face in the step before (0 when it had none), dimensionless.

A point that approaches a face crosses it and sinks in by the relative motion of one step, a
few micrometres, and then deepens as the tissue gives: in a stable explicit step nothing moves
by more than a small fraction of an element (the material speeds are far below the wave speed
that sets the step), so 0.2 h a step is not a limit any real approach meets. The search alone (the nearest face
above the point, down to h/2) also finds a face that has slid over a point already deep in
the cut (most likely the top face of the groove's wall, carried across the edge by the
turning trephine); the penalty then pushes that face up with up to k h/2 for one step, and
the point has lost it in the next. In 500 steps of the default umbrella run from 57.1 s, 95 %
of the points that took a face after holding none took it less than 0.11 h deep, and 16 of
the 20 taken deeper than 0.2 h did so in steps with |F_c| of 0.045-0.13 N, up to five times
its median (``docs/trephination.md``, "Edge contact"). Such a face is no support for the edge:
the groove's wall presses the trephine's side through the node contact."""

HOLD_DEPTH, HOLD_NORMAL, HOLD_WEIGHTS, HOLD_SIZE = 0, 1, 4, 8
N_HOLD = 9
"""Columns of the per-point contact geometry of :func:`_holding_faces`: depth below the face
(mm, > 0), the face triangle's unit normal, the weights of the face's four nodes and the
face size h (mm)."""


@njit(cache=True)
def _holding_face(x, face_nodes, point_start, point_faces, point_slots, boxes, j, px, py, pz, depth_before,
                  contact):
    """The listed face that holds edge point j at (px, py, pz) (module notes): the nearest one
    above it, seen along the axis, with the point less than half the face size h below it and
    at most ``ACQUIRE_DEPTH`` h deeper than ``depth_before`` (mm, its depth in the step before).
    ``boxes[point_slots[i]]`` is the plan-view box of list entry i (:func:`face_boxes`).
    Returns the face (-1: none) and writes its geometry to ``contact[j]`` (``HOLD_*``)."""
    best = math.inf
    held = -1
    for i in range(point_start[j], point_start[j + 1]):
        f = point_faces[i]
        k = point_slots[i]
        if px < boxes[k, 0] or px > boxes[k, 1] or py < boxes[k, 2] or py > boxes[k, 3]:
            continue  # not under the face seen from above
        hit, hit_d, nx, ny, nz, l0, l1, l2, area = point_over_face(x, face_nodes, f, px, py, pz, True)
        if hit < 0:
            continue
        h = math.sqrt(area)
        if hit_d <= -0.5 * h or -hit_d > depth_before + ACQUIRE_DEPTH * h or -hit_d >= best:
            continue
        best = -hit_d
        held = f
        w0, w1, w2, w3 = _face_weights(hit, l0, l1, l2)
        contact[j, HOLD_DEPTH] = best
        contact[j, HOLD_NORMAL], contact[j, HOLD_NORMAL + 1], contact[j, HOLD_NORMAL + 2] = nx, ny, nz
        contact[j, HOLD_WEIGHTS], contact[j, HOLD_WEIGHTS + 1] = w0, w1
        contact[j, HOLD_WEIGHTS + 2], contact[j, HOLD_WEIGHTS + 3] = w2, w3
        contact[j, HOLD_SIZE] = h
    return held


@njit(cache=True, parallel=True)
def _holding_faces(x, face_nodes, point_start, point_faces, point_slots, listed, boxes, directions, center,
                   radius, z_edge, depth_before, held, contact):
    """:func:`_holding_face` of every edge point into ``held`` (n_points,) and ``contact``
    (n_points, N_HOLD), given each point's depth in the step before, ``depth_before``
    (n_points,) mm, after the listed faces' plan-view boxes at ``x`` into ``boxes``
    (:func:`face_boxes`). The search over the points' face lists is the costly part of the edge
    contact and each point's is independent, so the points are shared among threads; the
    forces are then added in point order (:func:`eval_edge_contact`), so the result does not
    depend on the number of threads."""
    face_boxes(x, face_nodes, listed, boxes)
    n_points = point_start.shape[0] - 1
    for j in prange(n_points):
        held[j] = _holding_face(x, face_nodes, point_start, point_faces, point_slots, boxes, np.int64(j),
                                center[0] + radius * directions[j, 0], center[1] + radius * directions[j, 1],
                                z_edge, depth_before[j], contact)


@njit(cache=True)
def eval_edge_contact(x, v, face_nodes, face_owner, point_start, point_faces, point_slots, listed,
                      boxes, directions, node_mass, center, velocity, omega, radius, z_edge, penalty_fraction,
                      damping_ratio, friction, dt, f_ext, element_points, loaded, depth_before, out):
    """Add the forces of the edge points on the boundary faces to ``f_ext``; sum what the
    instrument feels into ``out`` (module notes).

    Parameters
    ----------
    x, v : ndarray (n_nodes, 3) float64
        Current positions (mm) and velocities (mm/s).
    face_nodes, face_owner : ndarray (n_faces, 4), (n_faces,) int64
        Face table (:func:`corneasim.mesh._surface.face_table`).
    point_start, point_faces : ndarray int64
        The faces each edge point may touch (:func:`edge_face_lists`).
    point_slots, listed : ndarray int64
        Index of each list entry among the distinct listed faces, and those faces
        (:func:`face_slots`).
    boxes : ndarray (n_listed, 4) float64
        Out: the listed faces' plan-view boxes at ``x`` (:func:`face_boxes`), mm.
    directions : ndarray (n_points, 2) float64
        The edge points' directions from the axis (:func:`edge_directions`).
    node_mass : ndarray (n_nodes,) float64
        Lumped (scaled) nodal masses, tonne.
    center : ndarray (3,) float64
        A point of the instrument axis at the edge's height, mm (the axis is parallel to z).
    velocity : ndarray (3,) float64
        The instrument's translation velocity, mm/s.
    omega : float
        Its angular velocity about the axis, rad/s.
    radius, z_edge : float
        Edge radius and height, mm.
    penalty_fraction, damping_ratio : float
        alpha and zeta of the contact (``ContactSettings``), dimensionless.
    friction : float
        Coulomb coefficient mu of the edge, dimensionless (module notes).
    dt : float
        Time step the penalty is sized for, s.
    f_ext : ndarray (n_nodes, 3) float64
        External nodal forces, N; the edge forces are added.
    element_points : ndarray (n_elements,) int64
        In/out: each point is counted on the element whose face holds it.
    loaded : ndarray (n_points,) int64
        Out: its first entries (as many as returned) are the elements that got a point, in the
        order of their first point (all zero in ``element_points`` on entry).
    depth_before : ndarray (n_points,) float64
        In/out: each point's depth below the face that held it in the step before (0 for none),
        mm (``ACQUIRE_DEPTH``); overwritten with this step's.
    out : ndarray (N_EDGE_OUTPUTS,) float64
        Overwritten: force (N) and torque (N mm) on the instrument, points in contact, largest
        penetration (mm), summed normal force magnitudes (N), friction power (mJ/s).

    Returns
    -------
    int
        The number of elements listed in ``loaded``.
    """
    for k in range(out.shape[0]):
        out[k] = 0.0
    n_loaded = 0
    n_points = point_start.shape[0] - 1
    spacing = 2.0 * math.pi * radius / n_points
    inverse_dt2 = 1.0 / (dt * dt)
    held = np.empty(n_points, dtype=np.int64)
    contact = np.empty((n_points, N_HOLD), dtype=np.float64)
    _holding_faces(x, face_nodes, point_start, point_faces, point_slots, listed, boxes, directions, center,
                   radius, z_edge, depth_before, held, contact)
    for j in range(n_points):
        f = held[j]
        depth_before[j] = contact[j, HOLD_DEPTH] if f >= 0 else 0.0
        if f < 0:
            continue
        ax, ay = radius * directions[j, 0], radius * directions[j, 1]
        best, best_h = contact[j, HOLD_DEPTH], contact[j, HOLD_SIZE]
        nx, ny, nz = contact[j, HOLD_NORMAL], contact[j, HOLD_NORMAL + 1], contact[j, HOLD_NORMAL + 2]
        best_w = (contact[j, HOLD_WEIGHTS], contact[j, HOLD_WEIGHTS + 1], contact[j, HOLD_WEIGHTS + 2],
                  contact[j, HOLD_WEIGHTS + 3])
        m = math.inf
        vfx, vfy, vfz = 0.0, 0.0, 0.0
        for a in range(4):
            node = face_nodes[f, a]
            m = min(m, node_mass[node])
            vfx += best_w[a] * v[node, 0]
            vfy += best_w[a] * v[node, 1]
            vfz += best_w[a] * v[node, 2]
        k = penalty_fraction * m * inverse_dt2 * min(spacing / best_h, 1.0)
        vtx, vty, vtz = velocity[0] - omega * ay, velocity[1] + omega * ax, velocity[2]
        w_n = (vfx - vtx) * nx + (vfy - vty) * ny + (vfz - vtz) * nz
        force = max(k * best + 2.0 * damping_ratio * math.sqrt(k * m) * w_n, 0.0)
        if force == 0.0:
            continue
        # Coulomb friction against the face's sliding, regularised below the speed at which
        # the equivalent viscosity mu f / w_reg would take m's whole momentum in one step
        w_x, w_y, w_z = vfx - vtx - w_n * nx, vfy - vty - w_n * ny, vfz - vtz - w_n * nz
        slip = math.sqrt(w_x * w_x + w_y * w_y + w_z * w_z)
        drag = friction * force / max(slip, friction * force * dt / m, 1e-300)
        t_x, t_y, t_z = -drag * w_x, -drag * w_y, -drag * w_z  # on the tissue
        for a in range(4):
            node = face_nodes[f, a]
            f_ext[node, 0] += best_w[a] * (t_x - force * nx)
            f_ext[node, 1] += best_w[a] * (t_y - force * ny)
            f_ext[node, 2] += best_w[a] * (t_z - force * nz)
        f_x, f_y, f_z = force * nx - t_x, force * ny - t_y, force * nz - t_z  # on the instrument
        out[EDGE_FORCE_X] += f_x
        out[EDGE_FORCE_Y] += f_y
        out[EDGE_FORCE_Z] += f_z
        out[EDGE_TORQUE_Z] += ax * f_y - ay * f_x
        out[EDGE_POINTS] += 1.0
        out[EDGE_PENETRATION] = max(out[EDGE_PENETRATION], best)
        out[EDGE_NORMAL] += force
        out[EDGE_FRICTION_POWER] += drag * slip * slip
        owner = face_owner[f]
        if element_points[owner] == 0:
            loaded[n_loaded] = owner
            n_loaded += 1
        element_points[owner] += 1
    return n_loaded
