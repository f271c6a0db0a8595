"""Kill runs of the coarse needle at random steps, resume them, and compare with an uninterrupted run.

Each trial starts ``corneasim run`` on the coarse needle (a short insertion at 5 mm/s, a
checkpoint every 200 steps), waits until the run has written a randomly drawn number of
history rows (a random step of the procedure), sends the signal, waits for the process to
end and runs ``corneasim run --resume`` on its folder. SIGINT and SIGTERM must stop the run
with exit code 130 and a summary ``interrupted``; SIGKILL stops it dead, possibly inside a
history row. Every resumed run must complete with ``history.csv`` and ``deletions.csv``
byte for byte those of the uninterrupted run, and with the preload's report in its summary.

The uninterrupted run is made twice and the two must agree (both load the element kernels
from one warm Numba cache, the condition for bitwise comparisons: docs/solver.md, "Round-off,
the host and the Numba cache").

Usage::

    python validation/fault_injection.py                 # 20 trials per signal
    python validation/fault_injection.py --trials 3 --signals SIGTERM,SIGKILL --seed 7

Prints a table: signal, trials, stopped as expected, resumed identical.
"""

from __future__ import annotations

import argparse
import json
import random
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

RUN = ["needle", "--preset", "coarse", "--speed", "5", "--no-progress",
       "--set", "preload.duration=0.02", "--set", "preload.damping=400",
       "--set", "solver.field_count=2", "--set", "solver.checkpoint_every=200"]
COMPARED = ("history.csv", "deletions.csv")


def corneasim(*arguments) -> list[str]:
    """The command line of ``corneasim ARGUMENTS`` with this interpreter."""
    return [sys.executable, "-m", "corneasim.cli.main", *arguments]


def uninterrupted(folder: Path, end_time: float) -> None:
    """One whole run into ``folder``."""
    done = subprocess.run(corneasim("run", *RUN, "--set", f"solver.end_time={end_time!r}", "--out", str(folder),
                                    "--overwrite"),
                          capture_output=True, text=True, timeout=1800)
    if done.returncode != 0:
        raise SystemExit(f"the uninterrupted run failed: {done.stderr.strip()}")


def rows(path: Path) -> int:
    """Complete data rows written so far (0 before the file exists)."""
    try:
        return max(path.read_bytes().count(b"\n") - 1, 0)
    except FileNotFoundError:
        return 0


def trial(folder: Path, number: int, target_rows: int, end_time: float) -> tuple[bool, bool, str]:
    """Stop a run with signal ``number`` once it has ``target_rows`` history rows; resume it.

    Returns (stopped as expected, resumed identical to the reference, a note)."""
    process = subprocess.Popen(corneasim("run", *RUN, "--set", f"solver.end_time={end_time!r}", "--out", str(folder)),
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    while process.poll() is None and rows(folder / "history.csv") < target_rows:
        time.sleep(0.002)
    process.send_signal(number)
    _, stderr = process.communicate(timeout=1800)
    if process.returncode == 0:
        return False, False, f"finished before the signal (row {target_rows})"
    if number == signal.SIGKILL:
        stopped = process.returncode == -signal.SIGKILL
    else:
        summary = json.loads((folder / "summary.json").read_text())
        stopped = process.returncode == 130 and summary["status"] == "interrupted" and "--resume" in stderr
    resumed = subprocess.run(corneasim("run", "--resume", str(folder), "--no-progress"), capture_output=True,
                             text=True, timeout=1800)
    if resumed.returncode != 0:
        return stopped, False, f"resume failed: {resumed.stderr.strip()}"
    summary = json.loads((folder / "summary.json").read_text())
    identical = summary["status"] == "completed" and summary["run"]["preload"] is not None and all(
        (folder / name).read_bytes() == (folder.parent / "reference" / name).read_bytes() for name in COMPARED)
    return stopped, identical, "" if identical else f"history differs (stopped at row {target_rows})"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trials", type=int, default=20, help="Trials per signal (default 20).")
    parser.add_argument("--signals", default="SIGINT,SIGTERM,SIGKILL", help="Comma-separated signal names.")
    parser.add_argument("--seed", type=int, default=1, help="Seed of the random stopping rows.")
    parser.add_argument("--end-time", type=float, default=0.1, help="Procedure time of each run, s.")
    parser.add_argument("--work", type=Path, help="Folder for the runs (default: a temporary folder).")
    arguments = parser.parse_args(argv)
    numbers = [signal.Signals[name.strip()] for name in arguments.signals.split(",")]
    work = arguments.work or Path(tempfile.mkdtemp(prefix="fault-injection-"))
    work.mkdir(parents=True, exist_ok=True)
    uninterrupted(work / "warm-up", arguments.end_time)
    uninterrupted(work / "reference", arguments.end_time)
    deterministic = all((work / "warm-up" / n).read_bytes() == (work / "reference" / n).read_bytes() for n in COMPARED)
    total_rows = rows(work / "reference" / "history.csv")
    print(f"reference: {total_rows} history rows; two uninterrupted runs identical: {deterministic}")
    generator = random.Random(arguments.seed)
    table = []
    for number in numbers:
        stopped = identical = 0
        for index in range(arguments.trials):
            folder = work / f"{number.name}-{index:02d}"
            ok_stop, ok_same, note = trial(folder, number, generator.randint(1, total_rows - 1), arguments.end_time)
            stopped += ok_stop
            identical += ok_same
            if note:
                print(f"  {folder.name}: {note}")
        table.append((number.name, arguments.trials, stopped, identical))
    print(f"{'signal':<8} {'trials':>6} {'stopped as expected':>20} {'resumed identical':>18}")
    for name, trials, stopped, identical in table:
        print(f"{name:<8} {trials:>6} {stopped:>20} {identical:>18}")
    print(f"runs in {work}")
    return 0 if deterministic and all(row[3] == row[1] for row in table) else 1


if __name__ == "__main__":
    raise SystemExit(main())
