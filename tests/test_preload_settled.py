"""How settled the eye is when the preload ends: the out-of-balance force and the warning.

Independent truths: a body at rest under a load it has not yet deformed for has
f_int = 0, so its out-of-balance ratio is exactly 1; an unloaded one has none. A long,
damped preload reaches static equilibrium (ratio near 0, no warning); a preload cut short
leaves the eye moving (warning, ratio above the limit).
"""

import numpy as np
import pytest

from corneasim.scenarios import run_scenario
from corneasim.scenarios._build import build
from corneasim.scenarios._postprocess import PRELOAD_OUT_OF_BALANCE_LIMIT
from corneasim.scenarios._registry import load_scenario
from corneasim.solver import new_state, out_of_balance
from corneasim.solver._pressure import eval_pressure_forces

COARSE = ["mesh.preset=coarse", "solver.target_time_step=2e-5", "solver.end_time=0.002"]


def test_a_loaded_body_at_rest_is_wholly_out_of_balance():
    scenario, _, base_dir = load_scenario("needle", COARSE)
    model = build(scenario, base_dir).model
    state = new_state(model)
    assert out_of_balance(model, state) == 0.0  # no load
    eval_pressure_forces(model.mesh.points, state.u, model.pressure_face_nodes, model.pressure_face_element,
                         model.pressure_value, model.pressure_amplitude, model.pressure_amplitude_table,
                         state.alive, 1.0, state.f_ext)
    assert np.abs(state.f_ext).max() > 0.0
    assert out_of_balance(model, state) == pytest.approx(1.0, rel=1e-12)


def _preload(duration, damping):
    return run_scenario("needle", [*COARSE, f"preload.duration={duration}", f"preload.damping={damping}"]).summary


def test_a_long_preload_settles_and_a_short_one_is_reported():
    settled = _preload(0.4, 200)["run"]
    assert settled["preload"]["out_of_balance"] < 0.1 * PRELOAD_OUT_OF_BALANCE_LIMIT
    assert not any("preload did not settle" in w for w in settled["warnings"])
    short = _preload(0.02, 200)["run"]
    assert short["preload"]["out_of_balance"] > PRELOAD_OUT_OF_BALANCE_LIMIT
    assert short["preload"]["max_speed_mm_per_s"] > 10 * settled["preload"]["max_speed_mm_per_s"]
    assert any("preload did not settle" in w and "preload.duration" in w for w in short["warnings"])


def test_a_cyclic_pair_counts_as_one_node():
    scenario, _, base_dir = load_scenario("trephine", ["mesh.preset=coarse"])
    model = build(scenario, base_dir).model
    master, slave = model.cyclic_master, model.cyclic_slave
    assert master.size > 0
    state = new_state(model)
    rng = np.random.default_rng(3)
    state.f_ext[:] = rng.normal(0.0, 1e-3, state.f_ext.shape)
    assert out_of_balance(model, state) == pytest.approx(1.0, rel=1e-12)  # at rest, nothing carried yet
    # the pair's master carries the whole applied force f_a + R^T f_b, the slave none: balanced
    rotation = np.array([-1.0, -1.0, 1.0])
    state.f_int[:] = state.f_ext
    state.f_int[master] = state.f_ext[master] + rotation * state.f_ext[slave]
    state.f_int[slave] = 0.0
    assert out_of_balance(model, state) < 1e-12
    state.f_int[slave] = state.f_ext[slave]  # the slave's force counted twice
    assert out_of_balance(model, state) > 1e-3
