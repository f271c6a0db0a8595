"""Study designs and sensitivity indices against closed forms (no simulation)."""

from __future__ import annotations

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.studies.calibrate import curve_rmse
from corneasim.scenarios._overrides import apply_overrides
from corneasim.studies.case import case_overrides
from corneasim.studies.designs import REALIZATIONS, cases, inverse_cdf, list_keys
from corneasim.studies.outputs import resample, summary_value
from corneasim.studies.sensitivity import morris_indices, sobol_indices
from corneasim.studies.spec import read_study


def study(kind, parameters, **design):
    return read_study({"scenario": "needle", "design": {"kind": kind, **design}, "parameters": parameters,
                       "outputs": {"peak": "peak_force_N"}})[0]


def test_a_grid_is_every_combination_last_parameter_fastest():
    spec = study("grid", {"a.x": [1, 2], "a.y": {"low": 1.0, "high": 100.0, "steps": 3, "scale": "log"},
                          "a.z": {"low": 0.0, "high": 1.0, "steps": 2}})
    points = [c.values for c in cases(spec, "needle")]
    assert len(points) == 2 * 3 * 2
    assert [p["a.z"] for p in points[:2]] == [0.0, 1.0]
    assert [p["a.y"] for p in points[:6:2]] == pytest.approx([1.0, 10.0, 100.0])
    assert [p["a.x"] for p in points] == [1] * 6 + [2] * 6
    assert [c.name for c in cases(spec, "needle")][:2] == ["c0000", "c0001"]


def test_a_list_design_runs_its_cases_as_written_and_tabulates_every_key_they_set():
    written = [{}, {"a.x": 0.1}, {"a.y": 5.0, "a.z": 0.2}, {"a.x": 0.3}]
    spec = read_study({"scenario": "needle", "design": {"kind": "list", "cases": written},
                       "outputs": {"peak": "peak_force_N"}})[0]
    assert [c.values for c in cases(spec, "needle")] == written
    assert list_keys(spec) == ["a.x", "a.y", "a.z"]


def test_a_list_design_tabulates_the_keys_its_cases_set_as_parameter_columns():
    from corneasim.studies.runner import Plan

    plan = Plan({"scenario": "needle", "design": {"kind": "list", "cases": [
        {"instrument.shape.diameter": 0.1}, {"instrument.motion.insertion.rate": 5.0, "solver.end_time": 0.2}]},
        "outputs": {"peak": "peak_force_N"}})
    assert plan.columns()[:4] == ["case", "instrument.shape.diameter", "instrument.motion.insertion.rate",
                                  "solver.end_time"]
    assert [plan.invalid(case) for case in plan.cases()] == [None, None]


def test_a_latin_hypercube_has_one_point_in_each_stratum_of_each_parameter():
    n = 16
    spec = study("latin-hypercube", {"a.x": {"distribution": "uniform", "low": 2.0, "high": 4.0},
                                     "a.y": {"low": -1.0, "high": 1.0}}, samples=n)
    points = [c.values for c in cases(spec, "needle")]
    for key, low, high in (("a.x", 2.0, 4.0), ("a.y", -1.0, 1.0)):
        strata = np.floor((np.array([p[key] for p in points]) - low) / (high - low) * n).astype(int)
        assert sorted(strata) == list(range(n))


def test_inverse_distribution_functions_match_closed_forms():
    spec = study("latin-hypercube", {
        "a.l": {"distribution": "log-uniform", "low": 0.01, "high": 1.0},
        "a.n": {"distribution": "normal", "mean": 3.0, "std": 0.5},
        "a.t": {"distribution": "truncated-normal", "mean": 0.0, "std": 1.0, "low": 0.0, "high": 10.0}}, samples=2)
    log_uniform, normal, truncated = (spec.parameters[k] for k in ("a.l", "a.n", "a.t"))
    assert inverse_cdf(log_uniform, np.array([0.0, 0.5, 1.0])) == pytest.approx([0.01, 0.1, 1.0])
    assert inverse_cdf(normal, np.array([0.5]))[0] == pytest.approx(3.0)
    # half-normal on [0, inf) truncated far out: median sqrt(2) erfinv(0.5) = 0.6745
    assert inverse_cdf(truncated, np.array([0.5]))[0] == pytest.approx(0.6744897502, rel=1e-6)
    assert np.all(np.isfinite(inverse_cdf(normal, np.array([0.0, 1.0]))))


def test_morris_trajectories_change_one_parameter_per_step():
    spec = study("morris", {f"a.{k}": {"low": 0.0, "high": 1.0} for k in "xyz"}, samples=5, levels=4)
    points = np.array([[c.values[f"a.{k}"] for k in "xyz"] for c in cases(spec, "needle")])
    assert points.shape == (5 * 4, 3)
    for t in range(5):
        steps = np.diff(points[4 * t:4 * t + 4], axis=0)
        assert np.all((np.abs(steps) > 1e-12).sum(axis=1) == 1)
        assert np.allclose(np.abs(steps[np.abs(steps) > 1e-12]), 4 / 6)  # Delta = p / (2 (p - 1))


def test_realizations_perturb_the_start_gap_of_the_scenario():
    spec = study("realizations", {"instrument.motion.insertion.rate": [1.0, 5.0]})
    runs = cases(spec, "needle")
    assert len(runs) == 2 * len(REALIZATIONS)
    gaps = {c.realization: c.values["instrument.start_gap"] for c in runs[:len(REALIZATIONS)]}
    assert gaps["as-given"] == 0.002  # the built-in needle's start gap, mm
    assert gaps["start-gap+1e-7"] - 0.002 == pytest.approx(1e-7, abs=1e-15)
    assert gaps["start-gap-1e-7"] - 0.002 == pytest.approx(-1e-7, abs=1e-15)
    assert gaps["start-gap+5e-8"] - 0.002 == pytest.approx(5e-8, abs=1e-15)
    assert [c.fresh_kernels for c in runs[:len(REALIZATIONS)]].count(True) == 1
    assert runs[len(REALIZATIONS) - 1].values["solver.threads"] == 1


def test_morris_indices_of_a_linear_law():
    """y = 3 x1 - 0.5 x2 + 0 x3 with x_i on [0, 2]: every elementary effect per unit of the
    normalised input is a_i * (high - low), so mu* = |a_i| 2 and sigma = 0."""
    spec = study("morris", {f"p.{k}": {"low": 0.0, "high": 2.0} for k in "abc"}, samples=12, levels=4)
    x = np.array([[c.values[f"p.{k}"] for k in "abc"] for c in cases(spec, "needle")])
    y = x @ np.array([3.0, -0.5, 0.0])
    indices = morris_indices(spec, y)
    assert indices["mu_star"] == pytest.approx([6.0, 1.0, 0.0], abs=1e-9)
    assert indices["sigma"] == pytest.approx([0.0, 0.0, 0.0], abs=1e-9)
    y[:4] = np.nan  # a failed case drops its trajectory
    assert morris_indices(spec, y)["trajectories"] == 11


def test_sobol_indices_of_an_additive_law():
    """y = x1 + 2 x2 with x_i uniform on [0, 1]: S1_i = ST_i = a_i^2 / (1 + 4) = 0.2, 0.8."""
    spec = study("sobol", {"p.a": {"low": 0.0, "high": 1.0}, "p.b": {"distribution": "uniform", "low": 0.0,
                                                                     "high": 1.0}}, samples=1024)
    x = np.array([[c.values["p.a"], c.values["p.b"]] for c in cases(spec, "needle")])
    assert len(x) == 1024 * (2 + 2)
    indices = sobol_indices(spec, x[:, 0] + 2 * x[:, 1])
    assert indices["S1"] == pytest.approx([0.2, 0.8], abs=0.03)
    assert indices["ST"] == pytest.approx([0.2, 0.8], abs=0.03)
    assert np.all(indices["S1_conf"] > 0)


def test_outputs_from_a_summary_and_a_history():
    summary = {"peak_force_N": 0.5, "punctures": [{"depth_mm": 0.3}], "fit": None}
    assert summary_value(summary, "punctures.0.depth_mm") == 0.3
    assert np.isnan(summary_value(summary, "punctures.1.depth_mm"))
    assert np.isnan(summary_value(summary, "fit.rmse_N"))
    curve = read_study({"scenario": "needle", "outputs": {"f": {"curve": "force_N", "x": "depth_mm",
                                                                "at": {"low": 0.0, "high": 2.0, "steps": 5}}}})[0]
    history = {"depth_mm": np.array([0.0, 1.0, 1.5]), "force_N": np.array([0.0, 2.0, 3.0])}
    values = resample(history, curve.outputs["f"], "outputs.f")
    assert values[:4] == pytest.approx([0.0, 1.0, 2.0, 3.0]) and np.isnan(values[4])


def test_curve_rmse_counts_the_points_inside_the_curve():
    at = np.array([0.0, 1.0, 2.0, np.nan])[:3]
    curve = np.array([0.0, 1.0, np.nan])  # y = x up to 1
    x, y = np.array([0.25, 0.5, 1.5]), np.array([0.25, 0.75, 9.0])
    assert curve_rmse(curve, at, x, y) == pytest.approx(np.sqrt((0 + 0.25 ** 2) / 2))


def test_a_key_into_a_list_of_tables_changes_that_entry_only():
    data = {"supports": [{"node_set": "a", "stiffness": 1.0, "amplitude": {"type": "ramp"}},
                         {"node_set": "b", "stiffness": 2.0}]}
    overrides = case_overrides({"mesh.preset": "coarse"}, {"supports[1].stiffness": 5.0})
    changed = apply_overrides(data, overrides)
    assert changed["supports"] == [data["supports"][0], {"node_set": "b", "stiffness": 5.0}]
    assert changed["mesh"] == {"preset": "coarse"}
    assert data["supports"][1]["stiffness"] == 2.0
    with pytest.raises(InputError, match="index out of range, the list has 2 entries"):
        apply_overrides(data, case_overrides({}, {"supports[2].stiffness": 5.0}))


def test_the_report_of_a_morris_table_has_the_indices_of_its_law(tmp_path):
    """A synthetic table (y = 3 x1 - 0.5 x2 on [0, 2]^2), rows shuffled and one case missing."""
    import pandas as pd
    import tomli_w

    from corneasim.studies import table as results
    from corneasim.studies.report import write_report

    tables = {"scenario": "needle", "design": {"kind": "morris", "samples": 6, "levels": 4},
              "parameters": {"p.a": {"low": 0.0, "high": 2.0}, "p.b": {"low": 0.0, "high": 2.0}},
              "outputs": {"y": "peak_force_N"}}
    (tmp_path / "study.toml").write_text(tomli_w.dumps(tables))
    spec = read_study(tables)[0]
    rows = {c.name: {"case": c.name, **c.values, "y": 3 * c.values["p.a"] - 0.5 * c.values["p.b"],
                     "status": "completed", "error": "", "wall_s": 1.0, "worker": "w"}
            for c in cases(spec, "needle") if c.index != 4}
    order = results.columns(["p.a", "p.b"], ["y"], False)
    frame = results.frame(rows, order).sample(frac=1.0, random_state=1)
    results.write(tmp_path, frame)
    text = write_report(tmp_path).read_text()
    assert "(5 complete trajectories" in text  # the trajectory of the missing case c0004 is left out
    for name, mu_star in (("p.a", 6.0), ("p.b", 1.0)):
        row = next(line for line in text.splitlines() if line.startswith(f"| {name} |"))
        mu, sigma = (float(cell.split("+-")[0]) for cell in row.split("|")[2:4])
        assert mu == pytest.approx(mu_star, rel=1e-9) and abs(sigma) < 1e-9
    y = pd.read_parquet(tmp_path / "results.parquet")["y"]
    assert f"| y | {y.min():.4g} | {y.median():.4g} | {y.max():.4g} |" in text
    assert (tmp_path / "report" / "y-morris.png").exists() and (tmp_path / "report" / "y-vs-parameters.png").exists()


def test_the_report_of_a_sobol_table_has_the_indices_of_its_law(tmp_path):
    """y = x1 + 2 x2 on [0, 1]^2: S1 = ST = 0.2, 0.8 (as above), through the report."""
    import tomli_w

    from corneasim.studies import table as results
    from corneasim.studies.report import write_report

    tables = {"scenario": "needle", "design": {"kind": "sobol", "samples": 512},
              "parameters": {"p.a": {"low": 0.0, "high": 1.0}, "p.b": {"low": 0.0, "high": 1.0}},
              "outputs": {"y": "peak_force_N"}}
    (tmp_path / "study.toml").write_text(tomli_w.dumps(tables))
    rows = {c.name: {"case": c.name, **c.values, "y": c.values["p.a"] + 2 * c.values["p.b"], "status": "completed",
                     "error": "", "wall_s": 1.0, "worker": "w"} for c in cases(read_study(tables)[0], "needle")}
    results.write(tmp_path, results.frame(rows, results.columns(["p.a", "p.b"], ["y"], False)))
    text = write_report(tmp_path).read_text()
    for name, share in (("p.a", 0.2), ("p.b", 0.8)):
        row = next(line for line in text.splitlines() if line.startswith(f"| {name} |"))
        first, total = (float(cell.split("+-")[0]) for cell in row.split("|")[2:4])
        assert first == pytest.approx(share, abs=0.05) and total == pytest.approx(share, abs=0.05)
    assert (tmp_path / "report" / "y-sobol.png").exists()
