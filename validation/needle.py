"""Validate a needle scenario against the needle paper's experiments (Table 2), over realizations.

Runs the needle scenario (the built-in ``needle``, or any needle scenario file given by
``--scenario``) at 1 mm/s and 5 mm/s with one parameter set, each speed as a study of the
``realizations`` design (``corneasim.studies``; ``docs/studies.md``): the run as given and
its five round-off realizations (start gap moved by +1e-7, -1e-7 and +5e-8 mm, kernels
compiled into an empty Numba cache in a process of their own, one thread). Each figure is
printed with its min / median / max over the realizations and PASS when every realization
meets its target (:data:`RULES`):

* RMSE of the fitted force against the experiment's mean curve at Table 2's 15 depths
  (the simulated force through its 3-term Gaussian fit, as the paper's "simulation"
  column, scored over Table 2's 0.7 mm): <= 0.035 N at 1 mm/s, <= 0.095 N at 5 mm/s;
* the largest kinetic / internal energy ratio after contact over the whole insertion
  (``run.max_kinetic_to_internal``): <= 0.05 at both speeds, so that inertia does not make
  the speed effect;
* the puncture order: the epithelium, the stroma and the whole cornea all punctured, at
  non-decreasing times in that order (the three events are recorded at the time of the
  deletion or separation that completes them, so two can share a step);
* the whole cornea's puncture depth: 0.55-0.75 mm of travel (the experiment's curves);
* the shaft's friction after the puncture (:func:`friction_fraction`): the mean force over the
  last :data:`FRICTION_WINDOW` mm of travel, which must lie wholly after the whole cornea's
  puncture, is at least :data:`FRICTION_FRACTION` of the peak force. A cornea that rides free
  once it is punctured (a hole wider than the shaft) leaves only contact chatter, far below a
  tenth of the peak; cut faces that grip the shaft keep a friction plateau.

Both speeds run to ``--depth`` (default 1.0 mm) so that the whole cornea is punctured and a
friction window follows it. ``--realizations 1`` runs only the case as given (a quick pass);
the figures then have one value each. Running again into the same ``--out`` resumes: the
cases already completed are not run again (a study's resume). The cases run one at a time by
default (``--workers 1``), each on all the cores as ``corneasim run`` would; a study worker
gets cores // workers threads, so with two workers on two cores every case runs on one
thread and the one-thread realization repeats the case as given (meshes under 5,000 elements,
such as the coarse preset, run on one thread either way).

Usage::

    python validation/needle.py [--scenario needle|FILE] [--preset MESH_PRESET]
                                [--depth 1.0] [--realizations 6|1] [--workers 1]
                                [--out results/validation-needle] [--set KEY=VALUE ...]

``--set variant=paper`` validates the needle paper's own model (the scenario's
``[presets.paper]``) the same way.

Writes the study folders ``OUT/1mm_s`` and ``OUT/5mm_s`` (each case's results folder under
``cases/``, the table ``results.csv``) and ``OUT/validation.json`` with every figure of every
realization, their spread and their verdicts.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from corneasim.output import NEEDLE_RMSE_N

SPEEDS = (1.0, 5.0)
"""Insertion speeds of the experiments, mm/s."""

RMSE_N = NEEDLE_RMSE_N
"""RMSE targets of the fitted force against Table 2, by speed (mm/s), N: the run summaries' own
(:data:`corneasim.output.NEEDLE_RMSE_N`)."""

KINETIC_TO_INTERNAL = 0.05
"""Largest kinetic / internal energy ratio over the insertion, dimensionless."""

CORNEA_PUNCTURE_MM = (0.55, 0.75)
"""Range of the whole cornea's puncture depth, mm of travel."""

FRICTION_WINDOW = 0.1
"""Travel at the end of the run over which the friction force is averaged, mm."""

FRICTION_FRACTION = 0.1
"""Smallest mean force over the friction window, as a fraction of the peak force."""

PUNCTURE_ORDER = ("epithelium", "stroma", "cornea")
"""The puncture events in the order they must happen."""

DEPTH_STEP = 0.001
"""Spacing of the force curve collected from every case, mm."""


@dataclass(frozen=True)
class Rule:
    """A figure and its target: ``low <= value <= high`` (None: unbounded)."""

    name: str
    text: str
    low: float | None = None
    high: float | None = None

    def met(self, value: float) -> bool:
        """Whether ``value`` meets the target (NaN never does)."""
        if value is None or not math.isfinite(value):
            return False
        return (self.low is None or value >= self.low) and (self.high is None or value <= self.high)


def rules(speed: float) -> list[Rule]:
    """The figures of one speed (mm/s) and their targets."""
    return [
        Rule("rmse_N", "RMSE of the fitted force vs Table 2, N", high=RMSE_N.get(speed)),
        Rule("max_kinetic_to_internal", "max KE/IE over the insertion", high=KINETIC_TO_INTERNAL),
        Rule("puncture_order", "punctures epithelium -> stroma -> cornea (1 yes, 0 no)", low=1.0),
        Rule("cornea_puncture_depth_mm", "whole-cornea puncture depth, mm",
             low=CORNEA_PUNCTURE_MM[0], high=CORNEA_PUNCTURE_MM[1]),
        Rule("friction_fraction", f"mean force over the last {FRICTION_WINDOW:g} mm / peak force",
             low=FRICTION_FRACTION),
    ]


def study_outputs(depth: float) -> dict:
    """The study's ``[outputs]``: the summary entries the figures need and the force curve."""
    outputs = {"rmse_N": "validation.rmse_N", "max_kinetic_to_internal": "run.max_kinetic_to_internal",
               "peak_force_N": "peak_force_N"}
    for index in range(len(PUNCTURE_ORDER)):
        for entry in ("event", "time_s", "depth_mm"):
            outputs[f"puncture_{index}_{entry}"] = f"punctures.{index}.{entry}"
    steps = int(round(depth / DEPTH_STEP)) + 1
    outputs["force"] = {"curve": "force_N", "x": "depth_mm", "at": {"low": 0.0, "high": depth, "steps": steps}}
    return outputs


def punctures(row: dict) -> dict[str, tuple[float, float]]:
    """{event: (time s, depth mm)} of a results-table row."""
    found = {}
    for index in range(len(PUNCTURE_ORDER)):
        event = row.get(f"puncture_{index}_event")
        if isinstance(event, str) and event:
            found[event] = (float(row[f"puncture_{index}_time_s"]), float(row[f"puncture_{index}_depth_mm"]))
    return found


def in_order(events: dict[str, tuple[float, float]]) -> bool:
    """All of :data:`PUNCTURE_ORDER` happened, at non-decreasing times in that order."""
    if not all(name in events for name in PUNCTURE_ORDER):
        return False
    times = [events[name][0] for name in PUNCTURE_ORDER]
    return all(a <= b for a, b in zip(times, times[1:]))


def friction_fraction(depth: np.ndarray, force: np.ndarray, cornea_depth: float, peak: float,
                      window: float = FRICTION_WINDOW) -> float:
    """Mean force over the last ``window`` mm of travel divided by the peak force.

    The window ``[d_end - window, d_end]`` (``d_end`` the deepest sampled travel, mm) must lie
    after the whole cornea's puncture at ``cornea_depth`` (mm); otherwise, or without a
    puncture, NaN (the figure cannot be measured, so it fails).
    """
    sampled = np.isfinite(force)
    if not sampled.any() or not math.isfinite(cornea_depth) or not peak > 0:
        return math.nan
    end = depth[sampled].max()
    if end - window < cornea_depth:
        return math.nan
    last = sampled & (depth >= end - window)
    return float(np.mean(force[last]) / peak)


def figures(row: dict, depth_axis: np.ndarray) -> dict:
    """The figures of one case from its results-table row; ``depth_axis``: the force curve's depths, mm."""
    events = punctures(row)
    cornea = events.get("cornea", (math.nan, math.nan))[1]
    force = np.asarray(row["force"], dtype=float)
    completed = row.get("status") == "completed"
    nan = math.nan
    return {
        "rmse_N": float(row["rmse_N"]) if completed else nan,
        "max_kinetic_to_internal": float(row["max_kinetic_to_internal"]) if completed else nan,
        "puncture_order": float(in_order(events)) if completed else nan,
        "cornea_puncture_depth_mm": cornea if completed else nan,
        "friction_fraction": friction_fraction(depth_axis, force, cornea, float(row["peak_force_N"]))
        if completed else nan,
        "peak_force_N": float(row["peak_force_N"]) if completed else nan,
        "punctures": {name: depth for name, (_, depth) in events.items()},
    }


def spread(values: list[float]) -> dict:
    """min / median / max of the finite values (NaN without any) and how many were finite."""
    finite = np.array([v for v in values if v is not None and math.isfinite(v)], dtype=float)
    if not finite.size:
        return {"min": math.nan, "median": math.nan, "max": math.nan, "finite": 0}
    return {"min": float(finite.min()), "median": float(np.median(finite)), "max": float(finite.max()),
            "finite": int(finite.size)}


def verdict(rule: Rule, values: list[float]) -> dict:
    """The spread of a figure over the realizations and PASS when every realization meets the target."""
    met = [rule.met(value) for value in values]
    return {**spread(values), "met": int(sum(met)), "of": len(values),
            "verdict": "PASS" if values and all(met) else "FAIL"}


def mean_force_over_experiment(depth_axis: np.ndarray, force: np.ndarray, speed: float,
                               window: float = 0.01) -> tuple[float, float]:
    """Mean simulated and measured force over the experiment's depths, N (the simulated force
    averaged over +- ``window`` mm at each depth: the cut makes it jagged)."""
    from corneasim.data import load_dataset

    data = load_dataset("needle-insertion-force")
    depths = data.columns["depth_mm"]
    depths = depths[(depths > 0.0) & (depths <= np.nanmax(np.where(np.isfinite(force), depth_axis, np.nan)))]
    simulated = [np.nanmean(force[np.abs(depth_axis - d) <= window]) for d in depths]
    measured = np.interp(depths, data.columns["depth_mm"], data.columns[f"experiment_{speed:g}mm_s_N"])
    return float(np.mean(simulated)), float(np.mean(measured))


def judge(table, speed: float, depth_axis: np.ndarray) -> dict:
    """Figures of every case of one speed's results table, their spread and verdicts."""
    rows = table.to_dict(orient="records")
    cases = [{"case": row["case"], "realization": row.get("realization", "as-given"), "status": row["status"],
              "error": row["error"], **figures(row, depth_axis)} for row in rows]
    verdicts = {rule.name: {"target": rule.text, "low": rule.low, "high": rule.high,
                            **verdict(rule, [case[rule.name] for case in cases])} for rule in rules(speed)}
    means = [mean_force_over_experiment(depth_axis, np.asarray(row["force"], dtype=float), speed)
             for row in rows if row["status"] == "completed"]
    return {"cases": cases, "figures": verdicts,
            "mean_force_N": float(np.median([m[0] for m in means])) if means else math.nan,
            "experiment_mean_force_N": means[0][1] if means else math.nan}


def run_speed(scenario: str, speed: float, overrides: list[str], depth: float, realizations: int,
              out: Path, workers: int | None):
    """Run one speed's study; return its results table."""
    import corneasim
    from corneasim.scenarios._needle import speed_overrides
    from corneasim.scenarios._overrides import override_table

    fixed = override_table([*speed_overrides(speed, depth), *overrides])
    spec = {"scenario": scenario, "description": f"needle validation at {speed:g} mm/s",
            "overrides": fixed, "design": {"kind": "realizations" if realizations > 1 else "grid"},
            "outputs": study_outputs(depth)}
    return corneasim.study(spec, out=out, workers=workers, progress=True)


def line(name: str, row: dict) -> str:
    """One figure as a Markdown table row."""
    def number(value):
        return f"{value:.4g}" if math.isfinite(value) else "nan"

    bounds = " .. ".join(f"{b:g}" for b in (row["low"], row["high"]) if b is not None)
    target = (f"[{bounds}]" if row["low"] is not None and row["high"] is not None
              else f">= {row['low']:g}" if row["low"] is not None else f"<= {row['high']:g}" if row["high"] is not None
              else "-")
    return (f"| {row['target']} | {target} | {number(row['min'])} | {number(row['median'])} | {number(row['max'])} "
            f"| {row['met']}/{row['of']} | {row['verdict']} |")


def report(result: dict) -> str:
    """The figures of both speeds as Markdown."""
    lines = []
    for speed, judged in result.items():
        lines += [f"\n{speed} ({len(judged['cases'])} realizations)\n",
                  "| figure | target | min | median | max | met | verdict |", "|---|---|---|---|---|---|---|"]
        lines += [line(name, row) for name, row in judged["figures"].items()]
        failed = [f"{case['case']} ({case['realization']}): {case['error']}" for case in judged["cases"]
                  if case["status"] != "completed"]
        lines += [f"not completed: {text}" for text in failed]
        for case in judged["cases"]:
            events = " -> ".join(f"{name} {depth:.3f}" for name, depth in case["punctures"].items()) or "none"
            lines.append(f"  {case['realization']}: punctures (mm) {events}")
    slow, fast = (result[f"{speed:g}mm_s"] for speed in SPEEDS)
    if math.isfinite(slow["mean_force_N"]) and math.isfinite(fast["mean_force_N"]):
        lines.append(f"\nmean force over the experiment's depths (median realization): "
                     f"{slow['mean_force_N']:.3f} -> {fast['mean_force_N']:.3f} N; experiment "
                     f"{slow['experiment_mean_force_N']:.3f} -> {fast['experiment_mean_force_N']:.3f} N")
    verdicts = [row["verdict"] for judged in result.values() for row in judged["figures"].values()]
    lines.append(f"\nall figures: {'PASS' if all(v == 'PASS' for v in verdicts) else 'FAIL'} "
                 f"({verdicts.count('PASS')}/{len(verdicts)} pass)")
    return "\n".join(lines)


def main() -> None:
    from corneasim.output import write_json

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="needle", help="built-in needle scenario name or a scenario file")
    parser.add_argument("--preset", default="default",
                        help="mesh preset of the scenario (mesh.preset: coarse, default, fine, needle-path, ...)")
    parser.add_argument("--out", type=Path, default=Path("results/validation-needle"))
    parser.add_argument("--depth", type=float, default=1.0,
                        help="insertion depth of both runs, mm (>= 0.7; the table scores the first 0.7 mm)")
    parser.add_argument("--realizations", type=int, default=6, choices=[1, 6],
                        help="6: the case as given and its five round-off realizations; 1: the case as given")
    parser.add_argument("--workers", type=int, default=1,
                        help="study workers; each case gets cores // workers threads, so with more than one "
                             "worker the one-thread realization is no longer the odd one out (default 1)")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    arguments = parser.parse_args()
    if not arguments.depth >= 0.7:
        parser.error(f"--depth: expected at least 0.7 mm (Table 2's range), got {arguments.depth}")
    scenario = arguments.scenario
    if Path(scenario).suffix == ".toml":
        scenario = str(Path(scenario).resolve())
    overrides = [f"mesh.preset={arguments.preset}", *arguments.overrides]
    depth_axis = np.linspace(0.0, arguments.depth, int(round(arguments.depth / DEPTH_STEP)) + 1)
    result = {}
    for speed in SPEEDS:
        key = f"{speed:g}mm_s"
        table = run_speed(scenario, speed, overrides, arguments.depth, arguments.realizations,
                          arguments.out / key, arguments.workers)
        result[key] = judge(table, speed, depth_axis)
    write_json(arguments.out / "validation.json", {"scenario": arguments.scenario, "overrides": overrides,
                                                   "depth_mm": arguments.depth, "speeds": result})
    print(report(result))


if __name__ == "__main__":
    main()
