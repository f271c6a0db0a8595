"""The sum of the per-thread force buffers of the fast kernels, shared by both elements.

Each thread of a fast kernel scatters the forces of a static range of blocks into its own
buffer ``buffers[t]``, touching only the nodes ``thread_range[t, 0] .. thread_range[t, 1]``
of its blocks (race-free without atomics: ``/work/shared/PERFORMANCE-NOTES.md`` note 4).
Node ranges of consecutive threads overlap only where their blocks share nodes, so the
sum runs over contiguous node chunks and adds each thread's part of the chunk with a
straight vector loop, clearing what it read: the buffers are zero before every kernel call
and after it, and no separate zeroing pass is needed.
"""

from __future__ import annotations

from numba import njit, prange

N_CHUNKS = 32  # node chunks of the parallel sum (static split between the threads)


@njit(cache=True)
def thread_blocks(t, nt, n_nodes, node_lo, node_hi, thread_range):
    """The static block range (b0, b1) of thread t of nt; records the thread's node range.

    Blocks t n_blocks / nt .. (t + 1) n_blocks / nt - 1; ``thread_range[t]`` gets the first
    and last node they touch (n_nodes, -1 when the thread has no block), which
    :func:`sum_thread_buffers` reads. node_lo, node_hi (n_blocks,) int64: each block's range.
    """
    n_blocks = node_lo.shape[0]
    b0 = t * n_blocks // nt
    b1 = (t + 1) * n_blocks // nt
    lo = n_nodes
    hi = -1
    for blk in range(b0, b1):
        lo = min(lo, node_lo[blk])
        hi = max(hi, node_hi[blk])
    thread_range[t, 0] = lo
    thread_range[t, 1] = hi
    return b0, b1


@njit(cache=True, fastmath=True, error_model="numpy", inline="always")
def _add_and_clear(total, part):
    """total += part, then part = 0 (two loops over 0-based slices: 3.4x faster than one
    loop indexing both whole arrays, which LLVM did not vectorise; 20,301 nodes, 2 dofs)."""
    for k in range(part.shape[0]):
        total[k] += part[k]
    part[:] = 0.0


@njit(cache=True, parallel=True, fastmath=True, error_model="numpy")
def sum_thread_buffers(buffers, thread_range, energy_parts, f_int, energy_rates):
    """f_int = sum_t buffers[t] (then buffers = 0); energy_rates = sum_t energy_parts[t].

    Parameters
    ----------
    buffers : ndarray (nt, n_nodes, dim) float64
        In/out: the threads' forces, N; zero outside each thread's node range; cleared.
    thread_range : ndarray (nt, 2) int64
        First and last node each thread wrote (last < first: none).
    energy_parts : ndarray (nt, 3) float64
        Each thread's hourglass energy (mJ) and bulk-viscous and viscoelastic power (mJ/s).
    f_int : ndarray (n_nodes, dim) float64
        Out: internal forces, N.
    energy_rates : ndarray (3,) float64
        Out: their sums, mJ/s.
    """
    nt, n_nodes, dim = buffers.shape
    flat = buffers.reshape(nt, n_nodes * dim)
    out = f_int.reshape(n_nodes * dim)
    for c in prange(N_CHUNKS):
        k0 = c * n_nodes // N_CHUNKS * dim
        k1 = (c + 1) * n_nodes // N_CHUNKS * dim
        out[k0:k1] = 0.0
        for t in range(nt):
            first = max(k0, thread_range[t, 0] * dim)
            last = min(k1, (thread_range[t, 1] + 1) * dim)
            if last > first:
                _add_and_clear(out[first:last], flat[t, first:last])
    for j in range(3):
        total = 0.0
        for t in range(nt):
            total += energy_parts[t, j]
        energy_rates[j] = total
