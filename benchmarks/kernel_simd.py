"""Whether the fast kernels' stress passes are vector code: counts in their LLVM IR.

Compiles the stress pass of each fast kernel (``_fast_quad._stress``, ``_fast_hex._stress``)
in a fresh, temporary Numba cache (a function loaded from the cache has no IR to show) and
counts in its optimised LLVM IR the ``<8 x double>`` / ``<4 x double>`` operations, the
vector ``floor`` calls (one per halving in ``exp_nonnegative``: the fibre term's exp) and
scalar calls of libm's ``exp`` (none expected: one would keep the fibre lanes scalar).

Run: ``python benchmarks/kernel_simd.py``. Prints one line per kernel; exit code 1 when a
kernel's fibre exp is not vectorised or a libm exp is called.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile

PROBE = """
import re
import numpy as np
from corneasim.materials import KernelMaterial, kernel_table
from corneasim.solver import elements as el
from corneasim.solver.elements import _fast_hex, _fast_quad

material = KernelMaterial(density=1e-9, c10=0.05, d1=0.02, prony_g=(0.3,), prony_tau=(0.01,),
                          fibre_k1=0.2, fibre_k2=70.0, fibre_kappa=0.1, fibre_angle=0.7)
quad = np.array([[1.0, 0.0], [1.2, 0.0], [1.2, 0.2], [1.0, 0.2]])
hexahedron = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1],
                       [0, 1, 1]], float)
for kind, points, frame in (("quad", quad, [1, 0, 0, 0, 0, 1]), ("hexahedron", hexahedron, [1, 0, 0, 0, 1, 0])):
    cells = np.arange(len(points))[None]
    es = el.prepare(points, cells, kind, [0], kernel_table([material]), fibre_frame=[frame])
    el.eval_internal_forces(es, np.zeros_like(points), 1e-6, np.ones(1, np.uint8), el.new_history(es),
                            np.zeros_like(points), np.zeros(1), np.zeros(3))
for name, module in (("quad", _fast_quad), ("hexahedron", _fast_hex)):
    ir = "".join(module._stress.inspect_llvm().values())
    print(name, ir.count("<8 x double>"), ir.count("<4 x double>"),
          len(re.findall(r"call [^\\n]*@llvm\\.floor\\.v[48]f64", ir)),
          len(re.findall(r"call [^\\n]*@exp\\(", ir)))
"""


def main() -> int:
    with tempfile.TemporaryDirectory(prefix="corneasim-simd-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        out = subprocess.run([sys.executable, "-c", PROBE], env=env, check=True, capture_output=True,
                             text=True).stdout
    failed = False
    for line in out.splitlines():
        name, wide8, wide4, vector_floor, libm_exp = line.split()
        ok = int(vector_floor) > 0 and int(libm_exp) == 0
        failed |= not ok
        print(f"{name:10s} stress pass: {wide8} <8 x double> and {wide4} <4 x double> operations, "
              f"{vector_floor} vector floor calls (fibre exp), {libm_exp} libm exp calls: "
              f"{'vectorised' if ok else 'NOT vectorised'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
