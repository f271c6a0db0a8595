"""Element deletion: the failure check and the release of orphaned nodes.

An element whose failure ratio (criterion value / limit, from the element kernel) reaches 1
dies for good: its ``alive`` flag drops to 0, after which the element kernel gives it zero
stress and force and stops updating its history, as a VUMAT deletion state variable does
(Abaqus Analysis User's Guide, "Element deletion"). Deletion is a mask: the mesh is never
changed. A node all of whose elements are dead is released: it keeps its mass and moves
freely, its boundary conditions no longer apply and contact ignores it (``node_active``).
"""

from __future__ import annotations

from numba import njit


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
def update_node_activity(cells, alive, node_active):
    """node_active[a] = 1 when node a belongs to at least one live element, else 0.

    cells (n_elements, nodes_per_element) int64; alive (n_elements,) uint8;
    node_active (n_nodes,) uint8, overwritten.
    """
    node_active[:] = 0
    for e in range(cells.shape[0]):
        if alive[e] != 0:
            for k in range(cells.shape[1]):
                node_active[cells[e, k]] = 1
