"""Calibration of the cut needle insertion on the 1 mm/s experiment, every constant inside its range.

Runs ``validation/needle_cut.toml`` (the radial-crack cut, HGO stroma, docs/cutting.md) on a
grid of the constants that the published ranges leave open (docs/materials.md, "Published
ranges"), scores each run by its RMSE against the needle paper's 1 mm/s experiment (Table 2,
0-0.7 mm, on the 3-term Gaussian fit as ``corneasim run``), and predicts 5 mm/s with the best
constants. The grid:

* ``k1`` (MPa) and ``k2`` of the stroma's fibres: no verified range of their own; ``k1`` is
  bounded by the in-plane modulus 0.3-1.33 MPa along a family, about 3 mu + 4 k1 (1 - 3 kappa)^2
  at small strain (``stroma.in_plane_modulus``), and a combination outside is skipped;
* the stroma's cut toughness G_c (N/mm, ``stroma.toughness``, 0.2-5.4);
* the Coulomb coefficient of the shaft (``contact.friction_coefficient``, 0.006-0.36).

The ground matter (mu = 0.005 MPa), dispersion, strengths and the epithelium stay at the
scenario's values. Each grid point writes its stroma file and results folder under ``--out``.

Usage::

    python validation/needle_cut_calibration.py [--out results/calibrate-needle-cut]
        [--preset needle-path-4x] [--k1 0.27 0.6] [--k2 59 300] [--toughness 0.3 2.5]
        [--friction 0.2 0.36] [--no-prediction]

Prints one row per grid point (RMSE, peak force, force at 0.35 and 0.7 mm, puncture depths,
largest kinetic / internal energy), the best point, and its 5 mm/s prediction; writes
``calibration.json``.
"""

from __future__ import annotations

import argparse
import itertools
import math
import os
import re
from pathlib import Path

import numpy as np

import corneasim
from corneasim.materials import published_ranges
from corneasim.output import write_json
from corneasim.output._run_report import read_results
from corneasim.scenarios._needle import speed_overrides
from corneasim.solver._checks import SimulationError

HERE = Path(__file__).resolve().parent
SCENARIO = HERE / "needle_cut.toml"
STROMA = HERE / "materials" / "needle-cut-stroma.toml"
EVENTS = ("epithelium", "stroma", "cornea")


def stroma_constants(text: str) -> dict[str, float]:
    """c10, k1, k2 and kappa of a stroma material file's ``[hyperelastic]`` table."""
    return {key: float(re.search(rf"^{key} = ([0-9.eE+-]+)", text, re.M).group(1))
                for key in ("c10", "k1", "k2", "kappa")}


def stroma_file(folder: Path, k1: float, k2: float) -> Path:
    """The scenario's stroma with k1 (MPa) and k2 replaced, written into ``folder``."""
    text = STROMA.read_text()
    text = re.sub(r"^k1 = [0-9.eE+-]+", f"k1 = {k1!r}", text, flags=re.M)
    text = re.sub(r"^k2 = [0-9.eE+-]+", f"k2 = {k2!r}", text, flags=re.M)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "stroma.toml"
    path.write_text(text)
    return path


def in_range(k1: float, toughness: float, friction: float) -> str | None:
    """The first constant outside its published range (a one-line reason), or None."""
    ranges = published_ranges()
    base = stroma_constants(STROMA.read_text())
    modulus = 6.0 * base["c10"] + 4.0 * k1 * (1.0 - 3.0 * base["kappa"]) ** 2
    for key, value in (("stroma.in_plane_modulus", modulus), ("stroma.toughness", toughness),
                       ("contact.friction_coefficient", friction)):
        r = ranges[key]
        if not r.low <= value <= r.high:
            return f"{key} = {value:.4g} outside {r.low:g}..{r.high:g} {r.unit}"
    return None


def run_point(folder: Path, overrides: list[str]) -> dict:
    """Run the scenario with ``overrides`` into ``folder``; its figures (a failed run's up to the failure)."""
    start = os.times().elapsed
    try:
        corneasim.run_scenario(str(SCENARIO), overrides, out_dir=folder, overwrite=True)
    except SimulationError as error:
        print(f"  {folder.name}: {error}")
    _, summary, history = read_results(folder)
    depth = np.asarray(history["depth_mm"], dtype=float)
    force = np.asarray(history["force_N"], dtype=float)
    punctures = {p["event"]: p["depth_mm"] for p in summary.get("punctures", [])}
    row = {"status": summary["status"],
           "rmse_N": float((summary.get("validation") or {}).get("rmse_N", math.nan)),
           "peak_force_N": float(force[depth <= 0.7 + 1e-9].max()),
           "max_kinetic_to_internal": float(summary["run"].get("max_kinetic_to_internal") or math.nan),
           "wall_s": os.times().elapsed - start}
    for x in (0.35, 0.7):
        row[f"force_{x:g}_mm_N"] = float(np.interp(x, depth, force)) if depth[-1] >= x - 1e-9 else math.nan
    for name in EVENTS:
        row[f"{name}_depth_mm"] = float(punctures.get(name, math.nan))
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/calibrate-needle-cut"))
    parser.add_argument("--preset", default="needle-path-4x")
    parser.add_argument("--k1", type=float, nargs="+", default=[0.27, 0.6], help="MPa")
    parser.add_argument("--k2", type=float, nargs="+", default=[59.0, 300.0])
    parser.add_argument("--toughness", type=float, nargs="+", default=[0.3, 2.5], help="stroma G_c, N/mm")
    parser.add_argument("--friction", type=float, nargs="+", default=[0.2, 0.36], help="Coulomb mu")
    parser.add_argument("--no-prediction", action="store_true", help="skip the 5 mm/s prediction")
    args = parser.parse_args()
    rows = {}
    for k1, k2, toughness, friction in itertools.product(args.k1, args.k2, args.toughness, args.friction):
        name = f"k1_{k1:g}-k2_{k2:g}-Gc_{toughness:g}-mu_{friction:g}"
        reason = in_range(k1, toughness, friction)
        if reason is not None:
            print(f"{name}: skipped, {reason}")
            continue
        folder = args.out / name
        material = stroma_file(folder / "material", k1, k2)
        overrides = [f"mesh.preset={args.preset}", f"materials.stroma.material={material}",
                     f"cut.blocks.stroma.fracture_energy={toughness!r}",
                     f"instrument.contact.friction.coefficient={friction!r}", "solver.field_count=0"]
        rows[name] = {"k1": k1, "k2": k2, "toughness": toughness, "friction": friction,
                      "overrides": overrides, **run_point(folder / "run", overrides)}
    keys = ["rmse_N", "peak_force_N", "force_0.35_mm_N", "force_0.7_mm_N", "epithelium_depth_mm",
            "stroma_depth_mm", "cornea_depth_mm", "max_kinetic_to_internal", "wall_s"]
    print(f"{'grid point':36s} {'status':10s}" + "".join(f"{key[:14]:>15s}" for key in keys))
    for name, row in rows.items():
        print(f"{name:36s} {row['status']:10s}" + "".join(f"{row[key]:15.4g}" for key in keys))
    scored = {name: row for name, row in rows.items() if math.isfinite(row["rmse_N"])}
    result = {"preset": args.preset, "rows": rows}
    if scored:
        best = min(scored, key=lambda name: scored[name]["rmse_N"])
        print(f"best at 1 mm/s: {best} (RMSE {scored[best]['rmse_N']:.4g} N)")
        result["best"] = best
        if not args.no_prediction:
            overrides = [*scored[best]["overrides"], *speed_overrides(5.0, 0.8)]
            prediction = run_point(args.out / f"{best}-5mm_s", overrides)
            print("prediction at 5 mm/s: " + ", ".join(f"{key} {prediction[key]:.4g}" for key in keys))
            result["prediction_5mm_s"] = prediction
    write_json(args.out / "calibration.json", result)


if __name__ == "__main__":
    main()
