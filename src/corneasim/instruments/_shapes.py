"""Signed distance and outward normal of the rigid instrument shapes, for Numba kernels.

Every shape lives in the *instrument-local frame*: the instrument axis is the z-axis,
the tip (the lowest point) lies at z = 0 and the instrument points down (-z); its body
occupies z >= 0. A shape is a flat float64 array (its first entry the kind):

=======  ==========  ==============================================================
kind     name        packed array
=======  ==========  ==============================================================
0        PROFILE     [0, n, closed, r_1..r_n, z_1..z_n]: a body of revolution whose
                     meridian section is the polygon (r_k, z_k), counter-clockwise in
                     (r, z). ``closed = 0`` when the closing edge n -> 1 lies on the axis
                     (a solid needle): that edge bounds the section but is no surface.
1        ROUNDED     [1, R, L]: cylinder of radius R with a hemispherical tip, centre
                     (0, 0, R), cut flat at z = L.
2        BEVELLED    [2, R, L, gamma]: cylinder of radius R cut by the bevel plane
                     z = (x + R) cot(gamma) through the tip point (-R, 0, 0), gamma the
                     angle between the bevel face and the axis; cut flat at z = L.
=======  ==========  ==============================================================

The signed distance d is negative inside the instrument; the normal is the gradient
of d (unit, outward). PROFILE is exact everywhere (distance to the nearest edge of the
meridian polygon, sign from a crossing-number test). ROUNDED and BEVELLED combine
their surfaces with ``max`` (constructive solid geometry): exact inside and away from
the edges where the surfaces meet; outside near those edges it underestimates the
distance, which contact never uses (only d < 0 matters).
"""

from __future__ import annotations

import math

from numba import njit

PROFILE, ROUNDED, BEVELLED = 0, 1, 2

TINY = 1.0e-300


@njit(cache=True)
def _profile_rz(shape, r, z):
    """Signed distance and outward normal (d, n_r, n_z) of a PROFILE meridian polygon."""
    n = int(shape[1])
    closed = shape[2] > 0.5
    rs = shape[3 : 3 + n]
    zs = shape[3 + n : 3 + 2 * n]
    best = math.inf
    best_r, best_z = 0.0, 0.0
    edge_nr, edge_nz = 0.0, 1.0
    inside = False
    for k in range(n):
        a_r, a_z = rs[k], zs[k]
        b_r, b_z = rs[(k + 1) % n], zs[(k + 1) % n]
        if (a_z > z) != (b_z > z):
            crossing = a_r + (z - a_z) * (b_r - a_r) / (b_z - a_z)
            if r < crossing:
                inside = not inside
        if k == n - 1 and not closed:
            continue
        e_r, e_z = b_r - a_r, b_z - a_z
        length2 = e_r * e_r + e_z * e_z
        s = ((r - a_r) * e_r + (z - a_z) * e_z) / length2
        s = min(max(s, 0.0), 1.0)
        c_r, c_z = a_r + s * e_r, a_z + s * e_z
        dist2 = (r - c_r) ** 2 + (z - c_z) ** 2
        if dist2 < best:
            best = dist2
            best_r, best_z = c_r, c_z
            length = math.sqrt(length2)
            edge_nr, edge_nz = e_z / length, -e_r / length
    dist = math.sqrt(best)
    sign = -1.0 if inside else 1.0
    if dist < 1.0e-12:
        return sign * dist, edge_nr, edge_nz
    return sign * dist, sign * (r - best_r) / dist, sign * (z - best_z) / dist


@njit(cache=True)
def _rounded_rz(shape, r, z):
    """Signed distance and normal of a hemispherical-tip cylinder, in (r, z)."""
    radius, length = shape[1], shape[2]
    if z >= radius:
        d, n_r, n_z = r - radius, 1.0, 0.0
    else:
        q_z = z - radius
        rho = math.sqrt(r * r + q_z * q_z)
        if rho < TINY:
            d, n_r, n_z = -radius, 0.0, -1.0
        else:
            d, n_r, n_z = rho - radius, r / rho, q_z / rho
    top = z - length
    if top > d:
        return top, 0.0, 1.0
    return d, n_r, n_z


@njit(cache=True)
def signed_distance_rz(shape, r, z):
    """Signed distance and outward normal of an axisymmetric shape in the meridian plane.

    Parameters
    ----------
    shape : ndarray, float64
        Packed shape of kind PROFILE or ROUNDED (see the module table).
    r, z : float
        Radius (>= 0) and axial coordinate in the instrument-local frame, mm.

    Returns
    -------
    (float, float, float)
        d in mm (negative inside), and the unit outward normal (n_r, n_z) = grad d.
    """
    if int(shape[0]) == PROFILE:
        return _profile_rz(shape, r, z)
    return _rounded_rz(shape, r, z)


@njit(cache=True)
def _bevelled(shape, x, y, z):
    """Signed distance and normal of a bevelled cylinder (max of three surfaces)."""
    radius, length, gamma = shape[1], shape[2], shape[3]
    r = math.sqrt(x * x + y * y)
    if r < TINY:
        d, n_x, n_y, n_z = -radius, 1.0, 0.0, 0.0
    else:
        d, n_x, n_y, n_z = r - radius, x / r, y / r, 0.0
    cos_g, sin_g = math.cos(gamma), math.sin(gamma)
    bevel = (x + radius) * cos_g - z * sin_g
    if bevel > d:
        d, n_x, n_y, n_z = bevel, cos_g, 0.0, -sin_g
    top = z - length
    if top > d:
        d, n_x, n_y, n_z = top, 0.0, 0.0, 1.0
    return d, n_x, n_y, n_z


@njit(cache=True)
def signed_distance(shape, x, y, z):
    """Signed distance and outward normal of a shape in the instrument-local 3D frame.

    Bodies of revolution evaluate :func:`signed_distance_rz` at r = sqrt(x^2 + y^2)
    (the nearest surface point of a body of revolution lies in the point's meridian
    half-plane) and turn (n_r, n_z) into (n_r x / r, n_r y / r, n_z).

    Parameters
    ----------
    shape : ndarray, float64
        Packed shape (see the module table).
    x, y, z : float
        Point in the instrument-local frame, mm.

    Returns
    -------
    (float, float, float, float)
        d in mm (negative inside) and the unit outward normal (n_x, n_y, n_z).
    """
    if int(shape[0]) == BEVELLED:
        return _bevelled(shape, x, y, z)
    r = math.sqrt(x * x + y * y)
    d, n_r, n_z = signed_distance_rz(shape, r, z)
    if r < TINY:
        return d, n_r, 0.0, n_z
    return d, n_r * x / r, n_r * y / r, n_z
