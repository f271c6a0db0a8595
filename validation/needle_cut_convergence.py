"""Mesh convergence of the needle insertion cut by radial cracks (docs/cutting.md).

Runs ``validation/needle_cut.toml`` (the needle scenario with ``[cut]``) at 1 mm/s on three
meshes refined 2x each along the needle's path (``needle-path-4x``, ``needle-path-2x``,
``needle-path``: 31, 15 and 7.7 um elements within 0.25 mm of the axis) and prints, per mesh,
the peak force over Table 2's 0.7 mm, the force at 0.35 and 0.7 mm, the puncture depths, the
RMSE against the 1 mm/s experiment (on the 3-term Gaussian fit, as ``corneasim run``), the
largest kinetic / internal energy ratio, the cracks' dissipation and the run's wall time;
then the relative change between the two finest meshes (target: below 5%).

Usage::

    python validation/needle_cut_convergence.py [--out results/validation-needle-cut]
                                                [--presets needle-path-4x needle-path-2x needle-path]
                                                [--set KEY=VALUE ...]

Writes each run's results folder under ``--out`` and ``convergence.json`` with the table.
"""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path

import numpy as np

import corneasim
from corneasim.output import write_json

SCENARIO = Path(__file__).resolve().parent / "needle_cut.toml"
PRESETS = ["needle-path-4x", "needle-path-2x", "needle-path"]
DEPTHS = (0.35, 0.7)
"""Depths (mm) at which the force is compared."""
EVENTS = ("epithelium", "stroma", "cornea")


def figures(result, wall: float) -> dict:
    """The compared figures of one run."""
    history, summary = result.history, result.summary
    depth, force = history["depth_mm"], history["force_N"]
    table = depth <= 0.7 + 1e-9
    row = {"status": summary["status"], "peak_force_N": float(force[table].max()) if table.any() else math.nan}
    for x in DEPTHS:
        row[f"force_{x:g}_mm_N"] = float(np.interp(x, depth, force)) if depth[-1] >= x - 1e-9 else math.nan
    punctures = {p["event"]: p["depth_mm"] for p in summary.get("punctures", [])}
    for name in EVENTS:
        row[f"{name}_depth_mm"] = float(punctures.get(name, math.nan))
    row["rmse_N"] = float((summary.get("validation") or {}).get("rmse_N", math.nan))
    row["max_kinetic_to_internal"] = float(summary["run"].get("max_kinetic_to_internal") or math.nan)
    row["dissipated_mJ"] = float(history["cut_dissipated_energy_mJ"][-1])
    row["deleted_elements"] = float(history["deleted_elements"][-1])
    row["elements"] = summary["run"]["elements"]
    row["wall_s"] = wall
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/validation-needle-cut"))
    parser.add_argument("--presets", nargs="+", default=PRESETS)
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    args = parser.parse_args()
    rows = {}
    for preset in args.presets:
        start = os.times().elapsed
        result = corneasim.run_scenario(str(SCENARIO), [f"mesh.preset={preset}", *args.overrides],
                                        out_dir=args.out / preset, overwrite=True)
        rows[preset] = figures(result, os.times().elapsed - start)
    keys = list(next(iter(rows.values())))
    print(f"{'figure':28s}" + "".join(f"{p:>16s}" for p in rows))
    for key in keys:
        print(f"{key:28s}" + "".join(f"{str(rows[p][key]) if isinstance(rows[p][key], str) else f'{rows[p][key]:.4g}':>16s}"
                                     for p in rows))
    change = {}
    if len(rows) >= 2:
        medium, finest = list(rows.values())[-2:]
        for key in keys:
            if key.endswith(("_N", "_mm")) and isinstance(finest[key], float):
                change[key] = abs(finest[key] - medium[key]) / abs(finest[key]) if finest[key] else math.nan
        print("change between the two finest meshes:")
        for key, value in change.items():
            print(f"  {key:26s} {100 * value:6.1f}%  {'ok' if value < 0.05 else 'above 5%'}")
    write_json(args.out / "convergence.json", {"rows": rows, "change_two_finest": change})


if __name__ == "__main__":
    main()
