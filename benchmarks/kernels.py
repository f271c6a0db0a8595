"""Element-kernel throughput: element-steps per second for the explicit step.

Times a whole explicit step without contact or output, as the solver runs it:
``eval_internal_forces`` (one-point forces, Flanagan-Belytschko hourglass, bulk viscosity,
visco-hyperelastic stress with a 4-term Prony update, failure ratio) followed by the
central-difference node update v += dt (f_ext - f_int) / m, u += dt v. About 20,000
elements of each kind: axisymmetric quads and hexahedra, a Yeoh-Mooney-Rivlin material
with 4 Prony terms and a von Mises failure ratio; with ``--material fibre`` the same matrix
with the two dispersed fibre families of the Holzapfel-Gasser-Ogden law (lamellae in the
r-theta plane of the quads, the x-y plane of the hexahedra).

Run: ``python benchmarks/kernels.py [--repeats 15] [--steps 40] [--material fibre]``. Prints element-steps
per second and ns per element-step (best and median over the repeats) on 1 and 2 threads
and writes the same to ``benchmarks/out/kernels.json``, with a machine check first: how
much 2 threads multiply the throughput of a simple vector loop (2.0 on two independent
cores; the 2-thread kernel figures cannot scale better than that). The machine may be
shared: the 1-minute load average is recorded with each figure, and the best of many short
repeats is the figure least disturbed by other jobs. Importing corneasim sets the OpenMP
wait policy (passive, with a short spin: ``corneasim/__init__.py``); a user's own
``OMP_WAIT_POLICY`` / ``GOMP_SPINCOUNT`` win.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numba
import numpy as np
from numba import njit, prange

from corneasim.materials import KernelMaterial, kernel_table
from corneasim.output import describe_platform
from corneasim.solver import elements as el

MATERIAL = KernelMaterial(density=1.062e-9, c10=0.05, c01=0.02, c20=0.3, c30=0.5, d1=0.02,
                          prony_g=(0.3, 0.2, 0.1, 0.1), prony_tau=(1e-3, 1e-2, 1e-1, 1.0),
                          failure_criterion=1, failure_limit=5.0)
FIBRE_MATERIAL = KernelMaterial(**{**MATERIAL.__dict__, "fibre_k1": 0.2, "fibre_k2": 70.0,
                                   "fibre_kappa": 0.1, "fibre_angle": np.pi / 4})
FIBRE_FRAMES = {"quad": [1.0, 0.0, 0.0, 0.0, 0.0, 1.0], "hexahedron": [1.0, 0.0, 0.0, 0.0, 1.0, 0.0]}


@njit(cache=True, fastmath=True, inline="always")
def _update_dofs(u, v, f_int, dof_inverse_mass, dt):
    """v += dt (-f_int) / m; u += dt v over one contiguous range of dofs."""
    for k in range(u.shape[0]):
        v[k] -= dt * f_int[k] * dof_inverse_mass[k]
        u[k] += dt * v[k]


@njit(cache=True, parallel=True, fastmath=True)
def central_difference_update(u, v, f_int, dof_inverse_mass, dt):
    """v += dt (-f_int) / m; u += dt v (no external force, no constraints), in place, over
    the flat dofs in 8 contiguous chunks (the solver's integrator is flat per dof too)."""
    n = u.size
    u_flat, v_flat, f_flat = u.reshape(n), v.reshape(n), f_int.reshape(n)
    for c in prange(8):
        k0 = c * n // 8
        k1 = (c + 1) * n // 8
        _update_dofs(u_flat[k0:k1], v_flat[k0:k1], f_flat[k0:k1], dof_inverse_mass[k0:k1], dt)


@njit(cache=True, parallel=True, fastmath=True)
def vector_throughput_probe(x, y, repeats):
    """Independent vectorisable multiply-adds, the same work on every thread (no memory
    traffic beyond L1): a machine check of how vector throughput scales with threads."""
    for t in prange(x.shape[0]):
        for _ in range(repeats):
            for i in range(x.shape[1]):
                y[t, i] = y[t, i] * x[t, i] + x[t, i]


def thread_scaling(repeats=5, work=200_000):
    """Throughput of 2 threads over 1 thread on ``vector_throughput_probe`` (2.0 for two
    independent cores; about 1 when the two logical CPUs share one core's vector units)."""
    seconds = {}
    for threads in (1, 2):
        numba.set_num_threads(threads)
        x = np.full((threads, 512), 0.5)
        y = np.zeros((threads, 512))
        vector_throughput_probe(x, y, 10)
        best = np.inf
        for _ in range(repeats):
            start = time.perf_counter()
            vector_throughput_probe(x, y, work)
            best = min(best, time.perf_counter() - start)
        seconds[threads] = best
    return 2.0 * seconds[1] / seconds[2]


def quad_mesh(nr=200, nz=100, width=5.0, height=0.55, seed=0):
    """Structured, slightly distorted (r, z) mesh with nodes on the axis."""
    r, z = np.meshgrid(np.linspace(0, width, nr + 1), np.linspace(0, height, nz + 1), indexing="ij")
    points = np.stack([r.ravel(), z.ravel()], axis=1)
    rng = np.random.default_rng(seed)
    inner = (points[:, 0] > 0) & (points[:, 0] < width) & (points[:, 1] > 0) & (points[:, 1] < height)
    points[inner] += 0.1 * min(width / nr, height / nz) * rng.uniform(-1, 1, (inner.sum(), 2))
    i, j = np.meshgrid(np.arange(nr), np.arange(nz), indexing="ij")
    n0 = (i * (nz + 1) + j).ravel()
    cells = np.stack([n0, n0 + nz + 1, n0 + nz + 2, n0 + 1], axis=1)
    return points, cells


def hex_mesh(n=(28, 28, 25), size=(6.0, 6.0, 0.55), seed=0):
    """Structured, slightly distorted brick of hexahedra (VTK order)."""
    axes = [np.linspace(0, s, k + 1) for s, k in zip(size, n)]
    x, y, z = np.meshgrid(*axes, indexing="ij")
    points = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    rng = np.random.default_rng(seed)
    h = min(s / k for s, k in zip(size, n))
    inner = np.all((points > 0) & (points < np.array(size)), axis=1)
    points[inner] += 0.1 * h * rng.uniform(-1, 1, (inner.sum(), 3))
    nx, ny, nz = n
    i, j, k = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij")
    node = lambda a, b, c: ((a * (ny + 1) + b) * (nz + 1) + c).ravel()  # noqa: E731
    cells = np.stack([node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k),
                      node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1),
                      node(i, j + 1, k + 1)], axis=1)
    return points, cells


def time_kind(kind, points, cells, threads, repeats, steps, fibre=False):
    """Best and median seconds per step over ``repeats`` runs of ``steps`` steps."""
    numba.set_num_threads(threads)
    frame = np.tile(FIBRE_FRAMES[kind], (len(cells), 1)) if fibre else None
    es = el.prepare(points, cells, kind, np.zeros(len(cells), np.int64),
                    kernel_table([FIBRE_MATERIAL if fibre else MATERIAL]), fibre_frame=frame)
    history = el.new_history(es)
    dof_inverse_mass = np.repeat(1.0 / el.lumped_masses(es), points.shape[1])
    dt = 0.5 * el.stable_time_steps(es, np.zeros_like(points)).min()
    rng = np.random.default_rng(1)
    u = 1e-3 * rng.uniform(-1, 1, points.shape) * np.ptp(points, axis=0).min()
    v = np.zeros_like(points)
    f = np.zeros_like(points)
    ratio = np.zeros(len(cells))
    rates = np.zeros(3)
    alive = np.ones(len(cells), np.uint8)

    def step():
        el.eval_internal_forces(es, u, dt, alive, history, f, ratio, rates)
        central_difference_update(u, v, f, dof_inverse_mass, dt)

    for _ in range(20):
        step()
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(steps):
            step()
        samples.append((time.perf_counter() - start) / steps)
    assert np.all(np.isfinite(f)) and np.all(np.isfinite(u))
    return min(samples), float(np.median(samples))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=15)
    parser.add_argument("--steps", type=int, default=40)
    parser.add_argument("--material", choices=("isotropic", "fibre"), default="isotropic")
    args = parser.parse_args(argv)
    scaling = None
    if numba.config.NUMBA_NUM_THREADS >= 2:
        scaling = thread_scaling()
        print(f"machine check: 2 threads give {scaling:.2f}x the vector throughput of 1 "
              "(2.0 = two independent cores)")
    meshes = {"quad": quad_mesh(), "hexahedron": hex_mesh()}
    results = []
    for kind, (points, cells) in meshes.items():
        for threads in (1, 2):
            if threads > numba.config.NUMBA_NUM_THREADS:
                continue
            best, median = time_kind(kind, points, cells, threads, args.repeats, args.steps,
                                     fibre=args.material == "fibre")
            n = len(cells)
            row = dict(kind=kind, material=args.material, elements=n, threads=threads,
                       element_steps_per_second_best=n / best,
                       element_steps_per_second_median=n / median,
                       ns_per_element_step_best=best / n * 1e9,
                       ns_per_element_step_median=median / n * 1e9,
                       load_average=os.getloadavg()[0])
            results.append(row)
            print(f"{kind:10s} {n:6d} elements {threads} thread(s): "
                  f"{row['element_steps_per_second_best']:.3g} element-steps/s best "
                  f"({row['ns_per_element_step_best']:.1f} ns), "
                  f"{row['element_steps_per_second_median']:.3g} median "
                  f"({row['ns_per_element_step_median']:.1f} ns); load {row['load_average']:.2f}")
    out = Path(__file__).parent / "out"
    out.mkdir(exist_ok=True)
    meta = dict(platform=describe_platform(), repeats=args.repeats, steps=args.steps,
                two_thread_vector_scaling=scaling)
    name = "kernels.json" if args.material == "isotropic" else "kernels-fibre.json"
    (out / name).write_text(json.dumps(dict(meta=meta, results=results), indent=2))
    print(f"wrote {out / name}")


if __name__ == "__main__":
    main()
