"""Where two threads start to pay for the element forces: a step on one and two threads
across mesh sizes.

For each element kind (axisymmetric quads, hexahedra) and mesh size, times the step a run
takes at the least: the element forces (``eval_internal_forces``) followed by a serial
node update v += dt (-f_int) / m, u += dt v, as ``solver.advance`` does it (serial, so the
worker thread falls asleep between the force calls, as it does in a run). The force
kernels are made to use both threads at every size (``PARALLEL_MIN_ELEMENTS`` set to 0 for
the measurement), one and two threads alternate in repeats of ``--steps`` steps, and the
median of the repeats is printed with the two-thread over one-thread speed-up, the
machine check of ``benchmarks/kernels.py`` (what two threads give a loop bound by the
vector units: 2.0 on two independent cores) and the load average. The smallest size from
which two threads are faster at every larger size is the kind's crossover: the
``PARALLEL_MIN_ELEMENTS`` of ``corneasim.solver.elements._schedule`` should not be below it on
the hosts the code runs on.

Usage::

    python benchmarks/threads.py [--sizes 1000,2000,3000,5000,8000,12000,20000]
                                 [--repeats 9] [--steps 200]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

import numba
import numpy as np
from numba import njit

from corneasim.materials import kernel_table
from corneasim.output import describe_platform
from corneasim.solver import elements as el
from corneasim.solver.elements import _schedule

HERE = Path(__file__).resolve().parent


@njit(cache=True, fastmath=True)
def serial_update(u, v, f_int, dof_inverse_mass, dt):
    """v += dt (-f_int) / m; u += dt v over the flat dofs, on the calling thread."""
    n = u.size
    u_flat, v_flat, f_flat = u.reshape(n), v.reshape(n), f_int.reshape(n)
    for k in range(n):
        v_flat[k] -= dt * f_flat[k] * dof_inverse_mass[k]
        u_flat[k] += dt * v_flat[k]


def mesh_of(kind, n_elements):
    """A mesh of about ``n_elements`` of ``kind`` from ``benchmarks/kernels.py``'s generators."""
    from kernels import hex_mesh, quad_mesh

    if kind == "quad":
        nz = max(2, round(math.sqrt(n_elements / 2)))
        return quad_mesh(nr=max(2, round(n_elements / nz)), nz=nz)
    side = max(2, round((n_elements / 0.9) ** (1 / 3)))
    return hex_mesh(n=(side, side, max(2, round(n_elements / side ** 2))))


def step_seconds(kind, points, cells, repeats, steps):
    """Median s per step on 1 and on 2 threads, the two alternating in each repeat."""
    from kernels import MATERIAL

    es = el.prepare(points, cells, kind, np.zeros(len(cells), np.int64), kernel_table([MATERIAL]))
    history = el.new_history(es)
    dof_inverse_mass = np.repeat(1.0 / el.lumped_masses(es), points.shape[1])
    dt = 0.5 * el.stable_time_steps(es, np.zeros_like(points)).min()
    u = 1e-3 * np.random.default_rng(1).uniform(-1, 1, points.shape) * np.ptp(points, axis=0).min()
    v = np.zeros_like(points)
    f = np.zeros_like(points)
    ratio = np.zeros(len(cells))
    rates = np.zeros(3)
    alive = np.ones(len(cells), np.uint8)
    samples = {1: [], 2: []}
    for repeat in range(repeats + 1):
        for threads in (1, 2) if repeat % 2 else (2, 1):
            numba.set_num_threads(threads)
            start = time.perf_counter()
            for _ in range(steps):
                el.eval_internal_forces(es, u, dt, alive, history, f, ratio, rates)
                serial_update(u, v, f, dof_inverse_mass, dt)
            if repeat:  # the first round warms the caches and the scratch rows
                samples[threads].append((time.perf_counter() - start) / steps)
    assert np.all(np.isfinite(f)) and np.all(np.isfinite(u))
    return float(np.median(samples[1])), float(np.median(samples[2]))


def crossover(rows):
    """Smallest size from which two threads beat one at every larger size, or None."""
    sizes = None
    for row in reversed(rows):
        if row["speedup"] <= 1.0:
            break
        sizes = row["elements"]
    return sizes


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1000,2000,3000,5000,8000,12000,20000")
    parser.add_argument("--repeats", type=int, default=9)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--kinds", default="quad,hexahedron")
    args = parser.parse_args(argv)
    if numba.config.NUMBA_NUM_THREADS < 2:
        raise SystemExit("needs NUMBA_NUM_THREADS >= 2")
    sys.path.insert(0, str(HERE))
    from kernels import thread_scaling

    check = thread_scaling()
    print(f"machine check: 2 threads give {check:.2f}x the vector throughput of 1 "
          f"(2.0 = two independent cores); load {os.getloadavg()[0]:.2f}")
    limits = dict(_schedule.PARALLEL_MIN_ELEMENTS)
    result = {"platform": describe_platform(), "machine_check": check, "kinds": {}}
    try:
        for kind in args.kinds.split(","):
            _schedule.PARALLEL_MIN_ELEMENTS[kind] = 0
            rows = []
            for size in (int(s) for s in args.sizes.split(",")):
                points, cells = mesh_of(kind, size)
                one, two = step_seconds(kind, points, cells, args.repeats, args.steps)
                rows.append(dict(elements=len(cells), one_thread_us=one * 1e6, two_threads_us=two * 1e6,
                                 speedup=one / two, load=os.getloadavg()[0]))
                print(f"{kind:10s} {len(cells):6d} elements: 1 thread {one * 1e6:8.1f} us, "
                      f"2 threads {two * 1e6:8.1f} us per step, {one / two:.2f}x; "
                      f"load {rows[-1]['load']:.2f}", flush=True)
            result["kinds"][kind] = dict(rows=rows, crossover=crossover(rows), limit=limits[kind])
            print(f"{kind}: two threads faster from {crossover(rows)} elements on "
                  f"(PARALLEL_MIN_ELEMENTS: {limits[kind]})")
    finally:
        _schedule.PARALLEL_MIN_ELEMENTS.update(limits)
    out = HERE / "out"
    out.mkdir(exist_ok=True)
    (out / "threads.json").write_text(json.dumps(result, indent=2))
    print(f"wrote {out / 'threads.json'}")


if __name__ == "__main__":
    main()
