"""Which part of a fast kernel's blocks a thread runs next: claimed at run time, from both ends.

The parts (``_reduce.part_layout``) are independent: each writes its own force rows and its
own ``part_energy`` row, so the results do not depend on which thread runs a part. Before,
thread t of nt ran the fixed parts t P / nt .. (t + 1) P / nt - 1, and a thread the host
stalled (a shared virtual machine takes a vCPU away for a while; a sleeping OpenMP thread
wakes late, about 20 µs here) held the other back. Now the threads are paired
over ranges of parts: in each range one thread takes parts from the front and its partner
from the back, each claim counted by one atomic add on the range's counter, until the
range is used up. The first thread to finish a range's share takes more of it; each thread
still walks neighbouring parts in order (its nodes stay in its cache). With one thread, or
an odd last thread, a range is walked front to back alone.

The element kernels run their parallel regions on :func:`kernel_threads` threads (the force
kernels' scratch rows, the others' ``threads`` argument; :func:`active_threads`,
:func:`use_threads`): a region run on one thread wakes no other thread, so a small element
set does not pay the wake-up of a sleeping OpenMP thread (:data:`PARALLEL_MIN_ELEMENTS`).
Which thread runs a part or an element never changes a sum, so the results are the same
either way.
"""

from __future__ import annotations

import numba
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic


@intrinsic
def fetch_add(typingctx, counters, index, value):
    """Atomically ``counters[index] += value``; returns the value before (an int64 array).

    LLVM ``atomicrmw add`` with monotonic ordering: the parallel region's closing barrier
    orders everything else, the counter only has to hand out each claim once.
    """
    signature = types.int64(counters, types.intp, types.int64)

    def codegen(context, builder, sig, args):
        array = context.make_array(sig.args[0])(context, builder, args[0])
        pointer = builder.gep(array.data, [args[1]])
        return builder.atomic_rmw("add", pointer, args[2], "monotonic")

    return signature, codegen


PARALLEL_MIN_ELEMENTS = {"quad": 5000, "hexahedron": 5000}
"""Fewest elements for which the element kernels of each kind (forces, stable steps, centre
Jacobians) run on more than one thread, by kind. A smaller element set runs them on one
thread even when Numba has more, so that it never pays the wake-up of a sleeping worker
thread (35-60 µs a call once the step's serial part has let it sleep: ``docs/performance.md``,
"Threads") for less work than it saves: two threads pay when half a call's work exceeds
the wake-up, from about 2 x 40 µs / (17 ns) = 4,700 quads and 80 µs / (50 ns) = 1,600
hexahedra a step on a host with two independent cores. On this machine kind the second
vCPU shares a core (``benchmarks/kernels.py``'s machine check reads about 1.0), and a
4,760-hexahedron punch ran 2 % slower on two threads than on one, so both kinds start at
5,000. ``benchmarks/threads.py`` measures the crossover of a host."""


def kernel_threads(elements):
    """Threads of the element kernels for ``elements`` (an ``ElementSet``): Numba's current
    count, or 1 below :data:`PARALLEL_MIN_ELEMENTS` of its kind."""
    if elements.n_elements < PARALLEL_MIN_ELEMENTS[elements.kind]:
        return 1
    return numba.get_num_threads()


@intrinsic
def active_threads(typingctx):
    """Threads the calling thread's next parallel region runs on (Numba's
    ``get_num_threads``), an int64.

    Called through the threading layer's ``get_num_threads`` symbol, as the parallel region
    itself reads it, rather than ``numba.get_num_threads``, whose compiled form holds a ctypes
    pointer and so keeps a kernel out of the on-disk cache. The symbol is declared with the
    pointer-width return type Numba's parallel lowering gives it (one declaration per module)
    and read as the C ``int`` it is.
    """
    signature = types.int64()

    def codegen(context, builder, sig, args):
        function = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(ir.IntType(64), []), "get_num_threads")
        value = builder.trunc(builder.call(function, []), ir.IntType(32))
        return builder.sext(value, ir.IntType(64))

    return signature, codegen


@intrinsic
def use_threads(typingctx, count):
    """Run the calling thread's next parallel regions on ``count`` threads (Numba's
    ``set_num_threads`` without its range check: ``count`` is between 1 and
    :func:`active_threads`), through the threading layer's symbol as :func:`active_threads`."""
    signature = types.void(types.int64)

    def codegen(context, builder, sig, args):
        function = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(ir.VoidType(), [ir.IntType(32)]), "set_num_threads")
        builder.call(function, [builder.trunc(args[0], ir.IntType(32))])
        return context.get_dummy_value()

    return signature, codegen


@njit(cache=True, inline="always")
def claim_part(claimed, t, nt, n_parts, taken):
    """The next part for thread ``t`` of ``nt``, or -1 when its range is used up.

    Parameters
    ----------
    claimed : ndarray ((nt + 1) // 2,) int64
        One claim counter per range, zero at the start of the parallel region.
    t, nt : int
        This thread's index and the number of threads (iterations of the ``prange``).
    n_parts : int
        Number of parts.
    taken : int
        How many parts thread ``t`` has taken so far in this region.

    Returns
    -------
    int
        Range r = t // 2 holds parts r P / R .. (r + 1) P / R - 1 (R ranges); an even thread
        takes them from the front, an odd one from the back.
    """
    n_ranges = (nt + 1) // 2
    pair = t // 2
    first = pair * n_parts // n_ranges
    last = (pair + 1) * n_parts // n_ranges
    if fetch_add(claimed, pair, 1) >= last - first:
        return -1
    return first + taken if t % 2 == 0 else last - 1 - taken
