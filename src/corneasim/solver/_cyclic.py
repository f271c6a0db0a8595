"""Cyclic symmetry of order 2 about the z axis: the cut plane of a half model under a rotary load.

A half model (y >= 0) of a body of revolution under a load that is itself unchanged by a
rotation R by pi about the z axis (a trephine: a full circle turning and descending the same
at every angle) has a solution with the same symmetry,

.. math::

    \\mathbf u(R\\mathbf X) = R\\,\\mathbf u(\\mathbf X), \\qquad
    R = \\operatorname{diag}(-1, -1, 1),

which maps the half plane y = 0, x > 0 of the cut onto the half plane x < 0. A node a at
(x, 0, z), x > 0, and its image b at (-x, 0, z) are two copies of one node of the full model
(a carries the elements on its y > 0 side, b those on the images of its y < 0 side), so
u_b = R u_a: u_bx = -u_ax, u_by = -u_ay, u_bz = u_az. Nodes on the axis (x = y = 0) have
u_x = u_y = 0. A mirror plane (u_y = 0) is the right condition only for loads symmetric under
the reflection y -> -y, which a turning instrument's friction is not (``docs/trephination.md``).

With lumped masses the condition is imposed exactly by treating each pair as one node
(master a, slave b): mass m = m_a + m_b, force f = f_a + R^T f_b, hence the master's
acceleration

.. math::

    \\mathbf a = \\frac{m_a \\mathbf a_a + m_b R^T \\mathbf a_b}{m_a + m_b},
    \\qquad \\mathbf a_b = R\\,\\mathbf a

(mass-weighted, so the mass-proportional damping -alpha v is carried along when the velocities
agree). The coupling forces m_a (a - a_a) on a and m_b (R a - a_b) on b do no work on
consistent displacements (du_b = R du_a), so the energy balance needs no extra term. The same
momentum-conserving average applied to velocities that disagree (an initial velocity, or after
variable mass scaling made the pair's two masses heavier by different ratios) is a perfectly
inelastic merge; the kinetic energy it removes is returned for the dissipated energy. This is
a multi-point constraint with a master node (Abaqus "*EQUATION", LS-DYNA
"*CONSTRAINED_NODAL_RIGID_BODY" for rigid pairs; here the pair shares one motion up to R).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from corneasim.errors import InputError

MATCH_TOLERANCE = 1e-3
"""Coordinates match when they agree to this fraction of the smallest spacing between the
node set's nodes (dimensionless)."""


@dataclass(frozen=True)
class CyclicSymmetry:
    """Cyclic symmetry of order 2 (rotation by pi) about an axis, on the cut plane of a half model.

    Attributes
    ----------
    node_set : str
        The nodes of the cut plane (for ``axis = "z"``: the plane y = 0 of a model in y >= 0).
    axis : str
        The rotation axis; only ``"z"`` (the optical axis) is supported.
    """

    node_set: str
    axis: str = "z"


def pair_nodes(points: np.ndarray, nodes: np.ndarray, where: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Match each node (x, 0, z), x > 0, of ``nodes`` with its image (-x, 0, z).

    Parameters
    ----------
    points : ndarray (n_nodes, 3) float64
        Reference coordinates, mm.
    nodes : ndarray (n,) int64
        The node set of the cut plane y = 0.
    where : str
        Names the condition in error messages.

    Returns
    -------
    master, slave : ndarray (n_pairs,) int64
        Node at x > 0 and its image at x < 0.
    axis_nodes : ndarray (n_axis,) int64
        Nodes on the z axis.

    Raises
    ------
    InputError
        Naming the first node (and its coordinates) that is off the plane y = 0, has no
        image, or shares an image with another node.
    """
    nodes = np.unique(np.asarray(nodes, dtype=np.int64))
    if points.shape[1] != 3:
        raise InputError(f"{where}: cyclic symmetry needs a 3D mesh (x, y, z)")
    xyz = points[nodes]
    tolerance = MATCH_TOLERANCE * _smallest_spacing(xyz)
    off_plane = np.flatnonzero(np.abs(xyz[:, 1]) > tolerance)
    if off_plane.size:
        raise InputError(f"{where}: node {int(nodes[off_plane[0]])} at {_coordinates(xyz[off_plane[0]])} "
                         f"is not on the cut plane y = 0 (tolerance {tolerance:.3g} mm)")
    on_axis = np.abs(xyz[:, 0]) <= tolerance
    positive = np.flatnonzero(xyz[:, 0] > tolerance)
    negative = np.flatnonzero(xyz[:, 0] < -tolerance)
    from scipy.spatial import cKDTree  # deferred: only cyclic models need it

    tree = cKDTree(xyz[:, [0, 2]])
    distance, image = tree.query(np.stack([-xyz[positive, 0], xyz[positive, 2]], axis=1))
    unmatched = np.flatnonzero(distance > tolerance)
    if unmatched.size:
        k = positive[unmatched[0]]
        raise InputError(f"{where}: node {int(nodes[k])} at {_coordinates(xyz[k])} has no image node at "
                         f"(-x, 0, z) in the node set (tolerance {tolerance:.3g} mm)")
    missing = np.setdiff1d(negative, image)
    if missing.size:
        k = missing[0]
        raise InputError(f"{where}: node {int(nodes[k])} at {_coordinates(xyz[k])} has no image node at "
                         f"(-x, 0, z) in the node set (tolerance {tolerance:.3g} mm)")
    if np.unique(image).size != image.size:
        values, counts = np.unique(image, return_counts=True)
        k = values[counts > 1][0]
        raise InputError(f"{where}: node {int(nodes[k])} at {_coordinates(xyz[k])} is the image of two "
                         "nodes (duplicate nodes on the cut plane?)")
    return nodes[positive], nodes[image], nodes[on_axis]


def _smallest_spacing(xyz: np.ndarray) -> float:
    """Smallest positive distance between two of the points (1 mm for fewer than two), mm."""
    if len(xyz) < 2:
        return 1.0
    from scipy.spatial import cKDTree  # deferred, as in pair_nodes

    distance, _ = cKDTree(xyz).query(xyz, k=2)
    positive = distance[:, 1][distance[:, 1] > 0.0]
    return float(positive.min()) if positive.size else 1.0


def _coordinates(point: np.ndarray) -> str:
    return "(" + ", ".join(f"{value:.6g}" for value in point) + ")"


@njit(cache=True)
def couple_pairs(x, mass, master, slave, held):
    """Replace a nodal field of each pair by its mass-weighted cyclic average (module notes).

    x_a <- (m_a x_a + m_b R^T x_b) / (m_a + m_b), x_b <- R x_a with R = diag(-1, -1, 1);
    components held fixed on the pair are set to 0.

    Parameters
    ----------
    x : ndarray (n_nodes, 3) float64
        In/out: velocities (mm/s) or accelerations (mm/s^2).
    mass : ndarray (n_nodes,) float64
        Lumped (scaled) nodal masses, tonne.
    master, slave : ndarray (n_pairs,) int64
        Node a at (x, 0, z), x > 0, and its image b at (-x, 0, z).
    held : ndarray (n_pairs, 3) uint8
        1 where both nodes of the pair have the component fixed.

    Returns
    -------
    float
        sum (m_a x_a^2 + m_b x_b^2 - (m_a + m_b) x^2) / 2 over the pairs: for velocities the
        kinetic energy (mJ) removed, 0 when they already satisfy the condition.
    """
    lost = 0.0
    for k in range(master.shape[0]):
        a, b = master[k], slave[k]
        m_a, m_b = mass[a], mass[b]
        m = m_a + m_b
        for i in range(3):
            sign = 1.0 if i == 2 else -1.0
            value = 0.0
            if held[k, i] == 0 and m > 0.0:
                value = (m_a * x[a, i] + sign * m_b * x[b, i]) / m
            lost += 0.5 * (m_a * x[a, i] * x[a, i] + m_b * x[b, i] * x[b, i] - m * value * value)
            x[a, i] = value
            x[b, i] = sign * value
    return lost


def couple_cyclic_pairs(model, state, velocities: bool = True) -> float:
    """Impose the model's cyclic pairs on ``state.a`` (and ``state.v``); return the kinetic energy removed, mJ.

    Called by the time loop before each step (velocities and accelerations) and after the
    new acceleration (accelerations only); a no-op without cyclic pairs.
    """
    if model.cyclic_master.size == 0:
        return 0.0
    lost = 0.0
    if velocities:
        lost = couple_pairs(state.v, state.mass, model.cyclic_master, model.cyclic_slave, model.cyclic_held)
    couple_pairs(state.a, state.mass, model.cyclic_master, model.cyclic_slave, model.cyclic_held)
    return lost


def pair_copies(model, node_copies: np.ndarray) -> None:
    """Add the cyclic pairs of node copies: (copy of a, copy of b) for every pair (a, b) of the
    model whose nodes both have a copy (``node_copies`` (n, 2) int64: original, copy); the copies
    of a split mesh sit where their originals do, so they are each other's images. Part of
    :func:`~corneasim.solver.build_model`."""
    copy_of = dict(zip(node_copies[:, 0].tolist(), node_copies[:, 1].tolist()))
    rows = [k for k, (a, b) in enumerate(zip(model.cyclic_master, model.cyclic_slave))
            if int(a) in copy_of and int(b) in copy_of]
    if not rows:
        return
    model.cyclic_master = np.concatenate([model.cyclic_master,
                                          [copy_of[int(model.cyclic_master[k])] for k in rows]]).astype(np.int64)
    model.cyclic_slave = np.concatenate([model.cyclic_slave,
                                         [copy_of[int(model.cyclic_slave[k])] for k in rows]]).astype(np.int64)
    model.cyclic_held = np.concatenate([model.cyclic_held, model.cyclic_held[rows]]).astype(np.uint8)
