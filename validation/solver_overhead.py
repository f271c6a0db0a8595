"""Per-step cost of the integrator around the element kernels, on a ~17,000-element model.

Times the element force kernel alone, then ``advance`` and a whole ``run`` (history and
checks every 100 steps, stable step every 100 steps) with the element force kernel replaced
by a no-op, which leaves exactly the integrator's own cost per step (node updates,
constraints, pressure, energy bookkeeping, Python calls, the periodic checks).
Timings on a shared machine are noisy: the median of several repetitions is printed.

    python validation/solver_overhead.py [--cells quad|hexahedron] [--steps 300]
"""

import argparse
import statistics
import time

import numpy as np

from corneasim.materials import KernelMaterial
from corneasim.mesh import Mesh
from corneasim.solver import Fixed, Pressure, advance, build_model, new_state, run
from corneasim.solver import elements as element_kernels
from corneasim.solver import SmoothStep

CORNEA = KernelMaterial(density=1.062e-9, c10=0.05, c01=0.0, d1=0.4, prony_g=(0.3, 0.2),
                        prony_tau=(0.1, 1.0))


def structured(cell_type, n):
    """A structured block: n x n/2 quads (axisymmetric) or n x n/4 x n/4 hexahedra."""
    if cell_type == "quad":
        nr, nz = n, n // 2
        r, z = np.linspace(0, 6, nr + 1), np.linspace(0, 1, nz + 1)
        R, Z = np.meshgrid(r, z, indexing="ij")
        points = np.column_stack([R.ravel(), Z.ravel()])
        index = np.arange(points.shape[0]).reshape(nr + 1, nz + 1)
        i, k = (a.ravel() for a in np.meshgrid(np.arange(nr), np.arange(nz), indexing="ij"))
        cells = np.column_stack([index[i, k], index[i + 1, k], index[i + 1, k + 1], index[i, k + 1]])
        top = [(e, 2) for e in range(len(cells)) if k[e] == nz - 1]
        return Mesh(points, cells.astype(np.int64), "quad", np.zeros(len(cells), np.int64), ["cornea"],
                    True, {"rim": np.flatnonzero(np.isclose(points[:, 0], 6))},
                    {}, {"posterior": np.array(top, np.int64)})
    nx, ny, nz = n, n // 4, n // 4
    x, y, z = np.linspace(0, 6, nx + 1), np.linspace(0, 3, ny + 1), np.linspace(0, 1, nz + 1)
    X, Y, Z = np.meshgrid(x, y, z, indexing="ij")
    points = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])
    index = np.arange(points.shape[0]).reshape(nx + 1, ny + 1, nz + 1)
    i, j, k = (a.ravel() for a in np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij"))
    cells = np.column_stack([index[i, j, k], index[i + 1, j, k], index[i + 1, j + 1, k], index[i, j + 1, k],
                             index[i, j, k + 1], index[i + 1, j, k + 1], index[i + 1, j + 1, k + 1],
                             index[i, j + 1, k + 1]])
    bottom = [(e, 0) for e in range(len(cells)) if k[e] == 0]
    return Mesh(points, cells.astype(np.int64), "hexahedron", np.zeros(len(cells), np.int64), ["cornea"],
                False, {"rim": np.flatnonzero(np.isclose(points[:, 0], 6))},
                {}, {"posterior": np.array(bottom, np.int64)})


def median_time(function, repeats, steps):
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(steps):
            function()
        samples.append((time.perf_counter() - start) / steps)
    return statistics.median(samples)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", choices=["quad", "hexahedron"], default="quad")
    parser.add_argument("--steps", type=int, default=100)
    arguments = parser.parse_args()
    n = 184 if arguments.cells == "quad" else 64
    mesh = structured(arguments.cells, n)
    components = "rz" if arguments.cells == "quad" else "xyz"
    # Zero pressure: the pressure kernel still runs every step, but with the element forces
    # replaced by a no-op any load would crush the model within a few thousand steps (the
    # stable-step floor of the solver then stops the run).
    model = build_model(mesh, {"cornea": CORNEA}, [Fixed("rim", components)],
                        [Pressure("posterior", 0.0, SmoothStep(0.0, 1e-3))])
    state = new_state(model)
    dt = model.stable_time_step()[0]
    advance(model, state, dt)
    forces = lambda: element_kernels.eval_internal_forces(  # noqa: E731
        model.elements, state.u, dt, state.alive, state.history, state.f_int,
        state.failure_ratio, state.energy_rates)
    step = lambda: advance(model, state, dt)  # noqa: E731
    steps = arguments.steps
    t_forces = median_time(forces, 3, steps)
    element_kernels.eval_internal_forces = lambda *arguments: None
    t_step = median_time(step, 3, steps)
    samples = []
    for _ in range(3):
        start = time.perf_counter()
        for _ in run(model, state, state.time + steps * dt * 0.999999, history_every=100,
                     check_every=100):
            pass
        samples.append((time.perf_counter() - start) / steps)
    t_run = statistics.median(samples)
    print(f"{arguments.cells}: {mesh.n_elements} elements, {mesh.n_nodes} nodes")
    print(f"element forces alone            {1e3 * t_forces:8.3f} ms/step")
    print(f"advance without element forces  {1e3 * t_step:8.3f} ms/step")
    print(f"run without element forces     {1e3 * t_run:8.3f} ms/step (checks, history, stable step)")
    print(f"35,000 steps: about {35000 * (t_forces + t_run):.0f} s, of which the integrator "
          f"{35000 * t_run:.0f} s")


if __name__ == "__main__":
    main()
