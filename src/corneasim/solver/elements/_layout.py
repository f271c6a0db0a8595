"""Block size shared by the history layout and the fast kernels (a compile-time constant)."""

BLOCK_SIZE = 32
"""Elements per block: the fast kernels run one SIMD loop over a block's elements."""
