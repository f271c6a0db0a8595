"""Study machinery against a plain loop: 8 coarse needle cases on 2 workers x 1 thread, and in sequence.

Targets: the study is at least 1.7x faster than the same 8 cases run one after the other in one
process (both on one Numba thread per case), and the study machinery (Dask scheduling, collecting
rows, rewriting the table) costs at most 0.5 s per case.

Measured and printed:

* ``sequential``: the 8 cases with :func:`corneasim.run_scenario` in this process, one thread,
  each into a results folder (as a study writes them);
* ``study``: :func:`corneasim.study` on a fresh 2-worker ``LocalCluster`` (cluster start-up
  timed apart), its wall time with and without the start-up;
* the speed-up sequential / study (without and with the start-up);
* the per-case overhead: the workers' time not spent inside the cases, (workers x study wall -
  sum of the cases' wall_s) / cases; it includes the idle worker at the end when the cases do
  not divide evenly, so it bounds the machinery's cost from above;
* the machinery alone: 8 empty jobs through the same engine, and one rewrite of the table.

The machine's load average is printed with the figures: on a shared machine both sides slow
down by whatever else runs, so compare figures of one run only.

Run: ``python benchmarks/study.py [--end-time 0.3] [--out DIR]``
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--end-time", type=float, default=0.3, help="Procedure time of each case, s.")
    parser.add_argument("--out", type=Path, help="Folder for the results (default: a temporary one).")
    arguments = parser.parse_args()
    out = arguments.out or Path(tempfile.mkdtemp(prefix="study-benchmark-"))

    import numpy as np

    import corneasim
    from corneasim.studies import table as results
    from corneasim.studies.case import case_overrides
    from corneasim.studies.engine import connect, execute

    spec = study_spec(arguments.end_time)
    load_before = os.getloadavg()
    start = time.perf_counter()
    for index, (rate, diameter) in enumerate((r, d) for r in RATES for d in DIAMETERS):
        overrides = case_overrides(spec["overrides"], {"instrument.motion.insertion.rate": rate,
                                                       "instrument.shape.diameter": diameter})
        corneasim.run_scenario("needle", overrides, out_dir=out / "sequential" / f"c{index:04d}")
    sequential = time.perf_counter() - start

    workers = 2
    start = time.perf_counter()
    with connect(workers=workers) as client:
        started = time.perf_counter()
        table = corneasim.study(spec, out=out / "study", client=client)
        study = time.perf_counter() - started
        empty_start = time.perf_counter()
        execute(client, {f"e{i}": (_nothing, (i,)) for i in range(8)}, lambda name, row: None,
                lambda name, message: {})
        empty = time.perf_counter() - empty_start
    startup = started - start
    write_start = time.perf_counter()
    results.write(out / "study", table)
    write = time.perf_counter() - write_start
    load_after = os.getloadavg()

    cases = len(table)
    busy = float(np.nansum(table["wall_s"]))
    print(f"load average before {load_before[0]:.2f} / {load_before[1]:.2f} / {load_before[2]:.2f}, "
          f"after {load_after[0]:.2f} / {load_after[1]:.2f} / {load_after[2]:.2f} (1 / 5 / 15 min; "
          f"{os.cpu_count()} cores)")
    print(f"{cases} coarse needle cases, end time {arguments.end_time} s, statuses "
          f"{table['status'].value_counts().to_dict()}")
    print(f"sequential, one process, 1 thread: {sequential:.1f} s")
    print(f"study, {workers} workers x 1 thread: {study:.1f} s (+ {startup:.1f} s cluster start-up)")
    print(f"speed-up: {sequential / study:.2f}x ({sequential / (study + startup):.2f}x with the start-up); "
          "target >= 1.7x")
    print(f"cases' own wall time: {busy:.1f} s in all; per-case overhead "
          f"(workers x wall - cases) / cases: {(workers * study - busy) / cases:.3f} s; target <= 0.5 s")
    print(f"machinery alone: 8 empty jobs {empty:.3f} s ({empty / 8:.4f} s a job), one table rewrite "
          f"{write:.4f} s")
    print(f"results: {out}")


if __name__ == "__main__":
    main()
