"""Do freshly compiled kernels compute what the same kernels loaded from Numba's cache compute?

Runs one internal-force evaluation of the needle scenario's coarse mesh (three calls at
growing random displacements, with the stable time steps and lumped masses) in two fresh
processes that share an empty ``NUMBA_CACHE_DIR``: the first compiles every kernel and
writes the cache, the second loads it. It prints the largest difference of each output.
All zero means the cache is transparent.

Found on 2026-11-24 (Numba 0.68, this 2-core host): the internal forces differed by
2.8e-14 N, while failure ratios, energy rates, stable steps and masses were identical, with
1 or 2 threads; the plain reference kernel (``prepare(..., kernel="reference")``, no
``parallel``) differed by 1.4e-14 N. The explicit runs amplify that round-off: the first coarse needle run after
a compile ended 7e-4 N away from every later (cached, mutually bit-identical) run.

Narrowed down (1 thread, forces assembled in a fixed order, so not
a summation-order effect): the inputs (packed geometry, material rows with the Prony
factors) are bit-identical, and the second process has no cache miss at all (it runs only
object code compiled by the first). Half of the nodes differ, by up to 2.8e-14 N, while the
failure ratios and energies agree bitwise. With ``NUMBA_OPT=0`` both processes agree
bitwise, so the difference comes from LLVM's optimisation (fastmath contraction and
reassociation) of the same source: the process that compiles evidently executes code that
differs from the object code it caches. Inlining the quad kernel's passes at the Numba IR
level (``inline="always"``) did not change it. The quad kernel and the force sum compiled
without the ``contract`` and ``reassoc`` fastmath flags agree bitwise, but the kernel runs
2.7x slower (76 instead of 28 ns per element-step on one thread: its lane sums no longer
vectorise); without ``contract`` alone they still differ (345 of 1,120 nodes) and run 4%
slower. Not fixed.

Usage::

    python validation/cache_determinism.py
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

EVALUATE = """
import sys
from pathlib import Path
import numpy as np
from corneasim.materials import KernelMaterial, kernel_table
from corneasim.scenarios import make_mesh
from corneasim.scenarios import load_scenario
from corneasim.solver import elements as el

scenario, _, _ = load_scenario("needle", ["mesh.preset=coarse"])
mesh = make_mesh(scenario, Path("."))
material = KernelMaterial(density=1.062e-9, c10=0.05, c01=0.02, c20=0.3, c30=0.5, d1=0.02,
                          prony_g=(0.3, 0.2, 0.1, 0.1), prony_tau=(1e-3, 1e-2, 1e-1, 1.0),
                          failure_criterion=1, failure_limit=5.0)
elements = el.prepare(mesh.points, mesh.cells, "quad", np.asarray(mesh.element_block),
                      kernel_table([material] * len(mesh.block_names)))
u = 1e-3 * np.random.default_rng(0).uniform(-1.0, 1.0, mesh.points.shape)
history = el.new_history(elements)
force, ratio, rates = np.zeros_like(u), np.zeros(mesh.n_elements), np.zeros(3)
alive = np.ones(mesh.n_elements, np.uint8)
forces = []
for k in range(3):
    el.eval_internal_forces(elements, u * (k + 1), 1e-7, alive, history, force, ratio, rates)
    forces.append(force.copy())
np.savez(sys.argv[1], internal_forces=np.array(forces), failure_ratio=ratio, energy_rates=rates,
         stable_time_steps=el.stable_time_steps(elements, u), lumped_masses=el.lumped_masses(elements))
"""


def main() -> int:
    with tempfile.TemporaryDirectory() as folder:
        environment = {**os.environ, "NUMBA_CACHE_DIR": str(Path(folder) / "cache")}
        outputs = []
        for label in ("compiled", "cached"):
            path = Path(folder) / f"{label}.npz"
            subprocess.run([sys.executable, "-c", EVALUATE, str(path)], env=environment, check=True)
            outputs.append(np.load(path))
        compiled, cached = outputs
        for name in compiled.files:
            print(f"{name:18s} largest difference compiled - cached: "
                  f"{np.abs(compiled[name] - cached[name]).max():.3g}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
