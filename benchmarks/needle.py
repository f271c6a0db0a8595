"""Wall time of ``corneasim run needle`` against its targets: default <= 30 s, coarse <= 5 s.

Runs the command as a user does (a fresh process, start-up and mesh included, Numba cache
warm: a short warm-up run first) for the default and the coarse preset at 1 mm/s, reads
``element_steps_per_s`` from each run's ``summary.json`` and compares it with the
axisymmetric (quad) kernel figure of ``benchmarks/out/kernels.json`` (written by
``benchmarks/kernels.py``) at the same thread count: the target is at least half of it.
Writes ``benchmarks/out/needle.json`` and prints a table. Timings on a shared machine
are noisy; the load average is recorded with each case.

The table gives each run's start-up too (``run.startup_s`` of ``summary.json``: the process's
start to the end of the first time step: imports, scenario, mesh, model, the kernels loaded
from the Numba cache).

Two more figures per preset:

* **reused preload**: the same run again, started from the first run's settled preload
  (``--preload-from``), as a second run of the same eye is (another speed, a study);
* **floor**: the wall time the run could not go below on this machine with its step count,
  if everything but the element forces cost nothing: the start-up and finish of a run of a
  few steps (imports, mesh, model, Numba cache, summary, plots) plus the run's steps times
  the element-force evaluation of the same model timed in a tight loop (threads kept busy
  between calls, so no thread wake-up), in this process;
* **floor with node updates**: the same with the central-difference node updates added to
  each step (velocity and displacement, then acceleration, as ``solver.advance`` does them,
  without contact, pressure, deletion checks or output): what a step of an explicit solver
  costs at the least, its worker thread waking after the serial node updates included.

Usage::

    python benchmarks/needle.py [--presets default,coarse] [--threads N] [--repeats 1]
                                [--set KEY=VALUE ...]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
TARGET_WALL_S = {"default": 30.0, "coarse": 5.0}
"""Wall-time targets of the needle runs, start-up included, s."""


def corneasim_run(preset: str, folder: Path, threads: int | None, overrides: list[str],
                  preload_from: Path | None = None) -> float:
    """Run ``corneasim run needle`` in a fresh process; return its wall time, s."""
    command = [sys.executable, "-m", "corneasim.cli.main", "run", "needle", "--out", str(folder),
               "--set", f"mesh.preset={preset}"]
    if preload_from is not None:
        command += ["--preload-from", str(preload_from)]
    for override in ([f"solver.threads={threads}"] if threads else []) + overrides:
        command += ["--set", override]
    started = time.perf_counter()
    completed = subprocess.run(command, capture_output=True, text=True)
    wall = time.perf_counter() - started
    if completed.returncode != 0:
        raise SystemExit(f"benchmark run failed ({preset}): {completed.stderr.strip()}")
    return wall


def kernel_figure(threads: int) -> float | None:
    """Best quad element-steps per second of the kernel benchmark at ``threads`` threads."""
    path = HERE / "out" / "kernels.json"
    if not path.exists():
        return None
    rows = [row for row in json.loads(path.read_text())["results"]
            if row["kind"] == "quad" and row["threads"] == threads]
    return max((row["element_steps_per_second_best"] for row in rows), default=None)


def minimal_step_seconds(preset: str, threads: int | None, overrides: list[str],
                         calls: int = 300) -> tuple[float, float]:
    """Median time of one element-force evaluation of the run's model in a tight loop, and of
    one step of element forces and node updates, s (blocks of the two alternate, so that both
    see the host in the same state)."""
    import numba

    from corneasim.scenarios import build
    from corneasim.scenarios import load_scenario
    from corneasim.scenarios._runner import _set_threads
    from corneasim.solver import elements as element_kernels
    from corneasim.solver import new_state
    from corneasim.solver._integrate import NO_REFERENCE, integrate_acceleration, integrate_velocity_displacement

    scenario, _, base = load_scenario("needle", [f"mesh.preset={preset}", *overrides])
    setup = build(scenario, base)
    model = setup.model
    before = numba.get_num_threads()
    _set_threads(threads, model.n_elements)
    state = new_state(model)
    state.u[:] = 1e-4 * np.random.default_rng(0).standard_normal(state.u.shape)  # a deformed eye
    dt = model.target_time_step or 1e-6

    def forces():
        element_kernels.eval_internal_forces(model.elements, state.u, dt, state.alive, state.history,
                                             state.f_int, state.failure_ratio, state.energy_rates)

    def step():
        integrate_velocity_displacement(
            state.u, state.v, state.a, state.f_int, state.f_ext, model.dof_mass, dt, dt, 0.0,
            model.constraint_dof, model.constraint_kind, model.constraint_value, model.constraint_amplitude,
            model.amplitude_table, state.node_active, state.energies)
        forces()
        integrate_acceleration(state.v, state.f_int, state.f_ext, model.dof_inverse_mass, model.dof_mass, dt,
                               0.0, state.energy_rates, state.a, state.energies, NO_REFERENCE)

    samples = {forces: [], step: []}
    for _ in range(6):
        for call in (forces, step):
            for _ in range(calls // 3):
                started = time.perf_counter()
                call()
                samples[call].append(time.perf_counter() - started)
    numba.set_num_threads(before)
    return tuple(float(np.median(samples[call][calls // 3:])) for call in (forces, step))


def floor(preset: str, threads: int | None, overrides: list[str], steps: int) -> dict:
    """Start-up and finish of a run of a few steps plus ``steps`` element-force evaluations,
    and plus ``steps`` steps of element forces and node updates, s."""
    with tempfile.TemporaryDirectory() as folder:
        overhead = corneasim_run(preset, Path(folder), threads,
                                 [*overrides, "preload.duration=2e-4", "solver.end_time=2e-4"])
    per_step, per_step_with_nodes = minimal_step_seconds(preset, threads, overrides)
    return {"floor_wall_s": overhead + steps * per_step, "floor_start_and_finish_s": overhead,
            "floor_element_forces_s_per_step": per_step,
            "floor_with_node_updates_wall_s": overhead + steps * per_step_with_nodes,
            "floor_with_node_updates_s_per_step": per_step_with_nodes}


def measure(preset: str, threads: int | None, repeats: int, overrides: list[str]) -> dict:
    """Best of ``repeats`` runs of one preset, the best of the same runs from the first one's
    settled preload, and the floor."""
    best = None
    reused = None
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as folder:
            load = os.getloadavg()[0]
            wall = corneasim_run(preset, Path(folder) / "own", threads, overrides)
            run = json.loads((Path(folder) / "own" / "summary.json").read_text())["run"]
            wall_reused = corneasim_run(preset, Path(folder) / "reused", threads, overrides,
                                        preload_from=Path(folder) / "own")
        row = {"preset": preset, "wall_s": wall, "solver_wall_s": run["wall_s"], "startup_s": run.get("startup_s"),
               "elements": run["elements"],
               "steps": run["steps"], "element_steps_per_s": run["element_steps_per_s"],
               "load_average": load, "platform": run.get("platform")}
        if best is None or wall < best["wall_s"]:
            best = row
        reused = wall_reused if reused is None else min(reused, wall_reused)
    best.update(wall_s_preload_reused=reused, **floor(preset, threads, overrides, best["steps"]))
    used = threads or (int(os.environ.get("NUMBA_NUM_THREADS", os.cpu_count() or 1))
                       if best["elements"] >= 5000 else 1)
    kernel = kernel_figure(used)
    best.update(threads=used, target_wall_s=TARGET_WALL_S.get(preset), kernel_element_steps_per_s=kernel,
                fraction_of_kernel=best["element_steps_per_s"] / kernel if kernel else None)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--presets", default="default,coarse")
    parser.add_argument("--threads", type=int, help="solver.threads (default: the scenario's rule)")
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--out", type=Path, default=HERE / "out" / "needle.json")
    arguments = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:  # warm the Numba cache
        corneasim_run("coarse", Path(folder), arguments.threads, ["solver.end_time=0.01"])
    rows = [measure(preset, arguments.threads, arguments.repeats, arguments.overrides)
            for preset in arguments.presets.split(",")]
    arguments.out.parent.mkdir(parents=True, exist_ok=True)
    arguments.out.write_text(json.dumps({"overrides": arguments.overrides, "cpu_count": os.cpu_count(),
                                         "rows": rows}, indent=2) + "\n")
    print("| preset | elements | steps | threads | wall s (command) | start-up s | target s | preload reused s "
          "| floor s (start-up and finish + steps x forces) | with node updates s | element-steps/s | of kernel "
          "| load |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for row in rows:
        fraction = f"{row['fraction_of_kernel']:.2f}" if row["fraction_of_kernel"] else "-"
        startup = f"{row['startup_s']:.2f}" if row["startup_s"] is not None else "-"
        print(f"| {row['preset']} | {row['elements']} | {row['steps']} | {row['threads']} | {row['wall_s']:.1f} "
              f"| {startup} | {row['target_wall_s']:g} | {row['wall_s_preload_reused']:.1f} "
              f"| {row['floor_wall_s']:.1f} "
              f"({row['floor_start_and_finish_s']:.1f} + {row['steps']} x "
              f"{1e6 * row['floor_element_forces_s_per_step']:.0f} us) | {row['floor_with_node_updates_wall_s']:.1f} "
              f"({1e6 * row['floor_with_node_updates_s_per_step']:.0f} us a step) | {row['element_steps_per_s']:.3g} "
              f"| {fraction} | {row['load_average']:.1f} |")


if __name__ == "__main__":
    main()
