"""Accuracy of the force surrogate on held-out finite-element cases, and its speed per call.

Runs (or resumes, skipping finished cases) a Latin-hypercube study of the needle on the
``needle-path`` mesh (the default mesh's 7.7 um elements along the needle's path) over
insertion rate, needle diameter, intraocular pressure and central corneal thickness, builds a
surrogate of the three punctures from it with a fifth of the cases held out (a case whose run
ends before one of them is left out and listed), and prints against the held-out cases
(never used in the fit): the force curve's RMSE as a fraction of each case's peak force (target <= 10%),
the puncture depth errors (target <= 0.03 mm) and the fraction of samples inside the 95%
band (target >= 90%). Then the finite-element model's own repeatability on the same held-out
cases (:func:`repeatability`: each case run again with the start gap moved by +1e-7 and -1e-7
mm, the round-off perturbations of the study design ``realizations``), which bounds what any
surrogate of these runs can score; the needle paper's experiment at the study's speed (Table 2;
``--speed``: 5 mm/s, rates 4-6 mm/s, or 1 mm/s, rates 0.9-1.1 mm/s) scored by an FE run at the
paper's needle (0.2 mm, 17.5 mmHg, 0.55 mm cornea) and by the surrogate at the same inputs; and
the time of one ``Surrogate.force`` call. The puncture detector's statistics on the same
held-out cases: ``validation/detector.py``.

``--add DIR`` pools another study of the same inputs (a corner where the first is sparse) and
scores the pooled model on the first study's held-out cases (``DIR/surrogate-pooled.npz``).

Run: ``python validation/surrogate.py [--out DIR] [--cases N] [--workers N] [--speed 5|1] [--add DIR]``
"""

from __future__ import annotations

import argparse
import hashlib
import time
import tomllib
from pathlib import Path

import numpy as np

import corneasim
from corneasim.analysis import compare_to_experiment
from corneasim.data import load_dataset
from corneasim.surrogate import build_surrogate, load
from corneasim.surrogate._study import EVENT_ORDER, read_study
from corneasim.surrogate._study import _case as read_case
from corneasim.surrogate.build import split

RATE, DIAMETER, PRESSURE, THICKNESS = "instrument.motion.insertion.rate", "instrument.shape.diameter", \
    "pressures[0].pressure", "mesh.geometry.central_thickness"
PRESET = "needle-path"
"""The mesh: 3,750 elements, the default's 7.7 um within 0.25 mm of the axis, at the paper's 2e-5 s step
(a case costs about an eighth of one on the default mesh)."""
SPEEDS = {5.0: ((4.0, 6.0), 0.3), 1.0: ((0.9, 1.1), 1.34)}
"""Per experiment of the needle paper (its insertion speed, mm/s): the study's range of insertion
rates (mm/s, 20% or 10% about it, inside the friction law's validity from 0.84 mm/s) and the
end time (s: at least 1.2 mm at the slowest rate, past the whole cornea's puncture, about
0.9-1.1 mm)."""
PAPER = {DIAMETER: 0.2, PRESSURE: 2.333e-3, THICKNESS: 0.55}
"""The needle paper's experiments besides the speed: needle No. 2 (0.2 mm), IOP 17.5 mmHg, 0.55 mm cornea
(mm, MPa, mm)."""
GAP = "instrument.start_gap"
PERTURBATIONS = (1e-7, -1e-7)
"""Start-gap changes of the repeatability runs, mm (those of the study design ``realizations``)."""


def study_spec(cases: int, speed: float) -> dict:
    """The study about the paper's experiment at ``speed`` (mm/s): insertion rate as
    :data:`SPEEDS`, diameter 0.18-0.22 mm, IOP 1.6-3.2e-3 MPa (12-24 mmHg), central thickness
    0.5-0.6 mm."""
    (low, high), end_time = SPEEDS[speed]
    return {
        "scenario": "needle",
        "overrides": {"mesh.preset": PRESET, "solver.end_time": end_time, "solver.field_count": 0},
        "design": {"kind": "latin-hypercube", "samples": cases, "seed": 1},
        "parameters": {RATE: {"distribution": "uniform", "low": low, "high": high},
                       DIAMETER: {"distribution": "uniform", "low": 0.18, "high": 0.22},
                       PRESSURE: {"distribution": "uniform", "low": 1.6e-3, "high": 3.2e-3},
                       THICKNESS: {"distribution": "uniform", "low": 0.5, "high": 0.6}},
        "outputs": {"peak_force_N": "peak_force_N"},
    }


def relative_rms(curve_a: np.ndarray, reference: np.ndarray) -> float:
    """RMS of ``curve_a - reference`` over the largest value of ``reference`` (both N, same depths)."""
    return float(np.sqrt(np.mean((curve_a - reference) ** 2)) / reference.max())


def repeatability(model, out: Path, workers: int, speed: float) -> None:
    """The held-out cases run again with the start gap moved by :data:`PERTURBATIONS`; prints,
    per case and as min / median / max: the RMSE between the FE runs of the same inputs and that
    of the surrogate against a run and against the runs' mean, each over the peak force of the
    curve it is compared with (:func:`relative_rms`; of two runs, the earlier), and the spread of
    each puncture depth over the runs with the surrogate's error against their mean.

    If the runs are one mean curve plus independent deviations of RMS sigma, two runs differ by
    sqrt(2) sigma RMS and the mean curve itself scores sigma against a run: no function of the
    inputs scores below that."""
    held = [name.rsplit("/", 1)[-1] for name in model.metadata["held_out_cases"]]  # the first study's
    cases = []
    for name in held:
        with open(out / "cases" / name / "scenario.toml", "rb") as handle:
            resolved = tomllib.load(handle)
        point = {RATE: resolved["instrument"]["motion"]["insertion"]["rate"],
                 DIAMETER: resolved["instrument"]["shape"]["diameter"],
                 PRESSURE: resolved["pressures"][0]["pressure"],
                 THICKNESS: resolved["mesh"]["geometry"]["central_thickness"]}
        cases += [{**point, GAP: resolved["instrument"]["start_gap"] + change} for change in PERTURBATIONS]
    spec = {"scenario": "needle", "overrides": study_spec(1, speed)["overrides"],
            "design": {"kind": "list", "cases": cases}, "outputs": {"peak_force_N": "peak_force_N"}}
    folder = out / f"repeatability-{hashlib.sha1(','.join(held).encode()).hexdigest()[:8]}"  # one per held-out set
    table = corneasim.study(spec, out=folder, workers=workers)
    rows = sorted(table.to_dict("records"), key=lambda row: row["case"])  # design order
    print(f"repeatability of the FE runs on the {len(held)} held-out cases (start gap {PERTURBATIONS[0]:+g} and "
          f"{PERTURBATIONS[1]:+g} mm; RMSE over the peak force of the curve compared with):")
    figures = {"fe": [], "run": [], "mean": []}
    spreads = {e: [] for e in model.events}
    errors = {e: [] for e in model.events}
    for k, name in enumerate(held):
        reruns = [rows[len(PERTURBATIONS) * k + j] for j in range(len(PERTURBATIONS))]
        if any(row["status"] != "completed" for row in reruns):
            print(f"  {name}: a repeat run did not complete; left out")
            continue
        runs = [read_case(path, np.zeros(0), "needle")
                for path in [out / "cases" / name] + [folder / "cases" / str(row["case"]) for row in reruns]]
        depth = runs[0].abscissa[runs[0].abscissa <= model.metadata["abscissa"]["max"]]
        forces = np.array([np.interp(depth, run.abscissa, run.forces["force_N"]) for run in runs])
        inputs = {key: reruns[0][key] for key in (RATE, DIAMETER, PRESSURE, THICKNESS)}
        predicted, _, _ = model.force(depth, extrapolate=True, **inputs)
        fe = [relative_rms(forces[j], forces[i]) for i in range(len(runs)) for j in range(i + 1, len(runs))]
        figures["fe"] += fe
        figures["run"].append(relative_rms(predicted, forces[0]))
        figures["mean"].append(relative_rms(predicted, forces.mean(axis=0)))
        punctures = model.punctures(extrapolate=True, **inputs)
        for event in model.events:
            depths = [run.events[event] for run in runs if event in run.events]
            if len(depths) == len(runs):
                spreads[event].append(max(depths) - min(depths))
                errors[event].append(abs(punctures[event][0] - float(np.mean(depths))))
        print(f"  {name}: FE run against FE run {100 * min(fe):.1f}-{100 * max(fe):.1f}%, surrogate against the run "
              f"{100 * figures['run'][-1]:.1f}% and against the runs' mean {100 * figures['mean'][-1]:.1f}%")

    def brief(values, scale=100.0, digits=1):
        return "/".join(f"{scale * v:.{digits}f}" for v in (np.min(values), np.median(values), np.max(values)))

    if figures["run"]:
        print(f"  min/median/max, % of peak: FE run against FE run {brief(figures['fe'])}; surrogate against the run "
              f"{brief(figures['run'])}, against the runs' mean {brief(figures['mean'])}")
        for event in (e for e in model.events if spreads[e]):
            print(f"  {event}: spread of the FE runs {brief(spreads[event], 1.0, 3)} mm; surrogate's error against "
                  f"their mean {brief(errors[event], 1.0, 3)} mm")


def paper_scores(model, out: Path, speed: float) -> None:
    """RMSE against Table 2 at ``speed`` (mm/s) of an FE run at the paper's inputs and of the surrogate."""
    inputs = {RATE: speed, **PAPER}
    folder = out / f"paper-{speed:g}mm_s"
    if not (folder / "summary.json").is_file():
        corneasim.run_scenario("needle", [f"{k}={v}" for k, v in study_spec(1, speed)["overrides"].items()]
                               + [f"{k}={v}" for k, v in inputs.items()], out_dir=folder)
    history = np.genfromtxt(folder / "history.csv", delimiter=",", names=True)
    table = load_dataset("needle-insertion-force")
    depth, experiment = table["depth_mm"], table[f"experiment_{speed:g}mm_s_N"]
    inside = history["depth_mm"] <= model.metadata["abscissa"]["max"]
    fe = compare_to_experiment(history["depth_mm"][inside], history["force_N"][inside], depth, experiment)
    grid = np.linspace(0.0, model.metadata["abscissa"]["max"], 601)
    mean, lower, upper = model.force(grid, **inputs)
    surrogate = compare_to_experiment(grid, mean, depth, experiment)
    print(f"needle paper, {speed:g} mm/s experiment (Table 2, {fe['n_points']} depths): RMSE FE {fe['rmse']:.4f} N, "
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
    parser.add_argument("--speed", type=float, default=5.0, choices=sorted(SPEEDS),
                        help="the paper's experiment the study is about, mm/s: 5 (rates 4-6 mm/s) "
                             "or 1 (0.9-1.1 mm/s)")
    parser.add_argument("--hold-out", type=float, default=0.2, help="fraction of cases held out")
    parser.add_argument("--add", type=Path, action="append", default=[], metavar="DIR",
                        help="a study of the same scenario and inputs (cases added where the first is sparse), "
                             "pooled with it; the first study's held-out cases stay held out (repeatable)")
    arguments = parser.parse_args()
    start = time.perf_counter()
    table = corneasim.study(study_spec(arguments.cases, arguments.speed), out=arguments.out,
                            workers=arguments.workers)
    print(f"study: {len(table)} cases, {int(np.sum(table['status'] == 'completed'))} completed "
          f"({time.perf_counter() - start:.0f} s here; case wall times sum to {table['wall_s'].sum():.0f} s)")
    events = list(EVENT_ORDER)
    if arguments.add:  # the first study's held-out cases, held out of the pooled model too
        first = read_study(arguments.out, events)
        _, held = split(len(first.cases), arguments.hold_out, 0)
        model = build_surrogate([arguments.out, *arguments.add], events=events,
                                held_out_cases=[f"{arguments.out.name}/{first.cases[k].name}" for k in held])
        path = arguments.out / "surrogate-pooled.npz"
    else:
        model = build_surrogate(arguments.out, hold_out=arguments.hold_out, seed=0, events=events)
        path = arguments.out / "surrogate.npz"
    model.save(path)
    model = load(path)
    meta = model.metadata
    print(f"surrogate: {len(meta['training_cases'])} training cases, {len(meta['held_out_cases'])} held out; "
          "inputs " + ", ".join(f"{i['name']} [{i['low']:.4g}, {i['high']:.4g}] {i['unit']}" for i in meta["inputs"])
          + f"; depth 0-{meta['abscissa']['max']:.3g} mm; events {', '.join(meta['events'])}")
    for item in meta["left_out_cases"]:
        print(f"  left out: {item['case']} ({item['reason']})")
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
    repeatability(model, arguments.out, arguments.workers, arguments.speed)
    paper_scores(model, arguments.out, arguments.speed)
    speed(model)


if __name__ == "__main__":
    main()
