"""Block sizes shared by the history layout and the fast kernels, and the one LLVM option
the fast kernels need.

The SIMD loop of a kernel reads and writes many rows of three arrays (scratch, geometry,
history). LLVM vectorises it behind a runtime check that the arrays do not overlap, and it
merges the per-row checks into one per array only if that takes fewer than
``-memory-check-merge-threshold`` comparisons (default 100): the hexahedron loop needs
more, so the threshold is raised here, before any kernel is compiled. The option only
affects compile time; it is process-wide and harmless to other Numba code.
"""

import llvmlite.binding as llvm

QUAD_BLOCK_SIZE = 32
HEX_BLOCK_SIZE = 16
"""Elements per block: the fast kernels run one SIMD loop over a block's elements. The
hexahedron's block is smaller so that its scratch, geometry and history rows fit in L1."""
BLOCK_SIZES = {"quad": QUAD_BLOCK_SIZE, "hexahedron": HEX_BLOCK_SIZE}

llvm.set_option("corneasim", "-memory-check-merge-threshold=1000")
