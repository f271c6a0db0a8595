"""Calibration of the trephine's eye support and cutting toughness on the robot experiment.

The two constants the trephination paper does not give and the built-in scenario calibrates
(docs/trephination.md, "Eye support" and "Cutting toughness"):

* the stiffness K of the eye's support (N/mm for the whole eye; the half model carries K/2),
  which with the eye wall's own stiffness sets the early slope of F_z (the experiment's
  0.08-0.1 N/mm up to 50 s);
* the cutting toughness G (N/mm of edge, ``instrument.contact.cutting_toughness``), the push
  per unit length at which the edge cuts (ring rule), which sets the plateau of F_z while
  the cornea is cut (the experiment's 0.09-0.10 N at 50-65 s).

Runs the scenario for each (K, G) of a grid, two processes at a time on one thread each,
and prints, per run, the validation against the experiment up to 65 s (F_z and F_c RMSE),
the peak F_z, the puncture times and the largest KE/IE before and after the cut through.
Writes ``OUT/calibration.csv`` (atomically, after each run).

    python validation/calibrate_trephine.py [--preset coarse] [--stiffness 0.08,0.11,0.15]
                                            [--toughness 0.0035,0.0042,0.005] [--out DIR]
"""

from __future__ import annotations

import argparse
import csv
import io
import os
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

COLUMNS = ["stiffness_N_per_mm", "toughness_N_per_mm", "fz_rmse_N", "fc_rmse_N", "peak_fz_N",
           "epithelium_s", "stroma_s", "cornea_s", "max_ke_ie_before_cut", "max_ke_ie", "wall_s"]


def one_run(preset: str, stiffness: float, toughness: float) -> dict:
    """The scenario with support stiffness ``stiffness`` (whole eye, N/mm) and ``toughness``."""
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    import numpy as np

    from corneasim.scenarios import load_scenario
    from corneasim.scenarios import simulate

    scenario, _, base = load_scenario("trephine", [f"mesh.preset={preset}", "solver.field_count=0",
                                                   f"instrument.contact.cutting_toughness={toughness}"])
    factor = scenario.instrument.symmetry_factor
    supports = [item.model_copy(update={"stiffness": stiffness / factor}) for item in scenario.supports]
    result = simulate(scenario.model_copy(update={"supports": supports}), base_dir=base, progress=False)
    summary, history = result.summary, result.history
    events = {item["event"]: item["time_s"] for item in summary["punctures"]}
    ratio = history["kinetic_energy_mJ"] / np.maximum(history["internal_energy_mJ"], 1e-30)
    after_contact = history["time_s"] >= 3.5
    before_cut = after_contact & (history["time_s"] < events.get("cornea", np.inf))
    validation = summary["validation"]
    return {"stiffness_N_per_mm": stiffness, "toughness_N_per_mm": toughness,
            "fz_rmse_N": validation["fz"]["rmse_N"], "fc_rmse_N": validation["fc"]["rmse_N"],
            "peak_fz_N": summary["peak_fz_N"], "epithelium_s": events.get("epithelium"),
            "stroma_s": events.get("stroma"), "cornea_s": events.get("cornea"),
            "max_ke_ie_before_cut": float(ratio[before_cut].max()) if before_cut.any() else None,
            "max_ke_ie": float(ratio[after_contact].max()), "wall_s": summary["run"]["wall_s"]}


def write_rows(path: Path, rows: list[dict]) -> None:
    """All rows so far to ``path`` (CSV), atomically."""
    from corneasim.output import atomic_write_text

    text = io.StringIO()
    writer = csv.DictWriter(text, COLUMNS)
    writer.writeheader()
    writer.writerows(rows)
    atomic_write_text(path, text.getvalue())


def numbers(text: str) -> list[float]:
    return [float(item) for item in text.split(",") if item]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--preset", default="coarse", help="mesh preset (coarse: about 65 s a run)")
    parser.add_argument("--stiffness", type=numbers, default=[0.08, 0.11, 0.15],
                        help="support stiffness of the whole eye, N/mm, comma-separated")
    parser.add_argument("--toughness", type=numbers, default=[0.0035, 0.0042, 0.005],
                        help="cutting toughness, N/mm, comma-separated")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=Path("validation/out/trephine-calibration"))
    arguments = parser.parse_args()
    arguments.out.mkdir(parents=True, exist_ok=True)
    grid = [(k, g) for k in arguments.stiffness for g in arguments.toughness]
    rows = []
    print("| K (N/mm) | G (N/mm) | Fz RMSE | Fc RMSE | peak Fz | epithelium / stroma / cornea (s) | "
          "KE/IE before cut / whole | wall |")
    print("|---|---|---|---|---|---|---|---|")
    with ProcessPoolExecutor(arguments.workers) as pool:
        futures = [pool.submit(one_run, arguments.preset, k, g) for k, g in grid]
        for future in futures:
            row = future.result()
            rows.append(row)
            write_rows(arguments.out / "calibration.csv", rows)
            times = " / ".join("-" if row[k] is None else f"{row[k]:.1f}"
                               for k in ("epithelium_s", "stroma_s", "cornea_s"))
            before = "-" if row["max_ke_ie_before_cut"] is None else f"{row['max_ke_ie_before_cut']:.3f}"
            print(f"| {row['stiffness_N_per_mm']:g} | {row['toughness_N_per_mm']:g} | {row['fz_rmse_N']:.4f} | "
                  f"{row['fc_rmse_N']:.4f} | {row['peak_fz_N']:.4f} | {times} | {before} / "
                  f"{row['max_ke_ie']:.3f} | {row['wall_s']:.0f} s |", flush=True)
    print("targets: Fz RMSE <= 0.020 N, Fc RMSE <= 0.0135 N, peak Fz within 15% of 0.1492 N "
          "(0.127-0.172 N), KE/IE < 0.05")


if __name__ == "__main__":
    main()
