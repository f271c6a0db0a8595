"""The needle validation's figures and verdicts on synthetic results tables (no simulation)."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "validation"))

import needle as validation  # noqa: E402

DEPTHS = np.linspace(0.0, 1.0, 1001)


def synthetic_force(peak: float = 0.6, puncture: float = 0.65, plateau: float = 0.12) -> np.ndarray:
    """A rise to ``peak`` N at ``puncture`` mm, then a friction plateau (N)."""
    return np.where(DEPTHS <= puncture, peak * DEPTHS / puncture, plateau)


def row(**changes) -> dict:
    base = {"case": "c0000", "realization": "as-given", "status": "completed", "error": "", "rmse_N": 0.03,
            "max_kinetic_to_internal": 0.02, "peak_force_N": 0.6, "force": synthetic_force(),
            "puncture_0_event": "epithelium", "puncture_0_time_s": 0.10, "puncture_0_depth_mm": 0.10,
            "puncture_1_event": "stroma", "puncture_1_time_s": 0.12, "puncture_1_depth_mm": 0.12,
            "puncture_2_event": "cornea", "puncture_2_time_s": 0.65, "puncture_2_depth_mm": 0.65}
    return {**base, **changes}


def test_a_rule_holds_within_its_bounds_only_and_never_for_nan():
    rule = validation.Rule("x", "x", low=0.55, high=0.75)
    assert [rule.met(v) for v in (0.55, 0.6, 0.75, 0.549, 0.751, math.nan, None)] == [
        True, True, True, False, False, False, False]
    assert validation.Rule("y", "y", high=0.035).met(-1.0)


def test_the_spread_is_min_median_max_of_the_finite_values():
    assert validation.spread([3.0, math.nan, 1.0, 2.0, 10.0]) == {"min": 1.0, "median": 2.5, "max": 10.0,
                                                                 "finite": 4}
    assert validation.spread([math.nan])["finite"] == 0


def test_a_figure_passes_only_when_every_realization_meets_its_target():
    rule = validation.Rule("rmse_N", "rmse", high=0.035)
    assert validation.verdict(rule, [0.03, 0.034, 0.035])["verdict"] == "PASS"
    failed = validation.verdict(rule, [0.03, 0.036, 0.02])
    assert (failed["verdict"], failed["met"], failed["of"]) == ("FAIL", 2, 3)
    assert validation.verdict(rule, [0.03, math.nan])["verdict"] == "FAIL"
    assert validation.verdict(rule, [])["verdict"] == "FAIL"


def test_the_friction_fraction_is_the_plateau_over_the_peak():
    force = synthetic_force(peak=0.6, puncture=0.65, plateau=0.12)
    assert validation.friction_fraction(DEPTHS, force, 0.65, 0.6) == pytest.approx(0.2)
    # the window 0.9-1.0 mm must lie after the puncture: a puncture at 0.95 mm cannot be judged
    assert math.isnan(validation.friction_fraction(DEPTHS, force, 0.95, 0.6))
    assert math.isnan(validation.friction_fraction(DEPTHS, force, math.nan, 0.6))
    # NaN beyond the run's end: the window is the last 0.1 mm the run reached (0.7-0.8 mm)
    short = np.where(DEPTHS <= 0.8, np.where(DEPTHS > 0.69, 0.3, 5.0), np.nan)
    assert validation.friction_fraction(DEPTHS, short, 0.65, 0.6) == pytest.approx(0.5)


@pytest.mark.parametrize("events, expected", [
    ({"epithelium": (0.1, 0.1), "stroma": (0.12, 0.12), "cornea": (0.6, 0.6)}, True),
    ({"epithelium": (0.1, 0.1), "stroma": (0.1, 0.1), "cornea": (0.6, 0.6)}, True),
    ({"epithelium": (0.2, 0.2), "stroma": (0.1, 0.1), "cornea": (0.6, 0.6)}, False),
    ({"epithelium": (0.1, 0.1), "stroma": (0.12, 0.12)}, False),
    ({}, False),
])
def test_the_puncture_order_needs_all_three_at_non_decreasing_times(events, expected):
    assert validation.in_order(events) is expected


def test_the_figures_of_a_row_meet_the_targets_they_were_built_to_meet():
    figures = validation.figures(row(), DEPTHS)
    assert figures["cornea_puncture_depth_mm"] == 0.65 and figures["puncture_order"] == 1.0
    assert figures["friction_fraction"] == pytest.approx(0.2)
    assert all(rule.met(figures[rule.name]) for rule in validation.rules(1.0))
    assert not validation.rules(5.0)[0].met(0.1)


def test_a_failed_case_fails_every_figure():
    figures = validation.figures(row(status="failed", force=np.full(DEPTHS.shape, np.nan)), DEPTHS)
    assert all(math.isnan(figures[rule.name]) for rule in validation.rules(1.0))


def test_a_table_of_realizations_is_judged_by_its_worst_case():
    late = row(case="c0001", realization="start-gap+1e-7", puncture_2_depth_mm=0.8, rmse_N=0.031)
    table = pd.DataFrame([row(), late])
    judged = validation.judge(table, 1.0, DEPTHS)
    figures = judged["figures"]
    assert figures["cornea_puncture_depth_mm"]["verdict"] == "FAIL"
    assert (figures["cornea_puncture_depth_mm"]["min"], figures["cornea_puncture_depth_mm"]["max"]) == (0.65, 0.8)
    assert figures["rmse_N"]["verdict"] == "PASS" and figures["rmse_N"]["median"] == pytest.approx(0.0305)
    assert "FAIL" in validation.report({"1mm_s": judged, "5mm_s": judged})


def test_the_study_outputs_are_entries_a_needle_summary_has():
    from corneasim.studies.outputs import check_path

    outputs = validation.study_outputs(1.0)
    for name, path in outputs.items():
        if isinstance(path, str):
            check_path(path, "needle", name)
    assert outputs["force"]["at"]["steps"] == DEPTHS.size


@pytest.mark.parametrize("speed", validation.SPEEDS)
def test_the_validation_and_the_run_summaries_score_the_rmse_against_one_target(speed):
    from corneasim.output import score

    target = validation.RMSE_N[speed]
    rule = next(rule for rule in validation.rules(speed) if rule.name == "rmse_N")
    for rmse in (0.5 * target, target, 1.01 * target, 1.2 * target):
        summary = {"kind": "needle", "validation": {"column": "experiment_N", "rmse_N": rmse}}
        met = score(summary, speed)[0][3]
        assert met is rule.met(rmse) is (rmse <= target), (speed, rmse)
