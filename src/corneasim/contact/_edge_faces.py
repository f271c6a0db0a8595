"""The faces an instrument's circular edge may touch: lists per edge point, made every few steps.

The edge contact (:mod:`corneasim.contact._edge_law`) tests points p_j spaced along the edge
circle against the tissue's boundary faces. Testing every face at every step would cost the
whole surface; instead each point gets the list of faces whose plan-view window (about the
instrument axis, grown by a margin) contains its angle and whose height range it can reach
(:func:`edge_face_lists`), made anew with the node contact's candidates and after deletions.
:func:`face_slots` numbers the distinct listed faces, :func:`face_list_nodes` marks their
nodes (the only positions the edge reads between two lists) and :func:`face_boxes` gives
their plan-view boxes at the current positions.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from corneasim.mesh import face_normal_z, face_size


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
