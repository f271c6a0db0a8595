"""The quasi-static recipe: lowest period, ramp, mass scaling, damping and the KE/IE report.

Truths: a slender bar fixed at one end has the lowest axial period T_1 = 4 L / sqrt(E / rho);
a cylinder on a frictionless base compressed by u carries F = E pi R^2 u / H (uniaxial
stress) once the run is quasi-static.
"""

import numpy as np
import pytest

import corneasim
from corneasim.mesh import write_mesh
from corneasim.scenarios import build, load_scenario
from corneasim.scenarios._quasi_static import rise_time
from corneasim.solver import SmoothStepAmplitude, TabularAmplitude, lowest_period

from byom_helpers import SUBSTRATE, compression_scenario, cylinder_mesh


def test_lowest_period_of_a_bar(tmp_path):
    write_mesh(cylinder_mesh(1.0, 10.0, 2, 20), tmp_path / "bar.inp")
    (tmp_path / "bar.toml").write_text(f"""
name = "bar"
[mesh]
file = "bar.inp"
[materials]
solid = {{ material = "{SUBSTRATE.as_posix()}" }}
[[constraints]]
node_set = "bottom"
fixed = "rz"
[solver]
end_time = 1e-3
""")
    scenario, _, base = load_scenario(str(tmp_path / "bar.toml"))
    period = lowest_period(build(scenario, base).model)
    assert period == pytest.approx(4 * 10.0 / np.sqrt(1.0 / 1.0e-9), rel=0.02)


def test_rise_time_of_amplitudes():
    assert rise_time(SmoothStepAmplitude(t0=1.0, t1=3.5), 10.0) == 2.5
    assert rise_time(TabularAmplitude(times=[0.0, 2.0, 100.0, 101.0], values=[0.0, 1.0, 1.0, 0.5]), 200.0) == 1.0


@pytest.fixture(scope="module")
def recipe_run(tmp_path_factory):
    path = compression_scenario(tmp_path_factory.mktemp("quasi"), end_time=1.0)
    text = path.read_text().replace('amplitude = { type = "smooth-step", t0 = 0.0, t1 = 0.6 }\n', "")
    path.write_text(text.replace("damping = 2000.0", "quasi_static = true"))
    return corneasim.run_scenario(path)


def test_recipe_ramps_scales_and_reports(recipe_run):
    report = recipe_run.summary["quasi_static"]
    assert report["ramp_time_s"] == pytest.approx(0.8)  # 0.8 of the end time: the load had no amplitude
    assert report["ramp_periods"] == pytest.approx(20.0, rel=0.03)
    assert report["lowest_period_scaled_s"] == pytest.approx(0.8 / 20.0, rel=0.03)
    assert report["damping_per_s"] == pytest.approx(2 * 0.2 * 2 * np.pi / report["lowest_period_scaled_s"])
    assert report["met"] and report["max_kinetic_to_internal"] < 0.01
    assert recipe_run.summary["run"]["steps"] < 2000  # mass-scaled to the period: a few hundred steps
    history = recipe_run.history
    x = np.clip(history["time_s"] / 0.8, 0.0, 1.0)
    smooth_step = x ** 3 * (10 - 15 * x + 6 * x ** 2)  # the quintic step 0 -> 1 over the ramp
    np.testing.assert_allclose(history["prescribed_top_z_mm"], -0.01 * smooth_step, atol=1e-9)
    assert history["base_N"][-1] == pytest.approx(np.pi * 0.01, rel=0.02)


def test_a_short_ramp_is_a_warning(tmp_path):
    path = compression_scenario(tmp_path, end_time=1.0)
    text = path.read_text().replace('amplitude = { type = "smooth-step", t0 = 0.0, t1 = 0.6 }\n', "")
    path.write_text(text.replace("damping = 2000.0", "quasi_static = true\nramp_time = 1.0e-4\nramp_periods = 2.0"))
    result = corneasim.run_scenario(path, ["solver.end_time=2e-4"])
    assert any("lowest periods only" in w for w in result.summary["run"]["warnings"])
    assert result.summary["quasi_static"]["target_time_step_s"] is None  # the model is slower: no scaling
