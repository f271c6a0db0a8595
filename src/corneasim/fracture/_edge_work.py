"""The work of a cutting edge on the ties it touches: the fracture energy paid by the blade's motion.

A blade cuts when the work it does at its edge pays the toughness of the new surface. For a
blade that slides as well as pushes, both motions do that work (A. G. Atkins, *The Science
and Engineering of Cutting*, 2009, ch. 7; A. G. Atkins, X. Xu, G. Jeronimidis, J. Mater. Sci.
39 (2004) 2761-2766: the push F_z a cut needs falls as the slice-push ratio grows): for the
trephine the edge slides at R theta' (up to 16 mm/s) against a descent of 0.02 mm/s, so the
rotation supplies most of the energy. Each step the work the instrument does on the two nodes
of a tie (:mod:`corneasim.fracture._ties`) is added to the energy supplied to it,

.. math::

    W_i \\leftarrow W_i + \\Delta t \\, \\max\\bigl(0, \\sum_{n \\in \\{a_i, b_i\\}}
        \\mathbf f_n \\cdot \\mathbf v_{\\text{blade}}(\\mathbf x_n)\\bigr), \\qquad
    \\mathbf v_{\\text{blade}}(\\mathbf x) = \\dot z\\, \\mathbf e_z + \\dot\\theta\\, \\mathbf e_z \\times
        (\\mathbf x - \\mathbf c),

f_n the instrument's force on node n (push and friction, N), c its axis (mm), z' and theta'
its descent and angular velocity: the blade's power on the tissue at the tie, summed over
each through-thickness line of ties and given to the line's front (its first tie from the
anterior surface not yet cut). The edge presses on the faces of the cut above the front
(its two copies stay together under the edge's tip), and the work it does there loads the
tissue ahead of the cut, which the front stands for. A tie is cut once W_i and its own
dissipation reach G_c A_i, and the front moves one tie down. The energy is not counted twice: the
solver books the contact's work and friction as it does without ties, W_i only decides when
the tie gives (``<name>_edge_energy_mJ`` reports the sum).

The instrument's forces on the tie nodes are the change of ``f_ext`` over the instrument's
hook: :class:`EdgeWork` is one hook before it (:meth:`EdgeWork.before`, which records
``f_ext`` there) and one after (:meth:`EdgeWork.add_forces`, which reads the change and adds
the power), so that neither the contact nor the ties need to know each other.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.instruments import POSE_OMEGA, POSE_VZ, POSE_X, POSE_Y


@njit(cache=True)
def edge_power(points, u, pairs, line_start, line_pairs, cut, f_ext, f_before, pose, time_step, supplied):
    """Add the blade's work over one step on each line of ties to its front tie (mJ; module notes).

    Parameters
    ----------
    points, u : ndarray (n_nodes, 3) float64
        Reference coordinates and displacements, mm.
    pairs : ndarray (n_pairs, 2) int64
        The ties' (a, b) node pairs.
    line_start : ndarray (n_lines + 1,) int64
        Line k holds the ties ``line_pairs[line_start[k]:line_start[k + 1]]``.
    line_pairs : ndarray (n_pairs,) int64
        Tie indices by line, each line from the anterior surface down.
    cut : ndarray (n_pairs,) uint8
        The ties cut through; a line's front is its first tie not cut.
    f_ext : ndarray (n_nodes, 3) float64
        External forces after the instrument's hook, N.
    f_before : ndarray (n_pairs, 2, 3) float64
        The pairs' rows of ``f_ext`` before it, N.
    pose : ndarray (8,) float64
        The instrument's pose (``instruments.pose_at``): axis, angle, velocities.
    time_step : float
        s.
    supplied : ndarray (n_pairs,) float64
        In/out: W_i, mJ.
    """
    v_z = pose[POSE_VZ]
    omega = pose[POSE_OMEGA]
    for line in range(line_start.size - 1):
        power = 0.0
        front = -1
        for k in range(line_start[line], line_start[line + 1]):
            i = line_pairs[k]
            if front < 0 and cut[i] == 0:
                front = i
            for side in range(2):
                n = pairs[i, side]
                x = points[n, 0] + u[n, 0] - pose[POSE_X]
                y = points[n, 1] + u[n, 1] - pose[POSE_Y]
                power += ((f_ext[n, 0] - f_before[i, side, 0]) * (-omega * y)
                          + (f_ext[n, 1] - f_before[i, side, 1]) * (omega * x)
                          + (f_ext[n, 2] - f_before[i, side, 2]) * v_z)
        if front >= 0 and power > 0.0:
            supplied[front] += power * time_step


@njit(cache=True)
def gather_pair_rows(f_ext, pairs, f_before):
    """Copy the pairs' rows of ``f_ext`` (n_nodes, 3), N, into ``f_before`` (n_pairs, 2, 3)."""
    for i in range(pairs.shape[0]):
        for side in range(2):
            n = pairs[i, side]
            for c in range(3):
                f_before[i, side, c] = f_ext[n, c]


def tie_lines(points: np.ndarray, pairs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The ties grouped by through-thickness line (same x, y to 1e-9 mm), each from the top (largest
    z) down: (line_start, line_pairs) of :func:`edge_power`."""
    x = points[pairs[:, 0]]
    key = np.round(x[:, :2] / 1e-9).astype(np.int64)
    _, line = np.unique(key, axis=0, return_inverse=True)
    line = line.ravel()
    order = np.lexsort((-x[:, 2], line))
    line_start = np.searchsorted(line[order], np.arange(line.max() + 2)).astype(np.int64)
    return line_start, order.astype(np.int64)


class EdgeWork:
    """The instrument's work on the ties' nodes, fed to the ties (module notes).

    Parameters
    ----------
    ties : corneasim.fracture.CohesiveTies
        The ties; their ``supplied`` energies grow.
    instrument : corneasim.contact.InstrumentContact
        The instrument whose hook runs between :meth:`before` and :meth:`add_forces`.
    line_points : ndarray (n_nodes, 3) float64, optional
        The coordinates (mm) the ties are grouped into through-thickness lines by
        (:func:`tie_lines`): the instrument's reference coordinates unless given. On a
        prestressed reference the measured mesh's, where the lines are parallel to the axis
        (the stress-free geometry moves each tie of a line by its own displacement).
    """

    def __init__(self, ties, instrument, line_points=None):
        self.name = f"{ties.name}_edge"
        self.ties = ties
        self.instrument = instrument
        self.nodes = ties.pairs
        grouped_by = instrument.points if line_points is None else line_points
        self.line_start, self.line_pairs = tie_lines(grouped_by, ties.pairs)
        self.f_before = np.zeros((len(ties.pairs), 2, 3))
        self.before = _Before(self)

    def record(self, f_ext: np.ndarray) -> None:
        """Keep the pairs' rows of ``f_ext`` (N) before the instrument adds its forces."""
        gather_pair_rows(f_ext, self.nodes, self.f_before)

    def add_forces(self, model, state, time: float, time_step: float, f_ext: np.ndarray) -> None:
        """Add the instrument's work over this step to the ties' supplied energies (adds no force)."""
        edge_power(model.mesh.points, state.u, self.nodes, self.line_start, self.line_pairs, self.ties.cut, f_ext,
                   self.f_before, self.instrument.pose, float(time_step), self.ties.supplied)

    def outputs(self) -> dict[str, float]:
        """None of its own (the ties report ``<name>_edge_energy_mJ``)."""
        return {}


class _Before:
    """The hook before the instrument's: records ``f_ext`` at the tie nodes."""

    def __init__(self, work: EdgeWork):
        self.name = f"{work.name}_before"
        self.work = work

    def outputs(self) -> dict[str, float]:
        """None."""
        return {}

    def add_forces(self, model, state, time: float, time_step: float, f_ext: np.ndarray) -> None:
        """Record the tie nodes' external forces (adds no force)."""
        self.work.record(f_ext)
