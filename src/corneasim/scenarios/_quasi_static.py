"""The quasi-static recipe (``[solver] quasi_static = true``): ramp, mass scaling and damping from the model.

An explicit run of a prescribed displacement or pressure is quasi-static when the load
changes slowly against the model's lowest natural period T_1: a load that rises smoothly
(zero rate at both ends) over n T_1 excites the fundamental mode to a kinetic energy of a
small fraction of the strain energy, falling fast with n (a quintic smooth step; Abaqus
Analysis User's Guide, "Quasi-static analysis", recommends loading times of 10 or more
periods of the fundamental mode and a kinetic energy of a few per cent of the internal
energy at most). The recipe (``docs/quasi-static.md``):

1. **Ramp.** Prescribed motions and pressures with the default constant amplitude rise by a
   smooth step from 0 to their value over the ramp time T_r (``solver.ramp_time``; default
   :data:`RAMP_FRACTION` of the end time), then hold. Loads with an amplitude of their own
   keep it (a relaxation test's ramp-hold); T_r then defaults to their shortest rise (a
   smooth step's t1 - t0, a table's shortest changing segment).
2. **Mass scaling.** T_1 of the model (:func:`~corneasim.solver.lowest_period`)
   sets the mass scaling: the target time step grows until the mass-scaled model's T_1 is
   T_r / n (n = ``solver.ramp_periods``), so the run takes no more steps than a quasi-static
   run needs; inertia stays negligible by construction, and the physical time (Prony
   relaxation) is unchanged. A model already slower than that is not scaled.
3. **Damping.** Mass-proportional damping alpha = 2 zeta omega_1 with zeta =
   :data:`DAMPING_RATIO` of the fundamental mode: it removes the mode's residual vibration
   within a few periods and costs a force error of at most about zeta / (pi n) while the load
   moves, none once it holds (the damping force is alpha m v). A ``solver.damping`` > 0 wins.
4. **Report.** ``summary.json`` gets ``quasi_static`` (T_1 before and after scaling, T_r,
   the target step, the damping, the largest KE/IE once the internal energy is 5% of its
   peak, and whether it met :data:`KINETIC_TARGET`); a miss is also a warning.
"""

from __future__ import annotations

import math
from pathlib import Path

from corneasim.scenarios._postprocess import max_kinetic_to_internal
from corneasim.solver import SmoothStepAmplitude, lowest_period

RAMP_FRACTION = 0.8
"""Default ramp time as a fraction of the end time (the rest holds the load and settles)."""

DAMPING_RATIO = 0.2
"""Fraction zeta of critical damping of the fundamental mode."""

KINETIC_TARGET = 0.01
"""Largest kinetic / internal energy ratio of a quasi-static run (once loaded)."""

SCALING_ITERATIONS = 4
"""Rebuilds of the model while the target step is adjusted to the period."""


def rise_time(amplitude, end_time: float) -> float:
    """Shortest time over which ``amplitude`` changes (s): the quasi-static ramp it imposes."""
    if amplitude.type == "smooth-step":
        return amplitude.t1 - amplitude.t0
    if amplitude.type == "tabular":
        segments = [t1 - t0 for t0, t1, a0, a1 in zip(amplitude.times, amplitude.times[1:], amplitude.values,
                                                     amplitude.values[1:]) if a1 != a0 and t1 > t0]
        return min(segments, default=end_time)
    return end_time


def _ramped(amplitude, ramp_time: float):
    if amplitude.type != "constant":
        return amplitude
    return SmoothStepAmplitude(t0=0.0, t1=ramp_time, a0=0.0, a1=amplitude.value)


def prepare(scenario, base_dir: str | Path = "."):
    """The scenario with the recipe applied, and the recipe's report (None without ``quasi_static``)."""
    solver = scenario.solver
    if not solver.quasi_static:
        return scenario, None
    from corneasim.scenarios._build import build

    loads = [c for c in scenario.constraints if c.prescribed] + list(scenario.pressures)
    own = [load.amplitude for load in loads if load.amplitude.type != "constant"]
    ramp = solver.ramp_time or (min(rise_time(a, solver.end_time) for a in own) if own
                                else RAMP_FRACTION * solver.end_time)
    ramped = scenario.model_copy(update={
        "constraints": [c.model_copy(update={"amplitude": _ramped(c.amplitude, ramp)}) if c.prescribed else c
                        for c in scenario.constraints],
        "pressures": [p.model_copy(update={"amplitude": _ramped(p.amplitude, ramp)}) for p in scenario.pressures]})
    scale = solver.time_scaling
    wanted = ramp / scale / solver.ramp_periods  # the mass-scaled T_1, solver time
    model = build(ramped, base_dir).model
    natural = period = lowest_period(model)
    target = solver.target_time_step
    for _ in range(SCALING_ITERATIONS):  # the scaled periods grow as the target step
        if period >= 0.98 * wanted and (target == solver.target_time_step or period <= 1.02 * wanted):
            break
        step = float(model.stable_time_step()[0])  # the target compares with the step after the safety factor
        target = max(solver.target_time_step or 0.0, step * wanted / period)
        trial = ramped.model_copy(update={"solver": ramped.solver.model_copy(update={"target_time_step": target})})
        model = build(trial, base_dir).model
        period = lowest_period(model)
    damping = solver.damping if solver.damping > 0.0 else 2.0 * DAMPING_RATIO * (2.0 * math.pi / period) / scale
    result = ramped.model_copy(update={"solver": ramped.solver.model_copy(update={
        "target_time_step": target, "damping": damping})})
    report = {
        "lowest_period_s": natural * scale,
        "lowest_period_scaled_s": period * scale,
        "ramp_time_s": ramp,
        "ramp_periods": ramp / (period * scale),
        "target_time_step_s": target,
        "added_mass_fraction": float(model.added_mass_fraction),
        "damping_per_s": damping,
        "kinetic_to_internal_target": KINETIC_TARGET,
    }
    return result, report


def finish(report: dict, history: dict, warnings: list) -> dict:
    """The report with the run's largest KE/IE; a warning when it missed the target."""
    ratio = max_kinetic_to_internal(history)
    report = {**report, "max_kinetic_to_internal": ratio, "met": ratio <= KINETIC_TARGET}
    if not report["met"]:
        warnings.append(f"quasi-static: kinetic energy reached {100 * ratio:.2g}% of the internal energy (target "
                        f"{100 * KINETIC_TARGET:g}%): lengthen solver.ramp_time or raise solver.ramp_periods")
    if report["ramp_periods"] < 0.98 * 10:
        warnings.append(f"quasi-static: the ramp lasts {report['ramp_periods']:.3g} lowest periods only")
    return report
