"""The intraocular pressure released when the cornea is cut through (scenarios._pressure_release).

Truths: the quintic smooth step's values (its ends and its midpoint, by symmetry), and the
uninterrupted run for the release carried through a checkpoint.
"""

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.scenarios._build import build
from corneasim.scenarios._pressure_release import PressureRelease, release_amplitude
from corneasim.scenarios._registry import load_scenario
from corneasim.solver._loads import pack_amplitudes
from corneasim.solver._amplitudes import Constant, SmoothStep, evaluate
from corneasim.solver._state import N_EVENTS, saved_fields


class Loads:
    """Just the pressure amplitude table and the event times of a state."""

    def __init__(self, amplitudes):
        self.pressure_amplitude_table = pack_amplitudes(amplitudes)
        self.event_time = np.full(N_EVENTS, np.nan)


@pytest.mark.parametrize("first", [Constant(0.8), SmoothStep(0.0, 0.5, 0.0, 0.8)])
def test_a_released_pressure_falls_smoothly_from_its_value_to_zero(first):
    """Released at t_e = 2 s over 1 s: 0.8 (its value) at 2 s, 0.4 at 2.5 s (the step's
    midpoint), 0 from 3 s; the other load keeps its amplitude; a narrow table is widened."""
    model = Loads([first, Constant(1.0)])
    release_amplitude(model, 0, 2.0, 1.0)
    table = model.pressure_amplitude_table
    values = [evaluate(table[0], t)[0] for t in (2.0, 2.5, 3.0, 10.0)]
    np.testing.assert_allclose(values, [0.8, 0.4, 0.0, 0.0], atol=1e-15)
    assert evaluate(table[1], 5.0)[0] == 1.0


def test_the_release_time_goes_through_a_checkpoint():
    """The release time and the released amplitude are state arrays (saved with it): a state
    restored from them releases no second time."""
    model, resumed = Loads([Constant(1.0)]), Loads([Constant(1.0)])
    release = PressureRelease([0], 0.5)
    release.trigger(model, 3.0)
    release.trigger(model, 4.0)  # once only
    for name in saved_fields():  # what a checkpoint of the state saves
        if hasattr(model, name):
            setattr(resumed, name, np.copy(getattr(model, name)))
    PressureRelease([0], 0.5).trigger(resumed, 3.1)
    np.testing.assert_array_equal(resumed.pressure_amplitude_table, model.pressure_amplitude_table)
    assert evaluate(model.pressure_amplitude_table[0], 3.5)[0] == 0.0


def test_a_release_needs_an_instrument():
    scenario, _, base = load_scenario("needle", ["mesh.preset=coarse"])
    pressures = [load.model_copy(update={"release_on_puncture": True}) for load in scenario.pressures]
    setup = build(scenario.model_copy(update={"pressures": pressures}), base)
    assert setup.pressure_release is not None
    with pytest.raises(InputError, match=r"pressures\[0\]\.release_on_puncture: needs an \[instrument\]"):
        build(scenario.model_copy(update={"pressures": pressures, "instrument": None}), base)
