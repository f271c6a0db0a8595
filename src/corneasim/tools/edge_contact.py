"""Contact of an instrument's sharp circular edge with the boundary faces of a hexahedral mesh.

The node-to-surface contact of :mod:`corneasim.tools.contact` tests the tissue's *nodes*
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

from corneasim.tools.surface import face_normal_z, face_size, face_table, point_over_face

(EDGE_FORCE_X, EDGE_FORCE_Y, EDGE_FORCE_Z, EDGE_TORQUE_Z, EDGE_POINTS, EDGE_PENETRATION, EDGE_NORMAL,
 EDGE_FRICTION_POWER) = range(8)
N_EDGE_OUTPUTS = 8
"""Entries of the ``out`` array of :func:`eval_edge_contact`: force (N) and torque about the
instrument axis (N mm) of the tissue on the instrument, the number of edge points in contact,
their largest penetration (mm), the sum of their normal force magnitudes (N) and the power
dissipated by their friction (mJ/s)."""


@njit(cache=True)
def edge_face_lists(x, face_nodes, face_owner, face_neighbour, faces, alive, center, radius,
                    z_edge, margin, n_points):
    """The boundary faces each edge point may touch before anything moves by ``margin``.

    Edge point j sits at the angle 2 pi j / n_points about the axis through ``center``
    (x, y, mm), at radius ``radius`` and height ``z_edge`` (mm). A boundary face (live owner,
    no live element across) that faces up (towards the instrument) is listed for the points
    within its angular span, grown by
    (``margin`` + h / 2) / ``radius``, when its radial and height ranges come within
    ``margin`` + h / 2 (mm) of the edge: h / 2 is the depth down to which a face holds a point
    (h the face size). Only the faces ``faces`` (ids into the face table) are considered: those of the
    band the edge can reach (``EdgeContact``).

    Returns
    -------
    (point_start, point_faces)
        CSR lists: the faces of point j are ``point_faces[point_start[j]:point_start[j + 1]]``.
    """
    step = 2.0 * math.pi / n_points
    span = np.empty((faces.shape[0], 2), dtype=np.int64)
    count = np.zeros(n_points + 1, dtype=np.int64)
    for i in range(faces.shape[0]):
        f = faces[i]
        span[i, 0], span[i, 1] = 0, -1
        neighbour = face_neighbour[f]
        if alive[face_owner[f]] == 0 or (neighbour >= 0 and alive[neighbour] != 0):
            continue
        r_lo, r_hi, z_lo, z_hi = math.inf, -math.inf, math.inf, -math.inf
        for a in range(4):
            node = face_nodes[f, a]
            dx, dy = x[node, 0] - center[0], x[node, 1] - center[1]
            r = math.sqrt(dx * dx + dy * dy)
            r_lo, r_hi = min(r_lo, r), max(r_hi, r)
            z_lo, z_hi = min(z_lo, x[node, 2]), max(z_hi, x[node, 2])
        reach = margin + 0.5 * face_size(x, face_nodes, f)  # a point this close may be in its window
        if r_hi < radius - reach or r_lo > radius + reach or z_hi < z_edge - reach or z_lo > z_edge + reach:
            continue
        if face_normal_z(x, face_nodes, f) <= 0.0:
            continue  # faces away from the instrument (walls turned over, the posterior surface)
        a_lo, a_hi = math.inf, -math.inf
        for a in range(4):
            node = face_nodes[f, a]
            angle = math.atan2(x[node, 1] - center[1], x[node, 0] - center[0])
            a_lo, a_hi = min(a_lo, angle), max(a_hi, angle)
        if a_hi - a_lo > math.pi:  # straddles the angle pi: angles in (0, 2 pi) instead
            a_lo, a_hi = math.inf, -math.inf
            for a in range(4):
                node = face_nodes[f, a]
                angle = math.atan2(x[node, 1] - center[1], x[node, 0] - center[0])
                angle += 2.0 * math.pi if angle < 0.0 else 0.0
                a_lo, a_hi = min(a_lo, angle), max(a_hi, angle)
        grow = reach / radius
        span[i, 0] = int(math.ceil((a_lo - grow) / step))
        span[i, 1] = min(int(math.floor((a_hi + grow) / step)), span[i, 0] + n_points - 1)
        for k in range(span[i, 0], span[i, 1] + 1):
            count[(k % n_points + n_points) % n_points + 1] += 1
    for j in range(n_points):
        count[j + 1] += count[j]
    point_faces = np.empty(count[n_points], dtype=np.int64)
    fill = count[:n_points].copy()
    for i in range(faces.shape[0]):
        for k in range(span[i, 0], span[i, 1] + 1):
            j = (k % n_points + n_points) % n_points
            point_faces[fill[j]] = faces[i]
            fill[j] += 1
    return count, point_faces


@njit(cache=True)
def edge_directions(n_points):
    """(cos beta_j, sin beta_j) of the edge points' angles beta_j = 2 pi j / n_points, (n_points, 2):
    made once per point count instead of by a cosine and a sine per point in both the search
    and the force loop of every step."""
    out = np.empty((n_points, 2))
    for j in range(n_points):
        beta = 2.0 * math.pi * j / n_points
        out[j, 0] = math.cos(beta)
        out[j, 1] = math.sin(beta)
    return out


@njit(cache=True)
def face_slots(point_faces, face_slot, listed, slot):
    """The distinct faces of the point lists, in order of first appearance, into ``listed``,
    and for each list entry its index there into ``slot`` (both as long as ``point_faces``).
    ``face_slot`` (n_faces,) int64 is -1 everywhere on entry and again on return. Returns the
    number of distinct faces."""
    n = 0
    for i in range(point_faces.shape[0]):
        f = point_faces[i]
        if face_slot[f] < 0:
            face_slot[f] = n
            listed[n] = f
            n += 1
        slot[i] = face_slot[f]
    for k in range(n):
        face_slot[listed[k]] = -1
    return n


@njit(cache=True)
def face_list_nodes(face_nodes, listed, node_mark):
    """The distinct nodes of the faces ``listed``, in order of first appearance, (n,) int64:
    the nodes whose positions the edge contact reads between two lists. ``node_mark``
    (n_nodes,) uint8 is 0 everywhere on entry and again on return. The same nodes as
    ``np.unique`` of the face nodes, without its sort: 4 us instead of 61-111 us for 432 faces
    of the umbrella mesh (2026-11-24)."""
    out = np.empty(4 * listed.shape[0], dtype=np.int64)
    n = 0
    for k in range(listed.shape[0]):
        for c in range(4):
            node = face_nodes[listed[k], c]
            if node_mark[node] == 0:
                node_mark[node] = 1
                out[n] = node
                n += 1
    for k in range(n):
        node_mark[out[k]] = 0
    return out[:n]


@njit(cache=True)
def face_boxes(x, face_nodes, listed, boxes):
    """Plan-view bounding box (x_min, x_max, y_min, y_max; mm) of each face of ``listed`` at the
    positions ``x`` into ``boxes`` (n_listed, 4): once per step for all the points that may
    touch a face (about 25 on the umbrella mesh) instead of once per point and face."""
    for k in range(listed.shape[0]):
        f = listed[k]
        n0, n1, n2, n3 = face_nodes[f, 0], face_nodes[f, 1], face_nodes[f, 2], face_nodes[f, 3]
        boxes[k, 0] = min(x[n0, 0], x[n1, 0], x[n2, 0], x[n3, 0])
        boxes[k, 1] = max(x[n0, 0], x[n1, 0], x[n2, 0], x[n3, 0])
        boxes[k, 2] = min(x[n0, 1], x[n1, 1], x[n2, 1], x[n3, 1])
        boxes[k, 3] = max(x[n0, 1], x[n1, 1], x[n2, 1], x[n3, 1])


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
        held[j] = _holding_face(x, face_nodes, point_start, point_faces, point_slots, boxes, j,
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
        Face table (:func:`corneasim.tools.surface.face_table`).
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


class EdgeContact:
    """The edge contact of a trephine on a hexahedral mesh (module notes).

    Parameters
    ----------
    points : ndarray (n_nodes, 3) float64
        Reference coordinates, mm.
    cells : ndarray (n_elements, 8) int64
        Hexahedra (VTK order).
    node_mass : ndarray (n_nodes,) float64
        Lumped (scaled) masses, tonne.
    radius : float
        Edge radius, mm.
    spacing : float
        Distance between two edge points as a fraction of the smallest face that meets the
        edge first (a face of the band that faces up in the reference mesh), dimensionless.
    band : float
        Faces with a node within ``band`` (mm) of the edge radius, about the instrument axis,
        in the reference mesh are the ones the edge can meet (the instrument moves along its
        axis and turns about it).
    margin : float
        Growth of the face lists' reach, mm (as the node contact's candidate margin).
    cut_nodes : ndarray (n_nodes,) bool
        Nodes on the model's cuts (symmetry planes, cyclic-symmetry cut planes, supports): a
        face with all four nodes there bounds the model, not the tissue, and is left out.
    """

    def __init__(self, points, cells, node_mass, radius: float, spacing: float, band: float,
                 margin: float, cut_nodes):
        self.points = np.asarray(points, dtype=np.float64)
        self.face_nodes, self.face_owner, self.face_neighbour = face_table(self.points, cells)
        self.cut_faces = np.asarray(cut_nodes, dtype=bool)[self.face_nodes].all(axis=1)
        self.node_mass = node_mass
        self.radius = float(radius)
        self.spacing = float(spacing)
        self.n_points = 8
        self.band = float(band)
        self.margin = float(margin)
        self.axis = None
        self.band_faces = np.zeros(0, dtype=np.int64)
        self.open_faces = np.zeros(0, dtype=np.int64)
        self.open_faces_dead = -1
        self.point_start = np.zeros(self.n_points + 1, dtype=np.int64)
        self.point_faces = np.zeros(0, dtype=np.int64)
        self.face_slot = np.full(self.face_nodes.shape[0], -1, dtype=np.int64)
        self.node_mark = np.zeros(self.points.shape[0], dtype=np.uint8)
        self._index_lists()
        self.directions = edge_directions(self.n_points)
        self.depth_before = np.zeros(self.n_points)
        self.out = np.zeros(N_EDGE_OUTPUTS)
        n_elements = np.asarray(cells).shape[0]
        self.element_points = np.zeros(n_elements, dtype=np.int64)
        self.loaded = np.zeros(0, dtype=np.int64)
        self.loaded_buffer = np.zeros(0, dtype=np.int64)

    def refresh(self, x, alive, pose) -> None:
        """New face lists from the current positions ``x`` (mm), ``alive`` and ``pose``.

        ``x`` must be current for the nodes of the band's boundary faces (after a deletion, of
        the faces it opened too), and for every node when the instrument axis has moved since
        the last call. Between two calls :meth:`add_forces` reads only the nodes of the listed
        faces, :attr:`listed_nodes`."""
        axis = (float(pose[0]), float(pose[1]))
        if axis != self.axis:
            r = np.hypot(self.points[:, 0] - axis[0], self.points[:, 1] - axis[1])
            near = np.abs(r - self.radius) <= self.band
            reachable = near[self.face_nodes].any(axis=1) & ~self.cut_faces
            self.band_faces = np.flatnonzero(reachable).astype(np.int64)
            self.axis = axis
            corners = self.points[self.face_nodes[self.band_faces]]
            normal = np.cross(corners[:, 2] - corners[:, 0], corners[:, 3] - corners[:, 1])
            area = 0.5 * np.linalg.norm(normal, axis=1)
            level = normal[:, 2] > 0.5 * np.linalg.norm(normal, axis=1)
            size = np.sqrt(area[level].min()) if level.any() else 0.1
            self.n_points = max(8, int(math.ceil(2.0 * math.pi * self.radius / (self.spacing * size))))
            self.depth_before = np.zeros(self.n_points)  # new points: none held a face before
            self.directions = edge_directions(self.n_points)
            self.open_faces_dead = -1
        dead = alive.size - int(np.count_nonzero(alive))
        if dead != self.open_faces_dead:  # elements were deleted: the boundary changed
            self.open_faces = self._boundary(self.band_faces, alive)
            self.open_faces_dead = dead
        self.point_start, self.point_faces = edge_face_lists(
            x, self.face_nodes, self.face_owner, self.face_neighbour, self.open_faces, alive,
            np.asarray(pose[:3], dtype=np.float64), self.radius, float(pose[2]), self.margin,
            self.n_points)
        self._index_lists()

    def _index_lists(self) -> None:
        """The distinct faces of the point lists, each entry's index among them, their nodes and
        a buffer for their plan-view boxes (:func:`face_slots`, :func:`face_boxes`)."""
        listed = np.empty(self.point_faces.size, dtype=np.int64)
        self.point_slots = np.empty(self.point_faces.size, dtype=np.int64)
        n = face_slots(self.point_faces, self.face_slot, listed, self.point_slots)
        self.listed_faces = listed[:n]
        self.listed_nodes = face_list_nodes(self.face_nodes, self.listed_faces, self.node_mark)
        self.boxes = np.empty((n, 4))

    def _boundary(self, faces, alive) -> np.ndarray:
        """The faces of ``faces`` on the tissue's boundary: live owner, no live element across.
        ``edge_face_lists`` tests the same; listing them once per deletion spares it the
        interior faces of the band (most of them) at every refresh."""
        neighbour = self.face_neighbour[faces]
        across_dead = (neighbour < 0) | (alive[np.maximum(neighbour, 0)] == 0)
        return faces[(alive[self.face_owner[faces]] != 0) & across_dead]

    def checkpoint(self) -> dict[str, np.ndarray]:
        """The face lists, the pressed elements and the points' depths of the last step (for a
        bit-for-bit restart)."""
        axis = np.full(2, np.nan) if self.axis is None else np.array(self.axis)
        return {"axis": axis, "band_faces": self.band_faces.copy(), "n_points": np.array(self.n_points),
                "point_start": self.point_start.copy(), "point_faces": self.point_faces.copy(),
                "loaded": self.loaded.copy(), "element_points": self.element_points[self.loaded].copy(),
                "depth_before": self.depth_before.copy()}

    def restore(self, arrays: dict[str, np.ndarray]) -> None:
        """Take back what :meth:`checkpoint` saved."""
        axis = arrays["axis"]
        self.axis = None if np.isnan(axis).any() else (float(axis[0]), float(axis[1]))
        self.band_faces = np.array(arrays["band_faces"], dtype=np.int64)
        self.open_faces_dead = -1
        self.n_points = int(arrays["n_points"])
        self.directions = edge_directions(self.n_points)
        self.depth_before = np.array(arrays["depth_before"], dtype=np.float64)
        self.point_start = np.array(arrays["point_start"], dtype=np.int64)
        self.point_faces = np.array(arrays["point_faces"], dtype=np.int64)
        self._index_lists()
        self.element_points[:] = 0
        self.loaded = np.array(arrays["loaded"], dtype=np.int64)
        self.element_points[self.loaded] = arrays["element_points"]

    def add_forces(self, x, v, pose, penalty_fraction: float, damping_ratio: float, friction: float,
                   dt: float, f_ext) -> np.ndarray:
        """Add the edge forces (N) to ``f_ext``; returns :attr:`out` (``N_EDGE_OUTPUTS``).
        ``friction``: Coulomb coefficient of the edge, dimensionless."""
        self.element_points[self.loaded] = 0
        if self.loaded_buffer.size < self.n_points:
            self.loaded_buffer = np.empty(self.n_points, dtype=np.int64)
        n_loaded = eval_edge_contact(
            x, v, self.face_nodes, self.face_owner, self.point_start, self.point_faces, self.point_slots,
            self.listed_faces, self.boxes, self.directions, self.node_mass, pose[:3], pose[4:7],
            float(pose[7]), self.radius, float(pose[2]), penalty_fraction, damping_ratio, friction, dt, f_ext,
            self.element_points, self.loaded_buffer, self.depth_before, self.out)
        self.loaded = self.loaded_buffer[:n_loaded]
        return self.out

    def holding_faces(self, x, pose) -> tuple[np.ndarray, np.ndarray]:
        """The face holding each edge point at the positions ``x`` (mm) and ``pose``, as
        :meth:`add_forces` would find it after the last step, without adding forces or
        changing the points' remembered depths: (held (n_points,) int64, -1 for none; contact
        geometry (n_points, N_HOLD), columns ``HOLD_*``, valid where held)."""
        n_points = self.point_start.size - 1  # the points the current lists were made for
        held = np.empty(n_points, dtype=np.int64)
        contact = np.empty((n_points, N_HOLD))
        _holding_faces(x, self.face_nodes, self.point_start, self.point_faces, self.point_slots,
                       self.listed_faces, self.boxes, self.directions, np.asarray(pose[:3], dtype=np.float64),
                       self.radius, float(pose[2]), self.depth_before, held, contact)
        return held, contact

    @property
    def point_spacing(self) -> float:
        """Length of edge each point stands for, mm."""
        return 2.0 * math.pi * self.radius / self.n_points

    def length_over_tissue(self) -> float:
        """Length of edge above the tissue, mm: the points with faces listed under them (the
        whole circle, or half of it over a half model)."""
        return max(int(np.count_nonzero(np.diff(self.point_start))), 1) * self.point_spacing
