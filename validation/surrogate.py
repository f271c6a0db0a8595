"""Accuracy of the force surrogate on held-out finite-element cases, and its speed per call.

Runs (or resumes, skipping finished cases) a Latin-hypercube study of the needle on the
``needle-path`` mesh (the default mesh's 7.7 um elements along the needle's path) over
insertion rate, needle diameter, intraocular pressure and central corneal thickness, builds a
surrogate from it with a fifth of the cases held out, and prints against the held-out cases
(never used in the fit): the force curve's RMSE as a fraction of each case's peak force (target <= 10%),
the puncture depth errors (target <= 0.03 mm) and the fraction of samples inside the 95%
band (target >= 90%). Then the needle paper's 5 mm/s experiment (Table 2) scored by an FE run
at the paper's needle (0.2 mm, 17.5 mmHg, 0.55 mm cornea) and by the surrogate at the same inputs, and
the time of one ``Surrogate.force`` call. The puncture detector's statistics on the same
held-out cases: ``validation/detector.py``.

Run: ``python validation/surrogate.py [--out DIR] [--cases N] [--workers N]``
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

import corneasim
from corneasim.analysis import compare_to_experiment
from corneasim.data import load_dataset
from corneasim.surrogate import build_surrogate, load

RATE, DIAMETER, PRESSURE, THICKNESS = "instrument.motion.insertion.rate", "instrument.shape.diameter", \
    "pressures[0].pressure", "mesh.geometry.central_thickness"
PRESET = "needle-path"
"""The mesh: 3,750 elements, the default's 7.7 um within 0.25 mm of the axis, at the paper's 2e-5 s step
(a case costs about an eighth of one on the default mesh)."""
END_TIME = 0.3
"""s: 1.2 mm at the slowest rate, past the whole cornea's puncture (about 0.9-1.0 mm)."""
PAPER = {RATE: 5.0, DIAMETER: 0.2, PRESSURE: 2.333e-3, THICKNESS: 0.55}
"""The needle paper's second experiment: 5 mm/s, needle No. 2 (0.2 mm), IOP 17.5 mmHg, 0.55 mm cornea
(mm/s, mm, MPa, mm)."""


def study_spec(cases: int) -> dict:
    """The study: insertion rate 4-6 mm/s, diameter 0.18-0.22 mm, IOP 1.6-3.2e-3 MPa (12-24 mmHg),
    central thickness 0.5-0.6 mm."""
    return {
        "scenario": "needle",
        "overrides": {"mesh.preset": PRESET, "solver.end_time": END_TIME, "solver.field_count": 0},
        "design": {"kind": "latin-hypercube", "samples": cases, "seed": 1},
        "parameters": {RATE: {"distribution": "uniform", "low": 4.0, "high": 6.0},
                       DIAMETER: {"distribution": "uniform", "low": 0.18, "high": 0.22},
                       PRESSURE: {"distribution": "uniform", "low": 1.6e-3, "high": 3.2e-3},
                       THICKNESS: {"distribution": "uniform", "low": 0.5, "high": 0.6}},
        "outputs": {"peak_force_N": "peak_force_N"},
    }


def paper_scores(model, out: Path) -> None:
    """RMSE against Table 2 at 5 mm/s of an FE run at the paper's inputs and of the surrogate."""
    folder = out / "paper-5mm_s"
    if not (folder / "summary.json").is_file():
        corneasim.run_scenario("needle", [f"mesh.preset={PRESET}", f"solver.end_time={END_TIME}",
                                          "solver.field_count=0"] + [f"{k}={v}" for k, v in PAPER.items()],
                               out_dir=folder)
    history = np.genfromtxt(folder / "history.csv", delimiter=",", names=True)
    table = load_dataset("needle-insertion-force")
    depth, experiment = table["depth_mm"], table["experiment_5mm_s_N"]
    inside = history["depth_mm"] <= model.metadata["abscissa"]["max"]
    fe = compare_to_experiment(history["depth_mm"][inside], history["force_N"][inside], depth, experiment)
    grid = np.linspace(0.0, model.metadata["abscissa"]["max"], 601)
    mean, lower, upper = model.force(grid, **PAPER)
    surrogate = compare_to_experiment(grid, mean, depth, experiment)
    print(f"needle paper, 5 mm/s experiment (Table 2, {fe['n_points']} depths): RMSE FE {fe['rmse']:.4f} N, "
          f"surrogate mean {surrogate['rmse']:.4f} N; max error FE {fe['max_abs_error']:.4f} N, "
          f"surrogate {surrogate['max_abs_error']:.4f} N")
    low, high = np.interp(depth, grid, lower), np.interp(depth, grid, upper)
    inside = int(np.sum((experiment >= low) & (experiment <= high)))
    print(f"  surrogate 95% band width at the table's depths: median {np.median(high - low):.4f} N; experiment "
          f"inside the band at {inside} of {depth.size} depths")


def speed(model, calls: int = 20000) -> None:
    """Time per ``force`` call with the same inputs (a controller's loop) and with new inputs each call."""
    inputs = {item["alias"]: 0.5 * (item["low"] + item["high"]) for item in model.metadata["inputs"]}
    depths = np.linspace(0.0, model.metadata["abscissa"]["max"], calls)
    rates = np.linspace(model.metadata["inputs"][0]["low"], model.metadata["inputs"][0]["high"], calls)
    first = model.metadata["inputs"][0]["alias"]
    start = time.perf_counter()
    for depth in depths:
        model.force(depth, **inputs)
    same = (time.perf_counter() - start) / calls
    start = time.perf_counter()
    for depth, rate in zip(depths, rates):
        model.force(depth, **{**inputs, first: rate})
    new = (time.perf_counter() - start) / calls
    print(f"Surrogate.force, one depth per call, {calls} calls: {1e6 * same:.1f} us per call with the same "
          f"inputs ({1 / same:,.0f} calls/s), {1e6 * new:.1f} us with new inputs each call ({1 / new:,.0f} calls/s)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/validation-surrogate"), help="study folder")
    parser.add_argument("--cases", type=int, default=40, help="Latin-hypercube cases")
    parser.add_argument("--workers", type=int, default=1, help="Dask workers")
    parser.add_argument("--hold-out", type=float, default=0.2, help="fraction of cases held out")
    arguments = parser.parse_args()
    start = time.perf_counter()
    table = corneasim.study(study_spec(arguments.cases), out=arguments.out, workers=arguments.workers)
    print(f"study: {len(table)} cases, {int(np.sum(table['status'] == 'completed'))} completed "
          f"({time.perf_counter() - start:.0f} s here; case wall times sum to {table['wall_s'].sum():.0f} s)")
    model = build_surrogate(arguments.out, hold_out=arguments.hold_out, seed=0)
    path = arguments.out / "surrogate.npz"
    model.save(path)
    model = load(path)
    meta = model.metadata
    print(f"surrogate: {len(meta['training_cases'])} training cases, {len(meta['held_out_cases'])} held out; "
          "inputs " + ", ".join(f"{i['name']} [{i['low']:.4g}, {i['high']:.4g}] {i['unit']}" for i in meta["inputs"])
          + f"; depth 0-{meta['abscissa']['max']:.3g} mm; events {', '.join(meta['events'])}")
    for label, scores in (("held-out", meta["held_out"]), ("cross-validation", meta["cross_validation"])):
        force = scores["channels"]["force_N"]
        print(f"{label} ({scores['cases']} cases): force RMSE / peak max {100 * force['relative_rmse_max']:.1f}% "
              f"(mean {100 * force['relative_rmse_mean']:.1f}%, target <= 10%); samples inside the 95% band "
              f"{100 * force['coverage']:.1f}% (target >= 90%); puncture depth error max "
              + ", ".join(f"{e} {scores['puncture_error_max'][e]:.4f} mm" for e in meta["events"])
              + " (target <= 0.03 mm)")
    for case in meta["held_out"]["per_case"]:
        print(f"  {case['case']}: RMSE/peak {100 * case['relative_rmse']['force_N']:.1f}%, puncture errors "
              + ", ".join(f"{e} {v:.4f}" for e, v in case["puncture_error"].items()) + " mm")
    paper_scores(model, arguments.out)
    speed(model)


if __name__ == "__main__":
    main()
