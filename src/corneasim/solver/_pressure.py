"""Follower pressure: nodal forces of a uniform pressure on faces in the current configuration.

A pressure p (MPa, positive pushing into the body) on a face Γ gives the nodal forces

.. math::

    f_a = -p \\int_\\Gamma N_a\\, n\\, d\\Gamma

with the outward normal n of the *current* face (a follower load; its load stiffness is
not needed by an explicit method). Faces of dead elements carry no pressure.

* Axisymmetric (r, z) line segment a -> b of a counter-clockwise quad, full ring:
  n dΓ = 2π r (dz, -dr)/L ds, so with linear N and r
  f_a = -2π p (Δz, -Δr)(2 r_a + r_b)/6 and f_b = -2π p (Δz, -Δr)(r_a + 2 r_b)/6.
* Bilinear quadrilateral face of a hexahedron (outward by the right-hand rule of its
  node order): n dΓ = (x_ξ × x_η) dξ dη, integrated exactly by the 2 × 2 Gauss rule
  (the integrand is at most cubic in each of ξ, η).

References: Bonet & Wood, *Nonlinear Continuum Mechanics for FE Analysis*, 2nd ed. 2008,
sec. 8.4 (follower pressure), ISBN 978-0-521-83870-2.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from corneasim.tools.amplitudes import evaluate

GAUSS = 0.5773502691896257
"""1/sqrt(3): the 2-point Gauss abscissa."""


@njit(cache=True, fastmath=True, error_model="numpy")
def eval_pressure_forces(points, u, face_nodes, face_element, value, amplitude, amplitude_table,
                         alive, t, f_ext):
    """Add follower-pressure nodal forces at time t to ``f_ext``.

    Parameters
    ----------
    points : ndarray (n_nodes, dim) float64
        Reference coordinates, mm.
    u : ndarray (n_nodes, dim) float64
        Displacement, mm.
    face_nodes : ndarray (n_faces, 2 | 4) int64
        Nodes of each face (2: axisymmetric segment, 4: hexahedron face).
    face_element : ndarray (n_faces,) int64
        Element owning each face (no force when it is dead).
    value : ndarray (n_faces,) float64
        Pressure magnitude, MPa.
    amplitude : ndarray (n_faces,) int64
        Row of ``amplitude_table`` scaling each face's pressure.
    amplitude_table : ndarray (n_amplitudes, width) float64
        Packed amplitudes.
    alive : ndarray (n_elements,) uint8
    t : float
        Time, s.
    f_ext : ndarray (n_nodes, dim) float64
        In/out: external forces, N (full ring when axisymmetric).
    """
    n_faces = face_nodes.shape[0]
    if n_faces == 0:
        return
    factor = np.empty(amplitude_table.shape[0])
    for row in range(amplitude_table.shape[0]):
        factor[row] = evaluate(amplitude_table[row], t)[0]
    if face_nodes.shape[1] == 2:
        for k in range(n_faces):
            if alive[face_element[k]] == 0:
                continue
            p = value[k] * factor[amplitude[k]]
            a = face_nodes[k, 0]
            b = face_nodes[k, 1]
            ra = points[a, 0] + u[a, 0]
            za = points[a, 1] + u[a, 1]
            rb = points[b, 0] + u[b, 0]
            zb = points[b, 1] + u[b, 1]
            nr = zb - za
            nz = -(rb - ra)
            scale = -2.0 * math.pi * p / 6.0
            wa = scale * (2.0 * ra + rb)
            wb = scale * (ra + 2.0 * rb)
            f_ext[a, 0] += wa * nr
            f_ext[a, 1] += wa * nz
            f_ext[b, 0] += wb * nr
            f_ext[b, 1] += wb * nz
        return
    x = np.empty((4, 3))
    force = np.empty((4, 3))
    for k in range(n_faces):
        if alive[face_element[k]] == 0:
            continue
        p = value[k] * factor[amplitude[k]]
        for a in range(4):
            node = face_nodes[k, a]
            for c in range(3):
                x[a, c] = points[node, c] + u[node, c]
                force[a, c] = 0.0
        for gauss in range(4):
            xi = -GAUSS if gauss % 2 == 0 else GAUSS
            eta = -GAUSS if gauss < 2 else GAUSS
            # tangents x_xi, x_eta of the bilinear map, nodes at (-1,-1), (1,-1), (1,1), (-1,1)
            t1x = 0.25 * ((x[1, 0] - x[0, 0]) * (1.0 - eta) + (x[2, 0] - x[3, 0]) * (1.0 + eta))
            t1y = 0.25 * ((x[1, 1] - x[0, 1]) * (1.0 - eta) + (x[2, 1] - x[3, 1]) * (1.0 + eta))
            t1z = 0.25 * ((x[1, 2] - x[0, 2]) * (1.0 - eta) + (x[2, 2] - x[3, 2]) * (1.0 + eta))
            t2x = 0.25 * ((x[3, 0] - x[0, 0]) * (1.0 - xi) + (x[2, 0] - x[1, 0]) * (1.0 + xi))
            t2y = 0.25 * ((x[3, 1] - x[0, 1]) * (1.0 - xi) + (x[2, 1] - x[1, 1]) * (1.0 + xi))
            t2z = 0.25 * ((x[3, 2] - x[0, 2]) * (1.0 - xi) + (x[2, 2] - x[1, 2]) * (1.0 + xi))
            nx = t1y * t2z - t1z * t2y
            ny = t1z * t2x - t1x * t2z
            nz = t1x * t2y - t1y * t2x
            for a in range(4):
                sa = -1.0 if (a == 0 or a == 3) else 1.0
                ta = -1.0 if a < 2 else 1.0
                w = -p * 0.25 * (1.0 + sa * xi) * (1.0 + ta * eta)
                force[a, 0] += w * nx
                force[a, 1] += w * ny
                force[a, 2] += w * nz
        for a in range(4):
            node = face_nodes[k, a]
            for c in range(3):
                f_ext[node, c] += force[a, c]
