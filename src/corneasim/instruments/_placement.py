"""Placing an instrument on the tissue: lower it along its axis until the nearest node is at a gap.

The tip of a needle sits above the corneal apex, but a trephine's cutting edge meets the
cornea at its cutting radius, about 1 mm below the apex. Both cases are one rule: with the
instrument axis on the optical axis pointing down, find the tip height H at which the
smallest signed distance from the instrument to the tissue's surface nodes equals the
requested gap,

.. math::

    \\min_i d\\big(x_i - H e_z\\big) = g ,

solved by bisection (the clearance grows monotonically as the instrument rises clear of the
tissue). A trephine's edge must also clear the surface *between* the nodes
(:func:`edge_surface_height`).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.mesh import face_table, point_over_face
from corneasim.instruments._shapes import signed_distance, signed_distance_rz


@njit(cache=True)
def clearance(shape, points, height, axisymmetric):
    """Smallest signed distance (mm) from the instrument with its tip at ``height`` on the axis to ``points``.

    ``points`` (n, 2) as (r, z) when ``axisymmetric`` else (n, 3) as (x, y, z), mm. A node of an
    axisymmetric model a round-off or a penalty's give past the axis (r < 0) is its mirror image |r|.
    """
    smallest = np.inf
    for i in range(points.shape[0]):
        if axisymmetric:
            d = signed_distance_rz(shape, abs(points[i, 0]), points[i, 1] - height)[0]
        else:
            d = signed_distance(shape, points[i, 0], points[i, 1], points[i, 2] - height)[0]
        if d < smallest:
            smallest = d
    return smallest


def tip_height_for_gap(shape: np.ndarray, points: np.ndarray, gap: float, axisymmetric: bool) -> float:
    """Tip height (mm) on the axis at which the instrument clears ``points`` by ``gap`` (mm).

    Parameters
    ----------
    shape : ndarray
        Packed instrument shape (``Needle.pack()``, ``Trephine.pack()``).
    points : ndarray (n, 2 or 3)
        Current positions of the tissue's surface nodes, mm.
    gap : float
        Required clearance, mm (>= 0).
    axisymmetric : bool
        Points are (r, z).
    """
    points = np.ascontiguousarray(points, dtype=np.float64)
    top = float(points[:, -1].max())
    span = float(np.ptp(points[:, -1])) + 1.0
    low, high = top - span, top + span + gap
    while clearance(shape, points, high, axisymmetric) < gap:
        high += span
    for _ in range(60):
        middle = 0.5 * (low + high)
        if clearance(shape, points, middle, axisymmetric) < gap:
            low = middle
        else:
            high = middle
    return high


@njit(cache=True)
def _highest_under_circle(x, face_nodes, radius, n_points):
    """Largest height (mm) of the faces ``face_nodes`` seen from above at the points of the
    circle of ``radius`` about the z axis (-inf where none lies under a point). Each face is
    split into four triangles about its centroid (``surface.point_over_face``)."""
    top = -np.inf
    for j in range(n_points):
        angle = 2.0 * np.pi * j / n_points
        px, py = radius * np.cos(angle), radius * np.sin(angle)
        for f in range(face_nodes.shape[0]):
            t, d, _, _, nz, _, _, _, _ = point_over_face(x, face_nodes, f, px, py, 0.0, False)
            if t >= 0:
                top = max(top, -d / nz)  # the plane's height above (px, py, 0)
    return top


def edge_surface_height(points: np.ndarray, cells: np.ndarray, surface_nodes: np.ndarray, radius: float,
                        spacing: float) -> float:
    """Highest point (z, mm) of a 3D mesh's surface under a circular edge about the z axis.

    :func:`tip_height_for_gap` keeps the *nodes* clear of the instrument; a trephine's edge,
    sharper than the elements, can then sit between two node rings below the surface they
    span (by 0.2 mm on the coarse trephine mesh, where the steep bevel, not the edge, met the
    first node). The surface is made of the boundary faces of ``cells`` whose four nodes are in
    ``surface_nodes``, seen from above (split into triangles about their centroids); the
    circle is sampled every ``spacing`` mm.

    Parameters
    ----------
    points : ndarray (n_nodes, 3) float64
        Current positions, mm.
    cells : ndarray (n_elements, 8) int64
        Hexahedra (VTK order).
    surface_nodes : ndarray int64
        The surface's nodes (e.g. the node set ``anterior_surface``).
    radius, spacing : float
        Edge radius and sampling distance, mm.

    Returns
    -------
    float
        The height, mm; -inf when the circle misses the surface.
    """
    face_nodes, _, neighbour = face_table(points, cells)
    on_surface = np.zeros(points.shape[0], bool)
    on_surface[surface_nodes] = True
    r = np.hypot(points[:, 0], points[:, 1])
    near = np.abs(r - radius) <= 1.0  # mm: the faces that can lie under the circle
    faces = face_nodes[(neighbour < 0) & on_surface[face_nodes].all(axis=1) & near[face_nodes].any(axis=1)]
    n_points = max(8, int(np.ceil(2.0 * np.pi * radius / spacing)))
    return float(_highest_under_circle(np.ascontiguousarray(points, dtype=np.float64), faces, radius, n_points))
