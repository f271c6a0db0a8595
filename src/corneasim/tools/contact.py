"""Penalty contact between a rigid instrument and the nodes of the tissue, with friction.

Node-to-rigid-surface contact: every active node of the contact set that lies inside
the instrument (signed distance d < 0) is pushed out along the instrument's outward
normal n by a penalty spring and a normal dashpot, and rubbed by friction against the
instrument's surface velocity (:mod:`corneasim.tools.friction`):

.. math::

    f_n = \\max\\left(k\\,p - c\\,(v_{rel}\\cdot n),\\ 0\\right),\\quad p = -d,\\quad
    k = \\alpha\\,\\frac{m}{\\Delta t^2},\\quad c = 2\\zeta\\sqrt{k m},

    f_t = -\\mu_{eff}\\, f_n \\min\\left(\\frac{s}{v_{eff}}, 1\\right)\\frac{v_t}{s},\\quad
    v_{eff} = \\max\\left(v_{reg}, \\frac{\\mu_{eff} f_n \\Delta t}{m}\\right),

with m the node's (scaled) lumped mass, v_rel = v - v_surface, v_t its tangential part
and s = |v_t|. The mass-based penalty k = alpha m / dt^2 adds alpha to the node's
(omega dt)^2, so central differences stay stable for alpha <= 4 (1 - s_f^2) with s_f
the time-step safety factor (alpha = 0.5: s_f <= 0.935); v_eff keeps the friction
dashpot mu f_n / v_eff explicit-stable (its c dt / m <= 1). See ``docs/contact.md``.

Nodes leave the contact when ``node_active`` is 0 (all their elements deleted,
:func:`active_nodes`); nodes inside the tissue join as soon as the instrument reaches
them, so a contact set of all nodes also handles surfaces exposed by element deletion.

Axisymmetric models ((r, z) nodes, dim 2): node forces are full-ring forces, like the
element kernels' 2 pi r weighting, so the force on the instrument is minus the sum of the
nodes' axial forces (the radial ring forces cancel); the instrument's rotation has no
in-plane velocity and gives neither friction nor torque.
"""

from __future__ import annotations

import math

from numba import njit

from corneasim.tools.friction import KARNOPP, effective_coefficient
from corneasim.tools.motion import surface_velocity, to_global_direction, to_local
from corneasim.tools.shapes import signed_distance, signed_distance_rz

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
power dissipated by friction (mJ/s)."""


@njit(cache=True)
def _node_state(x, v, node, shape, pose):
    """Signed distance, global normal, relative velocity and lever arm of one node.

    Returns (d, n_x, n_y, n_z, w_x, w_y, w_z, arm_x, arm_y); in 2D the (r, z) components are
    returned as the x and z components, with y and the arm zero.
    """
    if x.shape[1] == 2:
        r = x[node, 0]
        d, n_r, n_z = signed_distance_rz(shape, abs(r), x[node, 1] - pose[2])
        return d, n_r, 0.0, n_z, v[node, 0], 0.0, v[node, 1] - pose[6], 0.0, 0.0
    px, py, pz = x[node, 0], x[node, 1], x[node, 2]
    lx, ly, lz = to_local(pose, px, py, pz)
    d, m_x, m_y, m_z = signed_distance(shape, lx, ly, lz)
    n_x, n_y, n_z = to_global_direction(pose, m_x, m_y, m_z)
    s_x, s_y, s_z = surface_velocity(pose, px, py, pz)
    w_x, w_y, w_z = v[node, 0] - s_x, v[node, 1] - s_y, v[node, 2] - s_z
    return d, n_x, n_y, n_z, w_x, w_y, w_z, px - pose[0], py - pose[1]


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
    f_ext,
    out,
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
        Packed instrument shape (:mod:`corneasim.tools.shapes`).
    pose : ndarray, shape (8,), float64
        Instrument pose (:func:`corneasim.tools.motion.pose_at`).
    penalty_fraction : float
        alpha in k = alpha m / dt^2, dimensionless.
    damping_ratio : float
        zeta, fraction of the critical damping of the node's penalty spring, dimensionless.
    dt : float
        Time step, s.
    friction : ndarray, float64
        Packed friction law (:class:`corneasim.tools.friction.Friction`).
    f_ext : ndarray, shape (n_nodes, dim), float64
        External nodal forces, N; the contact forces are added.
    out : ndarray, shape (9,), float64
        Overwritten with the outputs named in ``OUTPUT_NAMES``.
    """
    dim = x.shape[1]
    for k in range(out.shape[0]):
        out[k] = 0.0
    inverse_dt2 = 1.0 / (dt * dt)
    normal_total = 0.0
    if int(friction[0]) == KARNOPP:
        for i in range(nodes.shape[0]):
            node = nodes[i]
            if not node_active[node]:
                continue
            d, n_x, n_y, n_z, w_x, w_y, w_z, arm_x, arm_y = _node_state(x, v, node, shape, pose)
            if d < 0.0:
                m = node_mass[node]
                k = penalty_fraction * m * inverse_dt2
                w_n = w_x * n_x + w_y * n_y + w_z * n_z
                normal_total += max(-k * d - 2.0 * damping_ratio * math.sqrt(k * m) * w_n, 0.0)
    for i in range(nodes.shape[0]):
        node = nodes[i]
        if not node_active[node]:
            continue
        d, n_x, n_y, n_z, w_x, w_y, w_z, arm_x, arm_y = _node_state(x, v, node, shape, pose)
        if d >= 0.0:
            continue
        m = node_mass[node]
        k = penalty_fraction * m * inverse_dt2
        w_n = w_x * n_x + w_y * n_y + w_z * n_z
        f_n = max(-k * d - 2.0 * damping_ratio * math.sqrt(k * m) * w_n, 0.0)
        t_x, t_y, t_z = w_x - w_n * n_x, w_y - w_n * n_y, w_z - w_n * n_z
        slip = math.sqrt(t_x * t_x + t_y * t_y + t_z * t_z)
        f_x, f_y, f_z = f_n * n_x, f_n * n_y, f_n * n_z
        mu = effective_coefficient(friction, slip, normal_total)
        if mu > 0.0 and slip > 0.0 and f_n > 0.0:
            v_eff = max(friction[2], mu * f_n * dt / m)
            scale = mu * f_n * min(slip / v_eff, 1.0) / slip
            f_x -= scale * t_x
            f_y -= scale * t_y
            f_z -= scale * t_z
            out[FRICTION_POWER] += scale * slip * slip
        f_ext[node, 0] += f_x
        if dim == 2:
            f_ext[node, 1] += f_z
        else:
            f_ext[node, 1] += f_y
            f_ext[node, 2] += f_z
            out[FORCE_X] -= f_x
            out[FORCE_Y] -= f_y
            out[TORQUE_Z] -= arm_x * f_y - arm_y * f_x
        out[FORCE_Z] -= f_z
        out[CONTACT_NODES] += 1.0
        out[CONTACT_AREA] += node_area[node]
        out[MAX_PENETRATION] = max(out[MAX_PENETRATION], -d)
        out[NORMAL_FORCE] += f_n


@njit(cache=True)
def active_nodes(cells, alive, node_active):
    """Mark the nodes that belong to at least one live element.

    Parameters
    ----------
    cells : ndarray, shape (n_elements, nodes_per_cell), int64
    alive : ndarray, shape (n_elements,), uint8 or bool
    node_active : ndarray, shape (n_nodes,), uint8
        Overwritten: 1 for nodes of live elements, 0 otherwise.
    """
    node_active[:] = 0
    for e in range(cells.shape[0]):
        if alive[e]:
            for a in range(cells.shape[1]):
                node_active[cells[e, a]] = 1
