"""Plot a one-factor-at-a-time needle study: force-depth curves and puncture depths per factor.

Reads a results folder of ``validation/studies/needle_parametric.toml`` (or of any study of a
``list`` design whose cases each change one factor of a needle scenario, with the outputs
``force`` (a force-depth curve), ``peak_force_N`` and ``puncture_<i>_event`` /
``puncture_<i>_depth_mm``: the summary's punctures by list position, read by event name).
A factor is a key a case sets other than ``solver.end_time`` (which only keeps the depth the
same at each speed); the case that sets none is the reference, at the base
scenario's value of every factor. Writes into the study folder:

* ``force_depth.png``: the force against the depth for each level of each factor;
* ``puncture_depths.png``: the depths of the epithelium, stroma and whole-cornea punctures
  (top) and the peak force (bottom: of the force averaged over :data:`SMOOTHING` mm, and raw)
  against each factor;

and prints the table of the same figures.

Usage::

    python validation/needle_parametric_plots.py results/needle-parametric
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

MMHG_MPA = 1.33322e-4
"""One millimetre of mercury in MPa."""

LABELS = {"instrument.shape.diameter": ("needle diameter, mm", 1.0),
          "instrument.motion.insertion.rate": ("insertion speed, mm/s", 1.0),
          "pressures[0].pressure": ("intraocular pressure, mmHg", 1.0 / MMHG_MPA)}
"""Axis label and the factor from the key's unit to the label's of the known factors."""

EVENTS = ("epithelium", "stroma", "cornea")
"""Puncture events, in the order they happen."""

NOT_FACTORS = ("solver.end_time",)
"""Keys that cases set beside a factor without being one."""


def factor_levels(table, keys: list[str], reference: dict) -> dict[str, list[tuple[float, dict]]]:
    """{factor key: [(value in the key's unit, row), ...] sorted by value}, the reference row in each."""
    rows = table.to_dict(orient="records")
    factors = [key for key in keys if key not in NOT_FACTORS]

    def set_here(row, key):
        value = row.get(key)
        return value is not None and not (isinstance(value, float) and math.isnan(value))

    base = [row for row in rows if not any(set_here(row, key) for key in factors)]
    levels = {}
    for key in factors:
        mine = [(float(row[key]), row) for row in rows if set_here(row, key)]
        mine += [(float(reference[key]), row) for row in base]
        levels[key] = sorted(mine, key=lambda item: item[0])
    return levels


def puncture_depths(row: dict) -> dict[str, float]:
    """{event: depth mm} of a row (NaN for an event that did not happen)."""
    depths = {event: math.nan for event in EVENTS}
    for index in range(len(EVENTS)):
        name = row.get(f"puncture_{index}_event")
        if isinstance(name, str) and name in depths:
            depths[name] = float(row[f"puncture_{index}_depth_mm"])
    return depths


SMOOTHING = 0.02
"""Travel over which the force is averaged before its peak is taken, mm: the cut makes the raw
force jagged, and a single-sample spike would set the raw peak."""


def smoothed_peak(depth: np.ndarray, force: np.ndarray, window: float = SMOOTHING) -> float:
    """Largest running mean of the force over ``window`` mm of travel, N (NaN samples left out)."""
    spacing = float(np.mean(np.diff(depth)))
    width = max(1, int(round(window / spacing)) + 1)
    sampled = np.isfinite(force)
    if sampled.sum() < width:
        return math.nan
    values = force[sampled]
    return float(np.max(np.convolve(values, np.ones(width) / width, mode="valid")))


def label(key: str) -> tuple[str, float]:
    """Axis label and unit factor of a factor key."""
    return LABELS.get(key, (key, 1.0))


def plot(directory: Path) -> list[Path]:
    """Write the two figures into ``directory``; return their paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from corneasim.studies import table as results
    from corneasim.studies.designs import base_value, list_keys
    from corneasim.studies.outputs import abscissa
    from corneasim.studies.spec import read_study, scenario_reference

    study, base_dir, _ = read_study(directory / "study.toml")
    table = results.read(directory)
    if table is None:
        raise SystemExit(f"{directory}: no results.parquet (run the study first)")
    table = table[table["status"] == "completed"]
    scenario = scenario_reference(study, base_dir)
    keys = [key for key in list_keys(study) if key not in NOT_FACTORS]
    reference = {key: base_value(study, scenario, {}, key) for key in keys}
    levels = factor_levels(table, keys, reference)
    depth = abscissa(study.outputs["force"])
    count = max(1, len(levels))

    figure, axes = plt.subplots(1, count, figsize=(4.5 * count, 3.8), squeeze=False, sharey=True)
    for axis, (key, entries) in zip(axes[0], levels.items()):
        text, scale = label(key)
        for value, row in entries:
            axis.plot(depth, np.asarray(row["force"], dtype=float), label=f"{value * scale:.3g}")
        axis.set(xlabel="insertion depth, mm", title=text)
        axis.legend(title=text.split(",")[0], fontsize="small")
    axes[0][0].set_ylabel("force, N")
    figure.tight_layout()
    curves = directory / "force_depth.png"
    figure.savefig(curves, dpi=120)
    plt.close(figure)

    figure, axes = plt.subplots(2, count, figsize=(4.5 * count, 6.5), squeeze=False, sharex="col")
    for column, (key, entries) in enumerate(levels.items()):
        text, scale = label(key)
        x = [value * scale for value, _ in entries]
        for event in EVENTS:
            axes[0][column].plot(x, [puncture_depths(row)[event] for _, row in entries], "o-", label=event)
        axes[1][column].plot(x, [smoothed_peak(depth, np.asarray(row["force"], dtype=float)) for _, row in entries],
                             "s-k", label=f"over {SMOOTHING:g} mm")
        axes[1][column].plot(x, [float(row["peak_force_N"]) for _, row in entries], "^:", color="grey", label="raw")
        axes[1][column].legend(fontsize="small")
        axes[0][column].set(ylabel="puncture depth, mm", title=text)
        axes[1][column].set(xlabel=text, ylabel="peak force, N")
        axes[0][column].legend(fontsize="small")
    figure.tight_layout()
    depths = directory / "puncture_depths.png"
    figure.savefig(depths, dpi=120)
    plt.close(figure)
    print(summary(levels, depth))
    return [curves, depths]


def summary(levels: dict, depth: np.ndarray) -> str:
    """The figures per factor level as Markdown (``depth``: the force curve's abscissa, mm)."""
    lines = [f"| factor | value | peak force over {SMOOTHING:g} mm, N | raw peak N | epithelium mm | stroma mm "
             "| cornea mm | max KE/IE |", "|---|---|---|---|---|---|---|---|"]
    for key, entries in levels.items():
        text, scale = label(key)
        for value, row in entries:
            depths = puncture_depths(row)
            peak = smoothed_peak(depth, np.asarray(row["force"], dtype=float))
            lines.append(f"| {text} | {value * scale:.3g} | {peak:.3f} | {float(row['peak_force_N']):.3f} | "
                         + " | ".join(f"{depths[event]:.3f}" for event in EVENTS)
                         + f" | {float(row.get('max_kinetic_to_internal', math.nan)):.3f} |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory", type=Path, help="results folder of the study")
    for path in plot(parser.parse_args().directory):
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
