"""Event terms of the time loop: updated in the step of a deletion, whatever the output interval.

Truth: the deletion's own record (``state.deleted_time``), which the loop writes in the step
the element dies; an event term must see that step, and its result must not depend on how
often history rows are written.
"""

import math

import numpy as np

from corneasim.scenarios._pressure_release import PressureRelease
from corneasim.solver import EVENT_CORNEA, EVENT_RELEASE, SmoothStep, evaluate_amplitude, new_state, run
from test_solver_deletion import RAMP, SHEAR, STRAIN, bar_model


class StepRecorder:
    """An event term that reports 'death' once, with the time and step it was called at."""

    def __init__(self):
        self.calls = []

    def update(self, model, state):
        self.calls.append((state.time, state.step))
        return ["death"] if len(self.calls) == 1 else []


def run_with_term(history_every):
    model = bar_model(6, 2, 0.97 * 2 * SHEAR * STRAIN)
    state, term = new_state(model), StepRecorder()
    frames = [(frame.step, frame.events) for frame in run(model, state, 3 * RAMP, history_every=history_every,
                                                          events=[term])]
    return state, term, frames


def test_an_event_term_runs_in_the_step_of_the_deletion_whatever_the_history_interval():
    state, term, frames = run_with_term(1)
    rare_state, rare_term, rare_frames = run_with_term(100000)
    assert term.calls == rare_term.calls  # independent of the output interval
    assert len(term.calls) == 1 and term.calls[0][0] == state.deleted_time[0]
    step = term.calls[0][1]
    assert [events for s, events in frames if s == step] == [["death"]]  # the frame of that step
    assert [events for _, events in rare_frames if events] == [["death"]]  # reported with the last frame
    assert rare_frames[-1][1] == ["death"]
    np.testing.assert_array_equal(rare_state.u, state.u)


class ReleaseState:
    """The state arrays a pressure release reads and writes."""

    def __init__(self, time):
        self.time = time
        self.pressure_amplitude_table = SmoothStep(0.0, 1.0).pack()[None, :].copy()
        self.event_time = np.full(4, np.nan)


def test_the_pressure_release_term_releases_in_the_step_of_the_cut_through_and_once():
    """Smooth step from the value at t_e (1, the load fully on) to 0 over 2 s: 0.5 at t_e + 1 s."""
    state = ReleaseState(time=3.0)
    release = PressureRelease([0], 2.0)
    assert release.update(None, state) == [] and math.isnan(state.event_time[EVENT_RELEASE])  # not yet cut
    state.event_time[EVENT_CORNEA] = 3.0
    release.update(None, state)
    state.time = 3.5
    release.update(None, state)  # once only
    assert state.event_time[EVENT_RELEASE] == 3.0
    values = [evaluate_amplitude(state.pressure_amplitude_table[0], t)[0] for t in (3.0, 4.0, 5.0)]
    np.testing.assert_allclose(values, [1.0, 0.5, 0.0], atol=1e-15)
