"""Nodes left behind by deleted elements, written where they last belonged to the mesh.

A node all of whose elements are deleted is released by the solver: it keeps its mass and
the velocity of the step in which it was released and flies on, with no force acting on it
(``solver._deletion``). Over a run such nodes travel tens of millimetres, which makes the
field files' bounds, and every warp by the displacement, useless. They carry no element, so
their position carries no information: the field output writes each one at its last
attached position instead, the position in the step its last element was deleted.

The frozen displacement is recorded in the output path, at the first frame after the
release (the history step that reports the deletion), not in the solver's time loop. A free
node moves at constant velocity (its acceleration is zero from its release on), so the
position of the release step is recovered exactly from the frame's position and velocity:

.. math:: u_{\\text{release}} = u(t) - v\\,(t - t_{\\text{release}})

where :math:`t_{\\text{release}}` is the deletion time of the node's last element. With a
mass-proportional damping the node slows down between the release and the frame, and the
recovered position is off by the damping's share of that short flight.
"""

from __future__ import annotations

import numpy as np


class OrphanNodes:
    """The displacement at which each released node is written.

    Parameters
    ----------
    cells : ndarray (n_elements, nodes_per_element) int
        Connectivity.
    n_nodes : int
    dim : int
        Components of the displacement (2 axisymmetric, 3 solid).
    """

    def __init__(self, cells: np.ndarray, n_nodes: int, dim: int):
        self.cells = np.asarray(cells)
        self.release_time = np.full(n_nodes, -np.inf)  # solver time of the node's latest element deletion, s
        self.frozen = np.zeros(n_nodes, dtype=bool)
        self.displacement = np.zeros((n_nodes, dim))  # mm

    def deleted(self, elements, times) -> None:
        """Note element deletions: ``elements`` (indices) at solver ``times`` (s)."""
        elements = np.asarray(elements, dtype=np.int64)
        if elements.size == 0:
            return
        times = np.broadcast_to(np.asarray(times, dtype=float), elements.shape)
        np.maximum.at(self.release_time, self.cells[elements], times[:, None])

    def update(self, time: float, u: np.ndarray, v: np.ndarray, node_active: np.ndarray) -> None:
        """Freeze the nodes released since the last update, at their position of the release.

        Parameters
        ----------
        time : float
            Solver time of the state, s.
        u, v : ndarray (n_nodes, dim)
            Displacement (mm) and velocity (mm/s, solver time) of the state.
        node_active : ndarray (n_nodes,)
            0 for a node without a live element. Only nodes whose deletions were noted
            (:meth:`deleted`) are frozen: a node that never had an element does not move.
        """
        released = (np.asarray(node_active) == 0) & ~self.frozen & np.isfinite(self.release_time)
        if not released.any():
            return
        flight = np.maximum(time - self.release_time[released], 0.0)
        self.displacement[released] = u[released] - v[released] * flight[:, None]
        self.frozen |= released

    def apply(self, displacement: np.ndarray) -> np.ndarray:
        """``displacement`` with the frozen nodes at their release displacement (a copy)."""
        if not self.frozen.any():
            return displacement
        written = np.array(displacement, dtype=float, copy=True)
        written[self.frozen] = self.displacement[self.frozen]
        return written
