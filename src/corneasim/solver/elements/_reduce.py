"""Race-free, thread-count-independent assembly of the fast kernels' nodal forces.

The element blocks are cut into ``P`` parts, contiguous runs of blocks fixed by the mesh
alone (:func:`part_layout`), and a thread of a fast kernel runs whole parts, each from its
first block to its last (which thread runs which part is decided at run time,
``_schedule``). An element adds its nodal forces to a *target* row of the
kernel's force array (``cells_target``): a node that only one part's elements touch is
its own row, the same for every element of that part; a node shared by several parts has
one extra row per part, after the node rows. :func:`sum_part_forces` copies the node rows
to the internal forces and adds each shared node's part rows in part order. Every row is
thus the same sum in the same order whoever ran the part, and the internal forces are
bitwise the same on any number of threads: with one buffer per thread, the nodes two
threads shared were summed in another order on another thread count, and that round-off
decided the outcome of runs near a failure cascade. No atomics are needed (they would
serialise the scatter; ``docs/performance.md``); the rows are cleared as they are read, so
the force array is zero between calls.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from corneasim.solver.elements._schedule import active_threads, use_threads

MAX_PARTS = 8
"""Parts of a fast kernel's blocks: as many threads as this share the work; more parts
would share more nodes (8 parts share 3.4% of the needle's default mesh's nodes, 17% of
the trephine's umbrella mesh's)."""
N_CHUNKS = 32  # node chunks of the parallel sum (static split between the threads)


def part_layout(blocked_cells, n_nodes):
    """Parts, target rows and the shared-node table of a block-major element-node table.

    Parameters
    ----------
    blocked_cells : ndarray (n_blocks, nodes_per_element, block) int64
        Node of each element node, block-major (padding lanes repeat an element).
    n_nodes : int
        Number of nodes of the mesh.

    Returns
    -------
    dict
        ``part_block`` (P + 1,): the blocks of part p are part_block[p] .. part_block[p + 1] - 1;
        ``cells_target`` (n_blocks, nodes_per_element, block) int32: the force row of each
        element node (32-bit, like the kernels' copy of the element-node table: less to
        stream); ``n_rows``: n_nodes plus the number of (shared node, part) rows;
        ``shared_node`` (n_shared,), ``shared_start`` (n_shared + 1,): the rows of shared
        node ``shared_node[j]`` are shared_start[j] .. shared_start[j + 1] - 1, in part order;
        ``chunk_shared`` (N_CHUNKS + 1,): the shared nodes of the sum's node chunk c are
        ``shared_node[chunk_shared[c]:chunk_shared[c + 1]]``.
    """
    n_blocks = blocked_cells.shape[0]
    n_parts = min(MAX_PARTS, n_blocks)
    part_block = np.arange(n_parts + 1, dtype=np.int64) * n_blocks // n_parts
    touched = np.zeros((n_parts, n_nodes), bool)
    for p in range(n_parts):
        touched[p, blocked_cells[part_block[p]:part_block[p + 1]].ravel()] = True
    shared = touched.sum(axis=0) > 1
    shared_node = np.flatnonzero(shared).astype(np.int64)
    # rows of the shared nodes: node-major, part order within a node
    parts_of_shared = touched[:, shared_node].T  # (n_shared, P)
    row_of = np.full(parts_of_shared.shape, -1, np.int64)
    row_of[parts_of_shared] = n_nodes + np.arange(int(parts_of_shared.sum()))
    shared_start = np.concatenate([[n_nodes], n_nodes + np.cumsum(parts_of_shared.sum(axis=1))])
    shared_index = np.full(n_nodes, -1, np.int64)
    shared_index[shared_node] = np.arange(shared_node.size)
    cells_target = blocked_cells.astype(np.int64)  # a copy
    for p in range(n_parts):
        cells = cells_target[part_block[p]:part_block[p + 1]]
        j = shared_index[cells]
        cells[j >= 0] = row_of[j[j >= 0], p]
    chunk_start = np.arange(N_CHUNKS + 1, dtype=np.int64) * n_nodes // N_CHUNKS
    return dict(part_block=part_block, cells_target=cells_target.astype(np.int32),
                n_rows=int(shared_start[-1]), shared_node=shared_node,
                shared_start=shared_start.astype(np.int64),
                chunk_shared=np.searchsorted(shared_node, chunk_start).astype(np.int64))


@njit(cache=True, fastmath=True, error_model="numpy", inline="always")
def _move(total, rows):
    """total = rows, then rows = 0 (0-based slices: LLVM vectorises both loops)."""
    for k in range(rows.shape[0]):
        total[k] = rows[k]
    rows[:] = 0.0


@njit(cache=True, fastmath=True, error_model="numpy", inline="always")
def _sum_shared_2(row_forces, shared_node, shared_start, j0, j1, out):
    """Shared nodes j0 .. j1 - 1 of a 2D mesh: out = their rows summed in order, rows = 0
    (one function per dimension: with the dimension known the loop is 4x faster)."""
    for j in range(j0, j1):
        a = 0.0
        b = 0.0
        for r in range(shared_start[j], shared_start[j + 1]):
            a += row_forces[2 * r]
            b += row_forces[2 * r + 1]
            row_forces[2 * r] = 0.0
            row_forces[2 * r + 1] = 0.0
        out[2 * shared_node[j]] = a
        out[2 * shared_node[j] + 1] = b


@njit(cache=True, fastmath=True, error_model="numpy", inline="always")
def _sum_shared_3(row_forces, shared_node, shared_start, j0, j1, out):
    """As :func:`_sum_shared_2` for a 3D mesh."""
    for j in range(j0, j1):
        a = 0.0
        b = 0.0
        c = 0.0
        for r in range(shared_start[j], shared_start[j + 1]):
            a += row_forces[3 * r]
            b += row_forces[3 * r + 1]
            c += row_forces[3 * r + 2]
            row_forces[3 * r] = 0.0
            row_forces[3 * r + 1] = 0.0
            row_forces[3 * r + 2] = 0.0
        out[3 * shared_node[j]] = a
        out[3 * shared_node[j] + 1] = b
        out[3 * shared_node[j] + 2] = c


@njit(cache=True, parallel=True, fastmath=True, error_model="numpy")
def sum_part_forces(row_forces, shared_node, shared_start, chunk_shared, part_energy, f_int,
                    energy_rates, threads):
    """Internal forces from the kernel's force rows, which are cleared.

    f_int[n] = row n, except for a shared node: the sum of its part rows in part order.
    energy_rates = sum_p part_energy[p], in part order.

    Parameters
    ----------
    row_forces : ndarray (n_rows * dim,) float64
        In/out: the kernel's force rows (N), row-major; zero on return.
    shared_node, shared_start, chunk_shared : ndarray int64
        Shared-node table of :func:`part_layout` and each node chunk's share of it.
    part_energy : ndarray (P, 3) float64
        Each part's hourglass energy (mJ) and bulk-viscous and viscoelastic power (mJ/s).
    f_int : ndarray (n_nodes, dim) float64
        Out: internal forces, N.
    energy_rates : ndarray (3,) float64
        Out: the sums of ``part_energy``.
    threads : int
        Threads to run on, at most Numba's current count (the force kernel's: one wakes no
        other thread; the sums do not depend on it).
    """
    n_nodes, dim = f_int.shape
    saved = active_threads()
    use_threads(min(threads, saved))
    out = f_int.reshape(n_nodes * dim)
    for c in prange(N_CHUNKS):
        n0 = c * n_nodes // N_CHUNKS
        n1 = (c + 1) * n_nodes // N_CHUNKS
        _move(out[n0 * dim:n1 * dim], row_forces[n0 * dim:n1 * dim])
        # then the chunk's shared nodes (the copy wrote 0 to them)
        if dim == 2:
            _sum_shared_2(row_forces, shared_node, shared_start, chunk_shared[c],
                          chunk_shared[c + 1], out)
        else:
            _sum_shared_3(row_forces, shared_node, shared_start, chunk_shared[c],
                          chunk_shared[c + 1], out)
    use_threads(saved)
    for j in range(3):
        total = 0.0
        for p in range(part_energy.shape[0]):
            total += part_energy[p, j]
        energy_rates[j] = total
