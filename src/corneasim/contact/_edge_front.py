"""Contact of a trephine's edge with the front of a cohesive cut: the edge rests where the tissue is not yet cut.

On a cohesive cut (:mod:`corneasim.fracture._ties`) the tissue is split along the blade's
cylinder r = R into through-thickness lines of tied node pairs. On each line the *front* is
the first pair from the anterior surface whose tie is not cut: below it the tissue is whole,
above it the two flanks are apart, the disc's along the blade's inner wall and the rim's on
its bevel. A sharp edge sits at the crack's tip, so the edge contact meets the tissue there:
the fronts of two neighbouring lines k and k + 1 (azimuths phi_k < phi_{k+1} about the
instrument axis, each at the mean position of its tied pair) bound a straight front segment,
and an edge point p_j at the angle beta_j between them is held by it at

.. math::

    t = \\frac{\\beta_j - \\varphi_k}{\\varphi_{k+1} - \\varphi_k}, \\qquad
    z_f = (1 - t)\\, z_k + t\\, z_{k+1}, \\qquad d = z_f - z_{\\text{edge}} > 0,

with the face law of :mod:`corneasim.contact._edge_law` along the axis (n = e_z): force
f = max(k d + c_d (v_f - v_t) . e_z, 0), k = alpha m / Delta t^2 min(Delta s / L, 1) (L the
segment's reference length, m the smallest mass of its four nodes), Coulomb friction mu f
against the in-plane sliding of the front, the force shared by the four nodes with the
weights (1 - t) / 2, (1 - t) / 2, t / 2, t / 2. As a face holds a point less than half its size
deep, the segment holds the point only while d < h / 2, h the fronts' spacing to the next tie
down (interpolated as z_f), no more than ``ACQUIRE_DEPTH`` h deeper than the point was in the
step before, and while the front is within half the width w of the elements beside the split
of the edge's circle, |r_f - R| < w / 2 (r_f, w interpolated): the reach of the faces it
stands for.

The faces with a node on the split surface are left out of the face contact
(``EdgeContact.hold_by_fronts``): the lip faces next to a cut tie, which the edge would
otherwise push down the wall with the cut (the disc's flank is held at R by the inner wall,
within the node contact's penetration, right under the edge's circle), and the faces ahead
of the front, which the front stands for. When a tie is cut its front moves one tie down,
below the edge, and the edge takes it up as it descends or as the tissue under it rises.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from corneasim.contact._edge_law import (
    ACQUIRE_DEPTH, EDGE_FORCE_X, EDGE_FORCE_Y, EDGE_FORCE_Z, EDGE_FRICTION_POWER, EDGE_NORMAL, EDGE_PENETRATION,
    EDGE_POINTS, EDGE_TORQUE_Z)


def front_segments(points, cells, pairs, line_start, line_pairs, center=(0.0, 0.0)):
    """The front segments between angularly neighbouring tie lines and each tie's reach.

    Parameters
    ----------
    points : ndarray (n_nodes, 3) float64
        Reference coordinates, mm.
    cells : ndarray (n_elements, 8) int64
        Hexahedra of the split mesh.
    pairs : ndarray (n_pairs, 2) int64
        The ties' (original, copy) node pairs.
    line_start, line_pairs : ndarray int64
        The ties by through-thickness line, each from the anterior surface down
        (:func:`corneasim.fracture._edge_work.tie_lines`).
    center : (float, float)
        The instrument axis (x, y), mm.

    Returns
    -------
    (segments, length, spacing, width)
        ``segments`` (n_segments, 2) int64: the lines (k, k + 1) in order of azimuth about the
        axis, and the segment from the last line back to the first when the lines go round
        the whole circle (its gap no more than 1.5 times the largest other); ``length``
        (n_segments,): the distance of the lines' top nodes, mm; ``spacing`` (n_pairs,): each
        tie's distance to the next tie down its line (the last: to the one above), mm;
        ``width`` (n_pairs,): the smallest radial extent about the axis of the elements at the
        tie's two nodes, mm.
    """
    n_lines = line_start.size - 1
    top = points[pairs[line_pairs[line_start[:-1]], 0]]  # (n_lines, 3)
    angle = np.mod(np.arctan2(top[:, 1] - center[1], top[:, 0] - center[0]), 2.0 * np.pi)
    order = np.argsort(angle, kind="stable")
    spacing = np.zeros(len(pairs))
    for line in range(n_lines):
        ties = line_pairs[line_start[line]:line_start[line + 1]]
        z = points[pairs[ties, 0], 2]
        if ties.size > 1:
            gaps = np.abs(np.diff(z))
            spacing[ties] = np.append(gaps, gaps[-1])
    radius = np.hypot(points[:, 0] - center[0], points[:, 1] - center[1])
    extent = np.ptp(radius[cells], axis=1)  # (n_elements,)
    node_width = np.full(points.shape[0], np.inf)
    np.minimum.at(node_width, cells.ravel(), np.repeat(extent, cells.shape[1]))
    width = np.minimum(node_width[pairs[:, 0]], node_width[pairs[:, 1]])
    segments = [(order[i], order[i + 1]) for i in range(n_lines - 1)]
    gaps = np.diff(angle[order])
    wrap = angle[order[0]] + 2.0 * np.pi - angle[order[-1]]
    if n_lines > 2 and wrap <= 1.5 * gaps.max():
        segments.append((order[-1], order[0]))
    segments = np.array(segments, dtype=np.int64).reshape(-1, 2)
    length = np.linalg.norm(top[segments[:, 1]] - top[segments[:, 0]], axis=1)
    spacing = np.where(spacing > 0.0, spacing, width)  # a line of one tie: as deep as wide
    return segments, length, spacing, width


@njit(cache=True, inline="always")
def _line_front(line_start, line_pairs, cut, line):
    """The line's front tie (its first from the top not cut) and its last tie; -1: all cut."""
    for k in range(line_start[line], line_start[line + 1]):
        if cut[line_pairs[k]] == 0:
            return line_pairs[k], line_pairs[k]
    return -1, line_pairs[line_start[line + 1] - 1]


@njit(cache=True)
def split_on_blade(points, u, pairs, line_start, line_pairs, cut, center, radius, shift, x):
    """Positions ``x`` (mm) of the split's nodes as the instrument meets them: on the blade's cylinder.

    A split made in the mesh lies where the mesh put it, within a fraction of an element of
    the blade's path, and moves off it as the eye deforms (by 0.01-0.08 mm on the coarse
    trephine mesh). The blade cuts where it is, so every node of a line k of ties meets the
    instrument moved radially about its axis by the line's offset

    .. math::

        \\delta_k = \\bar r_{f,k} - R, \\qquad
        \\mathbf x'_n = \\mathbf c + (r_n - \\delta_k) \\, \\mathbf e_r(\\mathbf x_n),

    with \\bar r_{f,k} the mean radius about the axis c of the line's front pair (its first
    tie not cut, whose two nodes are together) and R the edge radius: the crack's tip lies on
    the blade's cylinder, the disc's flank at its offset inside, the rim's outside, and only
    the contact sees the move (the forces act on the nodes where they are). A line cut
    through keeps its last offset. The same holds for the needle's slit
    (``InstrumentContact.shift_nodes``).

    Parameters
    ----------
    points, u : ndarray (n_nodes, 3) float64
        Reference coordinates and displacements, mm.
    pairs, line_start, line_pairs, cut : ndarray
        The ties and their lines (:meth:`corneasim.contact.EdgeContact.hold_by_fronts`).
    center : ndarray (2,) float64
        The instrument axis (x, y), mm.
    radius : float
        The edge radius R, mm.
    shift : ndarray (n_lines,) float64
        In/out: delta_k, mm.
    x : ndarray (n_nodes, 3) float64
        Out: the split nodes' rows.
    """
    cx, cy = center[0], center[1]
    for line in range(line_start.size - 1):
        front, _ = _line_front(line_start, line_pairs, cut, line)
        if front >= 0:
            a, b = pairs[front, 0], pairs[front, 1]
            shift[line] = 0.5 * (math.hypot(points[a, 0] + u[a, 0] - cx, points[a, 1] + u[a, 1] - cy)
                                 + math.hypot(points[b, 0] + u[b, 0] - cx, points[b, 1] + u[b, 1] - cy)) - radius
        d = shift[line]
        for k in range(line_start[line], line_start[line + 1]):
            for side in range(2):
                n = pairs[line_pairs[k], side]
                px = points[n, 0] + u[n, 0] - cx
                py = points[n, 1] + u[n, 1] - cy
                scale = 1.0 - d / math.hypot(px, py)
                x[n, 0] = cx + scale * px
                x[n, 1] = cy + scale * py
                x[n, 2] = points[n, 2] + u[n, 2]


@njit(cache=True)
def eval_front_contact(x, v, pairs, line_start, line_pairs, cut, segments, segment_length, tie_spacing,
                       tie_width, node_mass, center, velocity, omega, radius, z_edge, n_points, penalty_fraction,
                       damping_ratio, friction, dt, f_ext, depth_before, out):
    """Add the forces of the edge points on the cut's front segments to ``f_ext``; add what the
    instrument feels to ``out`` (module notes).

    Parameters
    ----------
    x, v : ndarray (n_nodes, 3) float64
        Current positions (mm) and velocities (mm/s).
    pairs, line_start, line_pairs : ndarray int64
        The tied pairs and their lines (:func:`front_segments`).
    cut : ndarray (n_pairs,) uint8
        The ties cut through.
    segments, segment_length, tie_spacing, tie_width : ndarray
        :func:`front_segments`: line pairs (int64), reference lengths, the ties' spacings down
        their lines and the widths of the elements at them (mm).
    node_mass : ndarray (n_nodes,) float64
        Lumped (scaled) nodal masses, tonne.
    center : ndarray (3,) float64
        A point of the instrument axis, mm (the axis is parallel to z).
    velocity : ndarray (3,) float64
        The instrument's translation velocity, mm/s.
    omega : float
        Its angular velocity about the axis, rad/s.
    radius, z_edge : float
        Edge radius and height, mm.
    n_points : int
        Edge points on the circle, point j at the angle 2 pi j / n_points.
    penalty_fraction, damping_ratio, friction : float
        alpha, zeta and the Coulomb coefficient mu, dimensionless.
    dt : float
        Time step the penalty is sized for, s.
    f_ext : ndarray (n_nodes, 3) float64
        External nodal forces, N; the front forces are added.
    depth_before : ndarray (n_points,) float64
        In/out: each point's depth below its front segment in the step before (0 for none), mm.
    out : ndarray (N_EDGE_OUTPUTS,) float64
        In/out: force (N) and torque (N mm) on the instrument, points in contact, largest
        penetration (mm), summed normal forces (N), friction power (mJ/s): added to.
    """
    step = 2.0 * math.pi / n_points
    spacing = radius * step
    inverse_dt2 = 1.0 / (dt * dt)
    vtz = velocity[2]
    for s in range(segments.shape[0]):
        lo, last_lo = _line_front(line_start, line_pairs, cut, segments[s, 0])
        hi, last_hi = _line_front(line_start, line_pairs, cut, segments[s, 1])
        end_lo = lo if lo >= 0 else last_lo
        end_hi = hi if hi >= 0 else last_hi
        a0, b0, a1, b1 = pairs[end_lo, 0], pairs[end_lo, 1], pairs[end_hi, 0], pairs[end_hi, 1]
        x0, y0 = 0.5 * (x[a0, 0] + x[b0, 0]) - center[0], 0.5 * (x[a0, 1] + x[b0, 1]) - center[1]
        x1, y1 = 0.5 * (x[a1, 0] + x[b1, 0]) - center[0], 0.5 * (x[a1, 1] + x[b1, 1]) - center[1]
        angle0 = math.atan2(y0, x0)
        gap = math.atan2(y1, x1) - angle0
        gap -= 2.0 * math.pi * math.floor((gap + math.pi) / (2.0 * math.pi))  # into [-pi, pi)
        if gap <= 0.0:
            continue
        first = int(math.ceil(angle0 / step))
        stop = int(math.ceil((angle0 + gap) / step))
        z0, z1 = 0.5 * (x[a0, 2] + x[b0, 2]), 0.5 * (x[a1, 2] + x[b1, 2])
        r0, r1 = math.sqrt(x0 * x0 + y0 * y0), math.sqrt(x1 * x1 + y1 * y1)
        m = min(node_mass[a0], node_mass[b0], node_mass[a1], node_mass[b1])
        k = penalty_fraction * m * inverse_dt2 * min(spacing / segment_length[s], 1.0)
        for q in range(first, stop):
            j = (q % n_points + n_points) % n_points
            before = depth_before[j]
            depth_before[j] = 0.0
            if lo < 0 or hi < 0:
                continue  # a line cut through: no front to rest on
            t = (q * step - angle0) / gap
            d = (1.0 - t) * z0 + t * z1 - z_edge
            r_f = (1.0 - t) * r0 + t * r1
            h = (1.0 - t) * tie_spacing[lo] + t * tie_spacing[hi]
            reach = 0.5 * ((1.0 - t) * tie_width[lo] + t * tie_width[hi])
            if d <= 0.0 or d >= 0.5 * h or d > before + ACQUIRE_DEPTH * h or abs(r_f - radius) >= reach:
                continue
            depth_before[j] = d
            w0, w1 = 0.5 * (1.0 - t), 0.5 * t
            vfx = w0 * (v[a0, 0] + v[b0, 0]) + w1 * (v[a1, 0] + v[b1, 0])
            vfy = w0 * (v[a0, 1] + v[b0, 1]) + w1 * (v[a1, 1] + v[b1, 1])
            vfz = w0 * (v[a0, 2] + v[b0, 2]) + w1 * (v[a1, 2] + v[b1, 2])
            beta = q * step
            ax, ay = radius * math.cos(beta), radius * math.sin(beta)
            force = max(k * d + 2.0 * damping_ratio * math.sqrt(k * m) * (vfz - vtz), 0.0)
            if force == 0.0:
                continue
            w_x, w_y = vfx - (velocity[0] - omega * ay), vfy - (velocity[1] + omega * ax)
            slip = math.sqrt(w_x * w_x + w_y * w_y)
            drag = friction * force / max(slip, friction * force * dt / m, 1e-300)
            t_x, t_y = -drag * w_x, -drag * w_y  # on the tissue
            for node, w in ((a0, w0), (b0, w0), (a1, w1), (b1, w1)):
                f_ext[node, 0] += w * t_x
                f_ext[node, 1] += w * t_y
                f_ext[node, 2] -= w * force
            out[EDGE_FORCE_X] -= t_x
            out[EDGE_FORCE_Y] -= t_y
            out[EDGE_FORCE_Z] += force
            out[EDGE_TORQUE_Z] += -ax * t_y + ay * t_x
            out[EDGE_POINTS] += 1.0
            out[EDGE_PENETRATION] = max(out[EDGE_PENETRATION], d)
            out[EDGE_NORMAL] += force
            out[EDGE_FRICTION_POWER] += drag * slip * slip
