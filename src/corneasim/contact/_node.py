"""Penalty contact between a rigid instrument and the nodes of the tissue, with friction.

Node-to-rigid-surface contact: every active node of the contact set that lies inside
the instrument (signed distance d < 0) is pushed out along the instrument's outward
normal n by a penalty spring and a normal dashpot, and held or rubbed by friction
(:mod:`corneasim.contact._friction`) through a tangential penalty spring with a Coulomb
cap (elastic-slip regularisation, a return mapping):

.. math::

    f_n = \\max\\left(k\\,p - c\\,(w\\cdot n),\\ 0\\right),\\quad p = -d,\\quad
    k = \\alpha\\,\\frac{m}{\\Delta t^2},\\quad c = 2\\zeta\\sqrt{k m},

    f_t^{trial} = -k_t\\,(I - n n^T)(X - X_0),\\qquad
    f_t = f_t^{trial}\\,\\min\\left(1, \\frac{\\mu_{eff} f_n}{|f_t^{trial}|}\\right),

with m the node's (scaled) lumped mass, w = v - v_surface the velocity relative to the
instrument, X the node in the instrument frame and X_0 its stick point (the anchor: set
at first touch, moved on sliding so that f_t = -k_t (X - X_0)). The mass-based penalty
k = alpha m / dt^2 adds alpha to the node's (omega dt)^2, so central differences stay
stable for alpha <= 4 (1 - s_f^2) with s_f the time-step safety factor (alpha = 0.5:
s_f <= 0.935); the tangential spring k_t = beta k (beta <= 1) obeys the same limit.
See ``docs/contact.md``.

Nodes leave the contact when ``node_active`` is 0 (all their elements deleted; the
solver keeps that mask); nodes inside the tissue join as soon as the instrument reaches
them, so a contact set of all nodes also handles surfaces exposed by element deletion.

Axisymmetric models ((r, z) nodes, dim 2): node forces are full-ring forces, like the
element kernels' 2 pi r weighting, so the force on the instrument is minus the sum of the
nodes' axial forces (the radial ring forces cancel); the instrument's rotation has no
in-plane velocity and gives neither friction nor torque.
"""

from __future__ import annotations

import math

from numba import njit

from corneasim.contact._friction import KARNOPP, effective_coefficient
from corneasim.instruments import PROFILE, signed_distance, signed_distance_rz
from corneasim.instruments import POSE_ANGLE, POSE_OMEGA, POSE_VX, POSE_VY, POSE_VZ, POSE_X, POSE_Y, POSE_Z

FORCE_X, FORCE_Y, FORCE_Z, TORQUE_Z = 0, 1, 2, 3
CONTACT_NODES, CONTACT_AREA, MAX_PENETRATION, NORMAL_FORCE, FRICTION_POWER = 4, 5, 6, 7, 8
N_OUTPUTS = 9
OUTPUT_NAMES = (
    "force_x",
    "force_y",
    "force_z",
    "torque_z",
    "contact_nodes",
    "contact_area",
    "max_penetration",
    "normal_force",
    "friction_power",
)
"""Entries of the ``out`` array of :func:`eval_contact`: the force (N) and the torque about the
instrument axis (N mm) exerted by the tissue on the instrument, the number of contacting nodes,
their area (mm^2), the largest penetration (mm), the summed normal force magnitudes (N) and the
power dissipated by sliding friction, -sum f_t . w over the sliding nodes (mJ/s)."""


@njit(cache=True)
def shape_bounds(shape):
    """Bounding shell of a shape in the instrument frame: (r_min, r_max, z_min, z_max) in mm.

    Points outside it are outside the instrument, which lets the kernel skip the distance.
    """
    kind = int(shape[0])
    if kind == PROFILE:
        n = int(shape[1])
        r_min = r_max = shape[3]
        z_min = z_max = shape[3 + n]
        for i in range(1, n):  # a loop, not .min() / .max(): numpy's reductions cost 0.5 s of compilation
            r_min, r_max = min(r_min, shape[3 + i]), max(r_max, shape[3 + i])
            z_min, z_max = min(z_min, shape[3 + n + i]), max(z_max, shape[3 + n + i])
        return r_min, r_max, z_min, z_max
    return 0.0, shape[1], 0.0, shape[2]


@njit(cache=True, inline="always")
def _outside_shell(x, node, pose, bounds):
    """True when the node lies outside the bounding shell (then it cannot touch)."""
    r_min, r_max, z_min, z_max = bounds
    dim = x.shape[1]
    z = x[node, dim - 1] - pose[POSE_Z]
    if z < z_min or z > z_max:
        return True
    if dim == 2:
        r2 = x[node, 0] * x[node, 0]
    else:
        dx, dy = x[node, 0] - pose[POSE_X], x[node, 1] - pose[POSE_Y]
        r2 = dx * dx + dy * dy
    return r2 > r_max * r_max or r2 < r_min * r_min


@njit(cache=True)
def current_positions(points, u, nodes, x):
    """x = X + u for the nodes ``nodes`` only (mm; arrays (n_nodes, dim), ``nodes`` int64).

    Between two candidate lists the node contact reads only the candidates' positions; the
    whole array (np.add) costs 9 us per step on the needle's 17,000-node mesh.
    """
    for i in range(nodes.shape[0]):
        node = nodes[i]
        for j in range(x.shape[1]):
            x[node, j] = points[node, j] + u[node, j]


@njit(cache=True)
def contact_candidates(x, nodes, shape, pose, margin, is_candidate, touching, candidates):
    """The nodes within ``margin`` (mm) of the instrument's bounding shell, in set order.

    Only these can touch before the shell or a node has moved by ``margin``; between two
    calls :func:`eval_contact` then visits them instead of the whole contact set. The shell
    is that of :func:`shape_bounds`, grown by ``margin`` in r and z, about the instrument
    axis at ``pose``.

    Parameters
    ----------
    x : ndarray (n_nodes, dim) float64
        Current positions, mm.
    nodes : ndarray (n_contact,) int64
        The contact node set.
    shape, pose : ndarray float64
        Packed shape and the current pose.
    margin : float
        Growth of the shell, mm.
    is_candidate : ndarray (n_nodes,) uint8
        In: 1 for the previous candidates (all 0 before the first call); out: the new ones.
    touching : ndarray (n_nodes,) uint8
        In/out: cleared for the nodes outside the grown shell (they cannot be in contact).
    candidates : ndarray (>= n_contact,) int64
        Out: the first ``count`` entries are the candidates.

    Returns
    -------
    (int, int)
        ``count``, and how many nodes inside the shell itself were not previous candidates
        (0 unless nodes or the instrument moved more than ``margin`` since the last call, or
        this is the first call).
    """
    r_min, r_max, z_min, z_max = shape_bounds(shape)
    grown = (max(r_min - margin, 0.0), r_max + margin, z_min - margin, z_max + margin)
    count = 0
    missed = 0
    bare = (r_min, r_max, z_min, z_max)
    for i in range(nodes.shape[0]):
        node = nodes[i]
        if _outside_shell(x, node, pose, grown):
            is_candidate[node] = 0
            touching[node] = 0
            continue
        if not is_candidate[node] and not _outside_shell(x, node, pose, bare):
            missed += 1
        is_candidate[node] = 1
        candidates[count] = node
        count += 1
    return count, missed


@njit(cache=True)
def _node_state(x, v, node, shape, pose, cos_t, sin_t):
    """One node in the instrument frame: position, signed distance, normal, relative velocity.

    Returns (X, Y, Z, d, n_x, n_y, n_z, w_x, w_y, w_z), all instrument-local; in 2D the
    (r, z) components are the x and z components and y is zero.
    """
    if x.shape[1] == 2:
        r, z = abs(x[node, 0]), x[node, 1] - pose[POSE_Z]
        d, n_r, n_z = signed_distance_rz(shape, r, z)
        return r, 0.0, z, d, n_r, 0.0, n_z, v[node, 0], 0.0, v[node, 1] - pose[POSE_VZ]
    dx, dy = x[node, 0] - pose[POSE_X], x[node, 1] - pose[POSE_Y]
    lx, ly, lz = cos_t * dx + sin_t * dy, -sin_t * dx + cos_t * dy, x[node, 2] - pose[POSE_Z]
    d, n_x, n_y, n_z = signed_distance(shape, lx, ly, lz)
    omega = pose[POSE_OMEGA]
    g_x = v[node, 0] - (pose[POSE_VX] - omega * dy)
    g_y = v[node, 1] - (pose[POSE_VY] + omega * dx)
    w_z = v[node, 2] - pose[POSE_VZ]
    return lx, ly, lz, d, n_x, n_y, n_z, cos_t * g_x + sin_t * g_y, -sin_t * g_x + cos_t * g_y, w_z


@njit(cache=True)
def _normal_force(k, m, damping_ratio, d, w_n):
    """Penalty plus dashpot normal force, never adhesive: max(k p - 2 zeta sqrt(k m) w_n, 0)."""
    return max(-k * d - 2.0 * damping_ratio * math.sqrt(k * m) * w_n, 0.0)


@njit(cache=True)
def eval_contact(
    x,
    v,
    nodes,
    node_active,
    node_mass,
    node_area,
    shape,
    pose,
    penalty_fraction,
    damping_ratio,
    dt,
    friction,
    anchor,
    touching,
    f_ext,
    out,
    hits,
):
    """Add the contact forces of one instrument to ``f_ext`` and sum what the instrument feels.

    Parameters
    ----------
    x, v : ndarray, shape (n_nodes, dim), float64
        Current nodal positions (mm) and velocities (mm/s); dim 2 means axisymmetric (r, z).
    nodes : ndarray, shape (n_contact,), int64
        The contact node set.
    node_active : ndarray, shape (n_nodes,), uint8 or bool
        1 where a node may touch (it belongs to a live element).
    node_mass : ndarray, shape (n_nodes,), float64
        Lumped (scaled) nodal masses used by the integrator, tonne (full ring in 2D).
    node_area : ndarray, shape (n_nodes,), float64
        Tributary area per node, mm^2 (only summed into the contact area output).
    shape : ndarray, float64
        Packed instrument shape (:mod:`corneasim.instruments._shapes`).
    pose : ndarray, shape (8,), float64
        Instrument pose (:func:`corneasim.instruments._motion.pose_at`).
    penalty_fraction : float
        alpha in k = alpha m / dt^2, dimensionless.
    damping_ratio : float
        zeta, fraction of the critical damping of the node's penalty spring, dimensionless.
    dt : float
        Time step the penalty is sized for, s.
    friction : ndarray, float64
        Packed friction law (:class:`corneasim.contact._friction.Friction`).
    anchor : ndarray, shape (n_nodes, 3), float64
        In/out: stick points in the instrument frame, mm ((r, 0, z) in 2D).
    touching : ndarray, shape (n_nodes,), uint8
        In/out: 1 while a node is in contact (its anchor is valid).
    f_ext : ndarray, shape (n_nodes, dim), float64
        External nodal forces, N; the contact forces are added.
    out : ndarray, shape (9,), float64
        Overwritten with the outputs named in ``OUTPUT_NAMES``.
    hits : ndarray, shape (>= n_contact,), int64
        Scratch: the nodes that penetrate, found by one pass over the set; the forces (and,
        for the lumped law, their total normal force first) are then computed for those only.
    """
    dim = x.shape[1]
    for k in range(out.shape[0]):
        out[k] = 0.0
    bounds = shape_bounds(shape)
    cos_t, sin_t = math.cos(pose[POSE_ANGLE]), math.sin(pose[POSE_ANGLE])
    inverse_dt2 = 1.0 / (dt * dt)
    beta = friction[2]
    normal_total = 0.0
    lumped = int(friction[0]) == KARNOPP
    n_hits = 0
    for i in range(nodes.shape[0]):
        node = nodes[i]
        if not node_active[node] or _outside_shell(x, node, pose, bounds):
            touching[node] = 0
            continue
        lx, ly, lz, d, n_x, n_y, n_z, w_x, w_y, w_z = _node_state(x, v, node, shape, pose, cos_t, sin_t)
        if d >= 0.0:
            touching[node] = 0
            continue
        hits[n_hits] = node
        n_hits += 1
        if lumped:
            m = node_mass[node]
            w_n = w_x * n_x + w_y * n_y + w_z * n_z
            normal_total += _normal_force(penalty_fraction * m * inverse_dt2, m, damping_ratio, d, w_n)
    for j in range(n_hits):
        node = hits[j]
        lx, ly, lz, d, n_x, n_y, n_z, w_x, w_y, w_z = _node_state(x, v, node, shape, pose, cos_t, sin_t)
        m = node_mass[node]
        k = penalty_fraction * m * inverse_dt2
        w_n = w_x * n_x + w_y * n_y + w_z * n_z
        f_n = _normal_force(k, m, damping_ratio, d, w_n)
        t_x, t_y, t_z = w_x - w_n * n_x, w_y - w_n * n_y, w_z - w_n * n_z
        slip_speed = math.sqrt(t_x * t_x + t_y * t_y + t_z * t_z)
        if not touching[node]:
            anchor[node, 0], anchor[node, 1], anchor[node, 2] = lx, ly, lz
            touching[node] = 1
        g_x, g_y, g_z = lx - anchor[node, 0], ly - anchor[node, 1], lz - anchor[node, 2]
        g_n = g_x * n_x + g_y * n_y + g_z * n_z
        k_t = beta * k
        q_x, q_y, q_z = -k_t * (g_x - g_n * n_x), -k_t * (g_y - g_n * n_y), -k_t * (g_z - g_n * n_z)
        trial = math.sqrt(q_x * q_x + q_y * q_y + q_z * q_z)
        cap = effective_coefficient(friction, slip_speed, normal_total) * f_n
        if trial > cap:
            scale = cap / trial
            q_x, q_y, q_z = scale * q_x, scale * q_y, scale * q_z
            anchor[node, 0], anchor[node, 1], anchor[node, 2] = lx + q_x / k_t, ly + q_y / k_t, lz + q_z / k_t
            out[FRICTION_POWER] -= q_x * t_x + q_y * t_y + q_z * t_z
        f_lx, f_ly, f_lz = f_n * n_x + q_x, f_n * n_y + q_y, f_n * n_z + q_z
        if dim == 2:
            f_ext[node, 0] += f_lx
            f_ext[node, 1] += f_lz
        else:
            f_x, f_y, f_z = cos_t * f_lx - sin_t * f_ly, sin_t * f_lx + cos_t * f_ly, f_lz
            f_ext[node, 0] += f_x
            f_ext[node, 1] += f_y
            f_ext[node, 2] += f_z
            out[FORCE_X] -= f_x
            out[FORCE_Y] -= f_y
            # Torque about the axis: arm and force both in the local frame (rotation about z).
            out[TORQUE_Z] -= lx * f_ly - ly * f_lx
        out[FORCE_Z] -= f_lz
        out[CONTACT_NODES] += 1.0
        out[CONTACT_AREA] += node_area[node]
        out[MAX_PENETRATION] = max(out[MAX_PENETRATION], -d)
        out[NORMAL_FORCE] += f_n
