"""Wall time of the trephine scenario (targets: umbrella 100 s process <= 10 min, coarse <= 60 s).

Runs the built-in ``trephine`` scenario (its defaults: mass scaling, time scaling, preload)
with the coarse preset and with the default umbrella mesh, and writes
``benchmarks/out/trephine.json`` with, per case: elements, steps, wall time, element-steps
per second, the largest kinetic/internal energy ratio after contact (quasi-static check,
target < 5%), the added mass, the physical time simulated, and the run's peak F_z, puncture
events and validation against the experiment (so that one run gives both the speed and the
validation figures), and its start-up (``run.startup_s``: the cases run in this process, so
the first one's counts from the process's start, the benchmark's own imports included, and a
later one's from the end of the case before it). ``--end-time`` shortens the
process (the wall time of the full 100 s is then extrapolated in proportion to the
procedure time, preload and set-up included, so on the high side, and reported as such).

Usage::

    NUMBA_NUM_THREADS=1 python benchmarks/trephine.py [--cases coarse,umbrella] [--end-time S]
                                                      [--threads N] [--set KEY=VALUE ...]
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

CASES = {"coarse": ["mesh.preset=coarse"], "umbrella": ["mesh.preset=default", "mesh.strategy=umbrella"]}
TARGET_WALL_S = {"coarse": 60.0, "umbrella": 600.0}
"""Wall-time targets of the trephine runs for the whole 100 s process, s."""


def measure(case: str, end_time: float | None, threads: int | None, overrides: list[str]) -> dict:
    """Run one case; return its figures."""
    import corneasim
    from corneasim.scenarios import load_scenario

    extra = list(CASES[case]) + ([f"solver.end_time={end_time}"] if end_time else [])
    extra += [f"solver.threads={threads}"] if threads else []
    extra += ["solver.field_count=0", *overrides]
    scenario, _, _ = load_scenario("trephine", extra)
    full_end = load_scenario("trephine")[0].solver.end_time
    result = corneasim.run_scenario("trephine", extra, progress=False)
    run = result.summary["run"]
    simulated = scenario.solver.end_time
    wall_full = run["wall_s"] * full_end / simulated
    return {"case": case, "elements": run["elements"], "simulated_s": simulated, "steps": run["steps"],
            "wall_s": run["wall_s"], "startup_s": run.get("startup_s"), "wall_100s_s": wall_full, "extrapolated": simulated < full_end,
            "target_wall_s": TARGET_WALL_S[case], "element_steps_per_s": run["element_steps_per_s"],
            "max_kinetic_to_internal": run["max_kinetic_to_internal"],
            "added_mass_fraction": run["added_mass_fraction"], "time_scaling": run["time_scaling"],
            "numba_threads": os.environ.get("NUMBA_NUM_THREADS"), "status": result.summary["status"],
            "peak_fz_N": result.summary["peak_fz_N"], "validation": result.summary["validation"],
            "punctures": result.summary["punctures"], "platform": run.get("platform")}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", default="coarse,umbrella")
    parser.add_argument("--end-time", type=float, help="procedure time to run, s (default: the scenario's)")
    parser.add_argument("--threads", type=int)
    parser.add_argument("--set", dest="overrides", action="append", default=[])
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "out" / "trephine.json")
    arguments = parser.parse_args()
    rows = [measure(case, arguments.end_time, arguments.threads, arguments.overrides)
            for case in arguments.cases.split(",")]
    arguments.out.parent.mkdir(parents=True, exist_ok=True)
    arguments.out.write_text(json.dumps(rows, indent=2) + "\n")
    print("| case | elements | simulated s | steps | wall s | start-up s | wall for 100 s | target | KE/IE max "
          "| peak Fz | Fz / Fc RMSE to 65 s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for row in rows:
        note = " (extrapolated)" if row["extrapolated"] else ""
        validation = row["validation"] or {}
        rmse = " / ".join(f"{validation[k]['rmse_N']:.4f}" if k in validation else "-" for k in ("fz", "fc"))
        startup = f"{row['startup_s']:.2f}" if row["startup_s"] is not None else "-"
        print(f"| {row['case']} | {row['elements']} | {row['simulated_s']:g} | {row['steps']} | {row['wall_s']:.1f} "
              f"| {startup} | {row['wall_100s_s']:.0f}{note} | {row['target_wall_s']:.0f} | "
              f"{100 * row['max_kinetic_to_internal']:.2f}% | {row['peak_fz_N']:.4f} | {rmse} N |")


if __name__ == "__main__":
    main()
