"""The intraocular pressure falls when the instrument cuts through the cornea.

Once a cut joins the anterior surface to the inner one (the ``cornea`` puncture event,
``scenarios._punctures``), the anterior chamber is open: the aqueous humour leaks and the
pressure it held falls. A model that kept pressing the remaining inner wall would push the
eye with the resultant of the pressure over the hole, p π R² ≈ 0.10 N for the 7.5 mm trephine
at 17.5 mmHg (no such force exists once the fluid is gone), and, in the trephine, onto the
button of cornea left inside the instrument. A pressure load with ``release_on_puncture``
therefore falls smoothly from its value at the event to 0 over ``release_duration``:

.. math::

    p(t) = p(t_e)\\, \\bigl(1 - S\\bigl((t - t_e)/\\tau\\bigr)\\bigr),

S the quintic smooth step (``solver._amplitudes.SmoothStep``), t_e the solver time of the
step whose deletion completes the cut, τ = ``release_duration``. The new amplitude and the release time are part of the
:class:`~corneasim.solver.State`, so that a resumed run releases the pressure as the
uninterrupted one did.
"""

from __future__ import annotations

import math

import numpy as np

from corneasim.solver import EVENT_CORNEA, EVENT_RELEASE, SmoothStep, evaluate_amplitude


def release_amplitude(state, load: int, time: float, duration: float) -> None:
    """Make pressure load ``load`` fall from its value at ``time`` (s) to 0 over ``duration`` (s).

    Replaces its row of ``state.pressure_amplitude_table`` (widening the table if needed)."""
    table = state.pressure_amplitude_table
    current = float(evaluate_amplitude(table[load], time)[0])
    packed = SmoothStep(time, time + duration, current, 0.0).pack()
    if packed.size > table.shape[1]:
        table = np.concatenate([table, np.zeros((table.shape[0], packed.size - table.shape[1]))], axis=1)
    table[load, :] = 0.0
    table[load, :packed.size] = packed
    state.pressure_amplitude_table = table


class PressureRelease:
    """Releases the pressure loads ``loads`` (indices in the scenario's list) over ``duration`` (s)
    from the moment :meth:`trigger` is called: an event term of the time loop
    (:func:`corneasim.solver.run`; :meth:`update`) that does so in the step in which the cut
    leaves the cornea. The release time and the new amplitudes are the state's
    (``State.event_time``, ``State.pressure_amplitude_table``), so a checkpoint carries them."""

    def __init__(self, loads: list[int], duration: float):
        self.loads = list(loads)
        self.duration = float(duration)

    def trigger(self, state, time: float) -> None:
        """The chamber opened at solver time ``time`` (s): release the loads (once)."""
        if math.isnan(state.event_time[EVENT_RELEASE]):
            state.event_time[EVENT_RELEASE] = float(time)
            for load in self.loads:
                release_amplitude(state, load, float(time), self.duration)

    def update(self, model, state) -> list[str]:
        """The event term: release when the ``cornea`` puncture event has been recorded (by the
        puncture term before it in the same step, ``scenarios._punctures.PunctureEvents``); no
        name is reported (the release time is ``state.event_time[EVENT_RELEASE]``)."""
        if not math.isnan(state.event_time[EVENT_CORNEA]):
            self.trigger(state, state.time)
        return []
