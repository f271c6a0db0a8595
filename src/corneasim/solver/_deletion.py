"""Element deletion: failure check, distortion control, orphaned nodes.

An element whose failure ratio (criterion value / limit, from the element kernel) reaches 1
dies for good: its ``alive`` flag drops to 0, after which the element kernel gives it zero
stress and force and stops updating its history, as a VUMAT deletion state variable does
(Abaqus Analysis User's Guide, "Element deletion"). Deletion is a mask: the mesh is never
changed. A node all of whose elements are dead is released: it keeps its mass and moves
freely, its boundary conditions no longer apply and contact ignores it (``node_active``).

Deletion takes effect in the step in which the criterion is met: the internal forces of
that step are re-evaluated without the dead elements (:func:`drop_dead_element_forces`), so
their stress does not act for one more step (which would push their nodes with a force the
energy balance cannot see). Their stored energy stays in the internal work: it is the energy
that deletion removes from the body.

Distortion control (element erosion): an element whose shape degenerates is deleted in
the same way, whatever its stress. The measure is the smallest corner Jacobian ratio

.. math::

    \\eta_e = \\min_a \\frac{j_a(\\mathbf{x})}{j_a(\\mathbf{X})},\\qquad
    j_a = (\\mathbf{x}_{a+1} - \\mathbf{x}_a) \\times (\\mathbf{x}_{a-1} - \\mathbf{x}_a)

(quad, in the (r, z) plane; the hexahedron uses the triple product of the three edges at a
corner): the local area (volume) change at a corner. It is 1 undeformed, det F for a
homogeneous deformation (the in-plane det F in the axisymmetric model), tends to 0
when a corner is crushed and is negative when the element folds over, which the
one-point centre Jacobian does not see. A folded or crushed element has a stable step
close to zero, so an explicit run with a fixed or mass-scaled step blows up a few steps
later; codes therefore erode such elements (LS-DYNA deletes solids whose step falls below
a limit, ``*CONTROL_TIMESTEP`` ERODE; G. R. Johnson and R. A. Stryk, "Eroding interface and
improved tetrahedral element algorithms for high-velocity impact computations in three
dimensions", Int. J. Impact Eng. 5 (1987) 411-421, for erosion at a deformation limit).
An element is eroded when eta_e < ``distortion_limit``, checked every ``DISTORTION_EVERY``
steps.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.solver import elements as element_kernels
from corneasim.solver._integrate import ENERGY_INTERNAL, NO_REFERENCE
from corneasim.solver._softening import update_softening


DISTORTION_EVERY = 10
"""Steps between distortion checks (a pass over all elements costs about 10 ns per element,
a fifth of a force evaluation; a fold develops over several steps)."""


@njit(cache=True)
def delete_failed_elements(failure_ratio, alive, deleted):
    """Kill live elements whose failure ratio is >= 1.

    Parameters
    ----------
    failure_ratio : ndarray (n_elements,) float64
        Criterion / limit from the last force evaluation (dimensionless).
    alive : ndarray (n_elements,) uint8
        In/out: 1 alive, 0 dead.
    deleted : ndarray (n_elements,) int64
        Out: the first ``count`` entries are the elements deleted now.

    Returns
    -------
    int
        ``count``, the number of elements deleted by this call.
    """
    count = 0
    for e in range(alive.shape[0]):
        if alive[e] != 0 and failure_ratio[e] >= 1.0:
            alive[e] = 0
            deleted[count] = e
            count += 1
    return count


@njit(cache=True)
def delete_distorted_elements(points, u, cells, corner_inverse, alive, distortion_limit, deleted, count):
    """Kill live elements whose smallest corner Jacobian ratio is below ``distortion_limit``.

    Parameters
    ----------
    points : ndarray (n_nodes, dim) float64
        Reference coordinates, mm.
    u : ndarray (n_nodes, dim) float64
        Displacement, mm.
    cells : ndarray (n_elements, 4 | 8) int64
        Quads (counter-clockwise in (r, z)) or hexahedra (VTK order).
    corner_inverse : ndarray (n_elements, 4 | 8) float64
        1 / j_a(X) (:func:`reference_corner_inverse`), 1/mm^2 or 1/mm^3.
    alive : ndarray (n_elements,) uint8
        In/out: 1 alive, 0 dead.
    distortion_limit : float
        Smallest admissible ratio of a corner Jacobian to its reference value, dimensionless.
    deleted : ndarray (n_elements,) int64
        Out: entries ``count`` onwards receive the elements deleted now.
    count : int
        Number of entries of ``deleted`` already used.

    Returns
    -------
    int
        The new ``count``.
    """
    quads = cells.shape[1] == 4
    for e in range(alive.shape[0]):
        if alive[e] == 0:
            continue
        if quads:
            ratio = _quad_corner_ratio(points, u, cells, corner_inverse, e)
        else:
            ratio = corner_jacobian_ratio(points, u, cells, corner_inverse, e)
        if ratio < distortion_limit:
            alive[e] = 0
            deleted[count] = e
            count += 1
    return count


@njit(cache=True, inline="always")
def _quad_corner_ratio(points, u, cells, corner_inverse, e):
    """:func:`corner_jacobian_ratio` of a quad with each node gathered once (the per-step path)."""
    n0, n1, n2, n3 = cells[e, 0], cells[e, 1], cells[e, 2], cells[e, 3]
    r0, z0 = points[n0, 0] + u[n0, 0], points[n0, 1] + u[n0, 1]
    r1, z1 = points[n1, 0] + u[n1, 0], points[n1, 1] + u[n1, 1]
    r2, z2 = points[n2, 0] + u[n2, 0], points[n2, 1] + u[n2, 1]
    r3, z3 = points[n3, 0] + u[n3, 0], points[n3, 1] + u[n3, 1]
    # edges a -> a+1; corner a: (x_{a+1} - x_a) x (x_{a-1} - x_a) = -(e_a x e_{a-1})
    er0, ez0, er1, ez1 = r1 - r0, z1 - z0, r2 - r1, z2 - z1
    er2, ez2, er3, ez3 = r3 - r2, z3 - z2, r0 - r3, z0 - z3
    j0 = er3 * ez0 - ez3 * er0
    j1 = er0 * ez1 - ez0 * er1
    j2 = er1 * ez2 - ez1 * er2
    j3 = er2 * ez3 - ez2 * er3
    return min(j0 * corner_inverse[e, 0], j1 * corner_inverse[e, 1], j2 * corner_inverse[e, 2],
               j3 * corner_inverse[e, 3])


def reference_corner_inverse(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """1 / j_a(X) for every corner of every element, (n_elements, 4 | 8), 1/mm^2 or 1/mm^3."""
    inverse = np.empty(cells.shape, dtype=np.float64)
    _corner_jacobians(np.ascontiguousarray(points, dtype=np.float64), np.zeros_like(points, dtype=np.float64),
                      np.ascontiguousarray(cells, dtype=np.int64), inverse)
    return 1.0 / inverse


@njit(cache=True)
def _corner_jacobians(points, u, cells, out):
    """out[e, a] = j_a(X + u) (module notes)."""
    for e in range(cells.shape[0]):
        for a in range(cells.shape[1]):
            out[e, a] = _corner_jacobian(points, u, cells, e, a)


@njit(cache=True)
def corner_jacobian_ratios(points, u, cells, corner_inverse, alive, out):
    """out[e] = eta_e (:func:`corner_jacobian_ratio`) of every live element, 1 for a dead one;
    quads as :func:`delete_distorted_elements` takes them, each node gathered once."""
    quads = cells.shape[1] == 4
    for e in range(cells.shape[0]):
        if alive[e] == 0:
            out[e] = 1.0
        elif quads:
            out[e] = _quad_corner_ratio(points, u, cells, corner_inverse, e)
        else:
            out[e] = corner_jacobian_ratio(points, u, cells, corner_inverse, e)


@njit(cache=True)
def corner_jacobian_ratio(points, u, cells, corner_inverse, e):
    """eta_e = min over corners of j_a(x) / j_a(X) of element ``e`` (module notes), dimensionless."""
    smallest = np.inf
    for a in range(cells.shape[1]):
        smallest = min(smallest, _corner_jacobian(points, u, cells, e, a) * corner_inverse[e, a])
    return smallest


@njit(cache=True, inline="always")
def _corner_jacobian(points, u, cells, e, a):
    """j_a(x) of corner ``a`` of element ``e``: cross (quad) or triple (hexahedron) product of its edges."""
    p = cells[e, a]
    if cells.shape[1] == 4:
        q, s = cells[e, (a + 1) % 4], cells[e, (a + 3) % 4]
        qx = points[q, 0] + u[q, 0] - points[p, 0] - u[p, 0]
        qy = points[q, 1] + u[q, 1] - points[p, 1] - u[p, 1]
        sx = points[s, 0] + u[s, 0] - points[p, 0] - u[p, 0]
        sy = points[s, 1] + u[s, 1] - points[p, 1] - u[p, 1]
        return qx * sy - qy * sx
    if a < 4:
        q, s, w = cells[e, (a + 1) % 4], cells[e, (a + 3) % 4], cells[e, a + 4]
    else:
        q, s, w = cells[e, 4 + (a + 3) % 4], cells[e, 4 + (a + 1) % 4], cells[e, a - 4]
    a0 = points[q, 0] + u[q, 0] - points[p, 0] - u[p, 0]
    a1 = points[q, 1] + u[q, 1] - points[p, 1] - u[p, 1]
    a2 = points[q, 2] + u[q, 2] - points[p, 2] - u[p, 2]
    b0 = points[s, 0] + u[s, 0] - points[p, 0] - u[p, 0]
    b1 = points[s, 1] + u[s, 1] - points[p, 1] - u[p, 1]
    b2 = points[s, 2] + u[s, 2] - points[p, 2] - u[p, 2]
    c0 = points[w, 0] + u[w, 0] - points[p, 0] - u[p, 0]
    c1 = points[w, 1] + u[w, 1] - points[p, 1] - u[p, 1]
    c2 = points[w, 2] + u[w, 2] - points[p, 2] - u[p, 2]
    return a0 * (b1 * c2 - b2 * c1) - a1 * (b0 * c2 - b2 * c0) + a2 * (b0 * c1 - b1 * c0)


@njit(cache=True)
def update_node_activity(cells, alive, node_active, a):
    """node_active[a] = 1 when node a belongs to at least one live element, else 0.

    Nodes released now (1 -> 0) get zero acceleration: they carry no element and no load,
    so they keep the velocity of the step in which they were released (no kick from the
    force of the element that just died or from an unbalanced constraint).

    cells (n_elements, nodes_per_element) int64; alive (n_elements,) uint8;
    node_active (n_nodes,) uint8, overwritten; a (n_nodes, dim) mm/s^2, in/out.
    """
    n_nodes = node_active.shape[0]
    was_active = node_active.copy()
    node_active[:] = 0
    for e in range(cells.shape[0]):
        if alive[e] != 0:
            for k in range(cells.shape[1]):
                node_active[cells[e, k]] = 1
    for node in range(n_nodes):
        if was_active[node] != 0 and node_active[node] == 0:
            for i in range(a.shape[1]):
                a[node, i] = 0.0


def drop_dead_element_forces(model, state, damping: float, reference=NO_REFERENCE) -> None:
    """Re-evaluate f_int at t^{n+1} without the elements just deleted; fix a and the internal work.

    Runs only in steps with deletions. The element kernel is called with Δt = 0 on a copy of
    the history (no relaxation, the history is not advanced twice); the half internal work
    booked with the old forces over the last half step is corrected to the new forces, and
    a^{n+1} = (f_ext - f_int) / m - α (v^{n+1/2} - v̄), with v̄ the ``reference`` velocity
    (mm/s, per component) that the step's damping acted on (``_run.damping_reference``).
    Pressure and hook forces are kept.
    """
    previous = state.f_int.copy()
    rates = state.energy_rates.copy()
    element_kernels.eval_internal_forces(state.elements, state.u, 0.0, state.alive,
                                         state.history.copy(), state.f_int, state.failure_ratio,
                                         state.energy_rates)
    state.energy_rates[:] = rates
    du = state.time_step * state.v
    state.energies[ENERGY_INTERNAL] += 0.5 * float(np.sum((state.f_int - previous) * du))
    state.a[:] = ((state.f_ext - state.f_int) * state.dof_inverse_mass.reshape(state.a.shape)
                  - damping * (state.v - reference[:state.v.shape[1]]))


def delete_elements(model, state, buffer, damping: float, reference=NO_REFERENCE) -> list:
    """The failure check of one step: kill failed and distorted elements, log them, release orphaned nodes.

    Blocks with a fracture energy soften before they are deleted (:mod:`corneasim.solver._softening`).
    ``buffer`` is scratch (n_elements,) int64; ``damping`` (1/s) and ``reference`` (mm/s) are
    the step's (:func:`drop_dead_element_forces`). Returns the new deletions as
    (time s, element, block name) tuples (also appended to ``state.deleted_*``).
    """
    if model.softening is None:
        count = delete_failed_elements(state.failure_ratio, state.alive, buffer)
    else:
        count = update_softening(model, state, buffer, 0)
    if model.distortion_limit > 0.0 and state.step % DISTORTION_EVERY == 0:
        count = delete_distorted_elements(model.mesh.points, state.u, model.mesh.cells, model.corner_inverse,
                                          state.alive, model.distortion_limit, buffer, count)
    if count == 0:
        return []
    elements = buffer[:count].copy()
    state.deleted_element = np.concatenate([state.deleted_element, elements])
    state.deleted_time = np.concatenate([state.deleted_time, np.full(count, state.time)])
    drop_dead_element_forces(model, state, damping, reference)
    update_node_activity(model.mesh.cells, state.alive, state.node_active, state.a)
    return [(state.time, int(e), model.block_of(e)) for e in elements]
