"""The parametric study's grouping of cases into factors and levels, on a synthetic table."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "validation"))

import needle_parametric_plots as plots  # noqa: E402

NAN = math.nan
D, V = "instrument.shape.diameter", "instrument.motion.insertion.rate"


def test_each_factor_gets_its_cases_and_the_reference_at_the_base_value_sorted():
    table = pd.DataFrame([
        {"case": "c0000", D: NAN, V: NAN, "solver.end_time": 1.0},
        {"case": "c0001", D: 0.3, V: NAN, "solver.end_time": 1.0},
        {"case": "c0002", D: 0.1, V: NAN, "solver.end_time": 1.0},
        {"case": "c0003", D: NAN, V: 5.0, "solver.end_time": 0.2},
    ])
    levels = plots.factor_levels(table, [D, V, "solver.end_time"], {D: 0.2, V: 1.0})
    assert list(levels) == [D, V]
    assert [(value, row["case"]) for value, row in levels[D]] == [(0.1, "c0002"), (0.2, "c0000"), (0.3, "c0001")]
    assert [(value, row["case"]) for value, row in levels[V]] == [(1.0, "c0000"), (5.0, "c0003")]


def test_puncture_depths_follow_the_event_names_not_the_list_positions():
    # no epithelium event: the summary's first puncture is the stroma's
    row = {"puncture_0_event": "stroma", "puncture_0_depth_mm": 0.3,
           "puncture_1_event": "cornea", "puncture_1_depth_mm": 0.7, "puncture_2_event": NAN,
           "puncture_2_depth_mm": NAN}
    depths = plots.puncture_depths(row)
    assert math.isnan(depths["epithelium"]) and (depths["stroma"], depths["cornea"]) == (0.3, 0.7)


def test_the_smoothed_peak_is_the_largest_running_mean_and_spreads_a_single_spike_over_its_window():
    depth = np.linspace(0.0, 1.0, 501)  # 0.002 mm spacing: 11 samples in 0.02 mm
    force = 0.5 * depth
    force[200] = 10.0  # one spike
    # the best window holding the spike starts at it; the ramp's last window is lower
    expected = (10.0 + 0.5 * depth[201:211].sum()) / 11
    assert expected > 0.5 * np.mean(depth[-11:])
    assert plots.smoothed_peak(depth, force) == pytest.approx(expected)
    assert plots.smoothed_peak(depth, 0.5 * depth) == pytest.approx(0.5 * np.mean(depth[-11:]))
    assert math.isnan(plots.smoothed_peak(depth, np.full(depth.shape, np.nan)))
