"""Study machinery against a plain loop: 8 coarse needle cases on 2 workers x 1 thread, and in sequence.

Targets: the study is at least 1.7x faster than the same 8 cases run one after the other in one
process (both on one Numba thread per case), and the study machinery (Dask scheduling, collecting
rows, rewriting the table) costs at most 0.5 s per case.

Measured and printed:

* ``sequential``: the 8 cases with :func:`corneasim.run_scenario` in this process, one thread,
  each into a results folder without plots (as a study writes them);
* ``study``: :func:`corneasim.study` on a 2-worker ``LocalCluster`` started once (its start-up
  timed apart);
* the speed-up sequential / study, per round: the two sides alternate (A B A B, ``--rounds``),
  since the load of a shared machine changes within minutes;
* the per-case overhead: the workers' time not spent inside the cases, (workers x study wall -
  sum of the cases' wall_s) / cases; it includes the idle worker at the end when the cases do
  not divide evenly, so it bounds the machinery's cost from above;
* the machinery alone: 8 empty jobs through the same engine, and one rewrite of the table.

The machine's load average is printed with the figures: on a shared machine both sides slow
down by whatever else runs, so compare figures of one run only.

Run: ``python benchmarks/study.py [--end-time 0.3] [--rounds 2] [--out DIR]``
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

RATES = [1.0, 2.0, 3.0, 5.0]
DIAMETERS = [0.15, 0.2]


def study_spec(end_time: float) -> dict:
    return {"scenario": "needle", "overrides": {"mesh.preset": "coarse", "solver.end_time": end_time,
                                                "solver.field_count": 0},
            "design": {"kind": "grid"},
            "parameters": {"instrument.motion.insertion.rate": RATES, "instrument.shape.diameter": DIAMETERS},
            "outputs": {"peak_force_N": "peak_force_N"}}


def _nothing(index: int) -> dict:
    return {"status": "completed", "error": "", "wall_s": 0.0, "worker": ""}


def sequential_run(spec: dict, out: Path) -> float:
    """Wall time of the 8 cases one after the other in this process, s."""
    import corneasim
    from corneasim.studies.case import case_overrides

    start = time.perf_counter()
    for index, (rate, diameter) in enumerate((r, d) for r in RATES for d in DIAMETERS):
        overrides = case_overrides(spec["overrides"], {"instrument.motion.insertion.rate": rate,
                                                       "instrument.shape.diameter": diameter})
        corneasim.run_scenario("needle", overrides, out_dir=out / f"c{index:04d}", plots=False)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--end-time", type=float, default=0.3, help="Procedure time of each case, s.")
    parser.add_argument("--rounds", type=int, default=2, help="Rounds of (sequential, study), interleaved.")
    parser.add_argument("--out", type=Path, help="Folder for the results (default: a temporary one).")
    arguments = parser.parse_args()
    out = arguments.out or Path(tempfile.mkdtemp(prefix="study-benchmark-"))

    import numpy as np

    import corneasim
    from corneasim.studies import table as results
    from corneasim.studies.engine import connect, execute

    spec = study_spec(arguments.end_time)
    workers = 2
    print(f"{os.cpu_count()} cores; {workers} workers x 1 thread against one process on 1 thread; "
          f"8 coarse needle cases, end time {arguments.end_time} s; A B rounds interleaved")
    start = time.perf_counter()
    with connect(workers=workers) as client:
        startup = time.perf_counter() - start
        speedups, overheads = [], []
        for round_ in range(arguments.rounds):
            load = os.getloadavg()[0]
            sequential = sequential_run(spec, out / f"sequential-{round_}")
            started = time.perf_counter()
            table = corneasim.study(spec, out=out / f"study-{round_}", client=client)
            study = time.perf_counter() - started
            busy = float(np.nansum(table["wall_s"]))
            overhead = (workers * study - busy) / len(table)
            speedups.append(sequential / study)
            overheads.append(overhead)
            print(f"round {round_ + 1}: load average {load:.2f} -> {os.getloadavg()[0]:.2f}; sequential "
                  f"{sequential:.1f} s, study {study:.1f} s: speed-up {sequential / study:.2f}x; cases "
                  f"{busy:.1f} s in all, workers' time outside them {overhead:.2f} s a case; statuses "
                  f"{table['status'].value_counts().to_dict()}")
        empty_start = time.perf_counter()
        execute(client, {f"e{i}": (_nothing, (i,)) for i in range(8)}, lambda name, row: None,
                lambda name, message: {})
        empty = time.perf_counter() - empty_start
    write_start = time.perf_counter()
    results.write(out / "study-0", table)
    write = time.perf_counter() - write_start
    print(f"cluster start-up {startup:.1f} s (once, not in the study times)")
    print(f"speed-up: median {np.median(speedups):.2f}x, best {max(speedups):.2f}x; target >= 1.7x")
    print(f"workers' time outside the cases (scheduling, collecting, the table, idle tail): median "
          f"{np.median(overheads):.2f} s a case; target <= 0.5 s")
    print(f"machinery alone: 8 empty jobs {empty:.3f} s ({empty / 8:.4f} s a job), one table rewrite "
          f"{write:.4f} s")
    print(f"results: {out}")


if __name__ == "__main__":
    main()
