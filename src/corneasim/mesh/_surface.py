"""The boundary faces of a hexahedral mesh and a point tested against them along z.

Shared by the trephine's edge contact (:mod:`corneasim.contact._edge`) and its
placement (:mod:`corneasim.instruments._placement`): the faces of every element with the element
across each one (a face is on the boundary when nothing alive is across), and the test of a
point against a face triangle seen from above, along the instrument axis z.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

HEX_FACES = np.array([[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6],
                      [3, 0, 4, 7]], dtype=np.int64)
"""The six faces of a VTK hexahedron, each counter-clockwise seen from outside."""
UPWARD = 0.05
"""Faces whose outward normal has a z component (along the instrument axis, towards the
instrument) below this do not hold the edge: it moves along the axis and meets the tissue
through the faces that face it."""


def face_table(points: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every face of every hexahedron, oriented outwards, with its element and the element across.

    Parameters
    ----------
    points : ndarray (n_nodes, 3) float64
        Reference coordinates, mm.
    cells : ndarray (n_elements, 8) int64
        Hexahedra in VTK order.

    Returns
    -------
    (face_nodes, face_owner, face_neighbour)
        ``face_nodes`` (6 n_elements, 4) int64, counter-clockwise seen from outside the owner
        (checked against the element centroid); ``face_owner`` (6 n_elements,) int64, the
        element of face 6 e + i is e; ``face_neighbour`` (6 n_elements,) int64, the other
        element with the same four nodes, -1 on the mesh boundary.
    """
    cells = np.asarray(cells, dtype=np.int64)
    n_e = cells.shape[0]
    face_nodes = cells[:, HEX_FACES].reshape(-1, 4)
    face_owner = np.repeat(np.arange(n_e, dtype=np.int64), 6)
    corners = points[face_nodes]  # (n_f, 4, 3)
    normal = np.cross(corners[:, 2] - corners[:, 0], corners[:, 3] - corners[:, 1])
    outward = corners.mean(axis=1) - points[cells].mean(axis=1)[face_owner]
    inverted = np.einsum("fi,fi->f", normal, outward) < 0.0
    face_nodes[inverted] = face_nodes[inverted][:, ::-1]
    key = np.sort(face_nodes, axis=1)
    order = np.lexsort(key.T[::-1])
    same = np.all(key[order[1:]] == key[order[:-1]], axis=1)
    face_neighbour = np.full(face_nodes.shape[0], -1, dtype=np.int64)
    first, second = order[:-1][same], order[1:][same]
    face_neighbour[first] = face_owner[second]
    face_neighbour[second] = face_owner[first]
    return np.ascontiguousarray(face_nodes), face_owner, face_neighbour


@njit(cache=True, inline="always")
def face_size(x, face_nodes, f):
    """sqrt of the area of face f (from its diagonals; exact for a plane quadrilateral), mm."""
    n0, n1, n2, n3 = face_nodes[f, 0], face_nodes[f, 1], face_nodes[f, 2], face_nodes[f, 3]
    ax, ay, az = x[n2, 0] - x[n0, 0], x[n2, 1] - x[n0, 1], x[n2, 2] - x[n0, 2]
    bx, by, bz = x[n3, 0] - x[n1, 0], x[n3, 1] - x[n1, 1], x[n3, 2] - x[n1, 2]
    cx, cy, cz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    return math.sqrt(0.5 * math.sqrt(cx * cx + cy * cy + cz * cz))


@njit(cache=True, inline="always")
def face_normal_z(x, face_nodes, f):
    """z component of the (area-weighted) normal of face f from its diagonals, mm^2."""
    n0, n1, n2, n3 = face_nodes[f, 0], face_nodes[f, 1], face_nodes[f, 2], face_nodes[f, 3]
    return ((x[n2, 0] - x[n0, 0]) * (x[n3, 1] - x[n1, 1])
            - (x[n2, 1] - x[n0, 1]) * (x[n3, 0] - x[n1, 0]))


@njit(cache=True, inline="always")
def point_over_triangle(p0, p1, p2, px, py, pz):
    """The edge point p against triangle (p0, p1, p2) (counter-clockwise seen from outside),
    along the instrument axis z.

    Returns the signed distance d = (p - p0) . n of p from the triangle's plane (positive
    outside), the outward unit normal n, the barycentric coordinates of p's vertical
    projection (all >= 0 when the vertical through p meets the triangle; -1 for a triangle
    that does not face up, n_z <= UPWARD) and the triangle's area (mm^2). p0, p1, p2 are
    (x, y, z) tuples.
    """
    e1x, e1y, e1z = p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]
    e2x, e2y, e2z = p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]
    nx, ny, nz = e1y * e2z - e1z * e2y, e1z * e2x - e1x * e2z, e1x * e2y - e1y * e2x
    twice_area = math.sqrt(nx * nx + ny * ny + nz * nz)
    if nz <= UPWARD * twice_area:
        return math.inf, 0.0, 0.0, 0.0, -1.0, -1.0, -1.0, 0.5 * twice_area
    qx, qy, qz = px - p0[0], py - p0[1], pz - p0[2]
    # nz is the plan-view determinant e1 x e2 . z (> 0 for a face seen counter-clockwise from above)
    l1 = (qx * e2y - qy * e2x) / nz
    l2 = (e1x * qy - e1y * qx) / nz
    d = (qx * nx + qy * ny + qz * nz) / twice_area
    return d, nx / twice_area, ny / twice_area, nz / twice_area, 1.0 - l1 - l2, l1, l2, 0.5 * twice_area


@njit(cache=True, inline="always")
def point_over_face(x, face_nodes, f, px, py, pz, inside_only):
    """The point p against face f split into four triangles about its centroid (corners t,
    t + 1 and the centroid), each tested by :func:`point_over_triangle`.

    Returns (t, d, n_x, n_y, n_z, l0, l1, l2, area): the first triangle whose vertical
    projection contains p's (with ``inside_only``, also with p below it, d < 0), or t = -1
    for none; its signed distance, unit normal and barycentric coordinates; and the face's
    area (mm^2).
    """
    n0, n1, n2, n3 = face_nodes[f, 0], face_nodes[f, 1], face_nodes[f, 2], face_nodes[f, 3]
    c = (0.25 * (x[n0, 0] + x[n1, 0] + x[n2, 0] + x[n3, 0]),
         0.25 * (x[n0, 1] + x[n1, 1] + x[n2, 1] + x[n3, 1]),
         0.25 * (x[n0, 2] + x[n1, 2] + x[n2, 2] + x[n3, 2]))
    corners = ((x[n0, 0], x[n0, 1], x[n0, 2]), (x[n1, 0], x[n1, 1], x[n1, 2]),
               (x[n2, 0], x[n2, 1], x[n2, 2]), (x[n3, 0], x[n3, 1], x[n3, 2]))
    area = 0.0
    hit = -1
    hit_d, hit_n, hit_l = 0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    for t in range(4):
        d, nx, ny, nz, l0, l1, l2, part = point_over_triangle(corners[t], corners[(t + 1) % 4], c,
                                                              px, py, pz)
        area += part
        if l0 >= 0.0 and l1 >= 0.0 and l2 >= 0.0 and (d < 0.0 or not inside_only) and hit < 0:
            hit, hit_d, hit_n, hit_l = t, d, (nx, ny, nz), (l0, l1, l2)
    return hit, hit_d, hit_n[0], hit_n[1], hit_n[2], hit_l[0], hit_l[1], hit_l[2], area
