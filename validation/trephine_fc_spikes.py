"""Single-sample spikes of the trephine's rotary cutting force F_c in one or more results folders.

The validation compares the experiment's F_c with the largest |F_c| of the simulation over one
rotation period, so one history sample far above its neighbours holds that envelope up for a
whole period (``docs/trephination.md``, "Edge contact"). This counts such samples in each
folder's ``history.csv``: |F_c| above ``--factor`` times the median |F_c| of the samples
within ``--window`` seconds around it and above ``--floor`` N. It prints, per folder, their
number from ``--start`` to 65 s (Table 2's last time) and to the end, the largest of them, and
the median |F_c| from ``--start`` to 65 s. Nothing is written.

Usage::

    corneasim run trephine --out DIR
    python validation/trephine_fc_spikes.py DIR [DIR ...] [--start 50] [--factor 2.5]
"""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

import numpy as np

TABLE_END_S = 65.0
"""Last time of the trephination paper's Table 2, s."""


def spikes(time: np.ndarray, fc: np.ndarray, window: float, factor: float, floor: float) -> np.ndarray:
    """Indices of the samples whose |F_c| (N) exceeds ``factor`` times the median |F_c| of the
    samples within ``window`` (s) either side of it, and ``floor`` (N)."""
    magnitude = np.abs(fc)
    lo = np.searchsorted(time, time - window)
    hi = np.searchsorted(time, time + window, side="right")
    local = np.array([np.median(magnitude[a:b]) for a, b in zip(lo, hi)])
    return np.flatnonzero((magnitude > factor * local) & (magnitude > floor))


def read_history(folder: Path) -> tuple[np.ndarray, np.ndarray]:
    """Procedure time (s) and F_c (N) of a trephine results folder; ValueError naming the
    folder when it has no trephine history."""
    path = folder / "history.csv"
    if not path.is_file():
        raise ValueError(f"{folder}: no history.csv (expected a trephine results folder)")
    with open(path, newline="") as stream:
        rows = list(csv.DictReader(stream))
    if not rows or "fc_N" not in rows[0]:
        raise ValueError(f"{path}: no fc_N column (expected a trephine run's history)")
    return (np.array([float(row["time_s"]) for row in rows]), np.array([float(row["fc_N"]) for row in rows]))


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folders", type=Path, nargs="+", help="trephine results folders")
    parser.add_argument("--start", type=float, default=50.0, help="procedure time to count from, s")
    parser.add_argument("--window", type=float, default=0.5, help="half width of the median's window, s")
    parser.add_argument("--factor", type=float, default=2.5, help="spike: |F_c| over this many local medians")
    parser.add_argument("--floor", type=float, default=0.04, help="spike: |F_c| above this, N")
    args = parser.parse_args(argv)
    try:
        histories = [read_history(folder) for folder in args.folders]
    except ValueError as error:
        print(f"error: {error}", file=sys.stderr)
        raise SystemExit(2) from None
    print("| folder | spikes to 65 s | spikes to the end | largest spike N | median abs(F_c) to 65 s N |")
    print("|---|---|---|---|---|")
    for folder, (time, fc) in zip(args.folders, histories):
        found = spikes(time, fc, args.window, args.factor, args.floor)
        found = found[time[found] >= args.start]
        early = found[time[found] <= TABLE_END_S]
        band = (time >= args.start) & (time <= TABLE_END_S)
        largest = f"{np.abs(fc[found]).max():.4f}" if found.size else "-"
        median = f"{np.median(np.abs(fc[band])):.4f}" if band.any() else "-"
        print(f"| {folder} | {early.size} | {found.size} | {largest} | {median} |")


if __name__ == "__main__":
    main()
