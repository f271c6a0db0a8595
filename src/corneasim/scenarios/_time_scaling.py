"""Time scaling: run a slow quasi-static process lambda times faster without changing its physics.

With ``solver.time_scaling = lambda`` every time in the scenario stays in *physical*
time and the solver integrates in the compressed time :math:`\\hat t = t / \\lambda`:

* durations and instants divide by lambda (``end_time``, the preload's ``duration``,
  amplitude start times, smooth-step ``t0``/``t1``, tabular ``times``);
* rates multiply by lambda (a linear amplitude's ``rate``, a Fourier amplitude's
  ``circular_frequency``, a prescribed ``velocity``, the preload's mass-proportional
  ``damping``, the Karnopp friction's validity speed), a viscous friction coefficient
  divides by lambda (same force at the lambda-times faster slip);
* every Prony relaxation time divides by lambda (:func:`scaled_material`).

A material point then sees the same deformation history as a function of
:math:`\\hat t \\lambda = t`: the hereditary integral
:math:`S(t) = \\int_0^t G(t - s)\\,\\dot{\\bar S}_0(s)\\,ds` with
:math:`G(t) = g_\\infty + \\sum_i g_i e^{-t/\\tau_i}` is invariant under
:math:`t \\to \\hat t = t/\\lambda,\\ \\tau_i \\to \\tau_i/\\lambda` (Simo & Hughes,
*Computational Inelasticity*, 1998, sec. 10.3). Only inertia changes: accelerations
grow as lambda squared, exactly as a uniform mass scaling by lambda squared would
(Abaqus Analysis User's Guide, "Mass scaling"; docs/trephination.md). The results are
reported back in physical time (``history.csv`` ``time_s``, deletions, field frames), so
they compare directly with an experiment. Kinetic energies are those of the compressed
run (the quasi-static indicator), the mass-scaling target and fixed step are solver-time
steps.
"""

from __future__ import annotations

import dataclasses

from corneasim.materials import KernelMaterial


def _amplitude(amplitude, factor: float):
    """An amplitude table in solver time (``factor`` = lambda)."""
    kind = amplitude.type
    if kind == "constant":
        return amplitude
    if kind == "linear":
        return amplitude.model_copy(update={"rate": amplitude.rate * factor,
                                            "start_time": amplitude.start_time / factor})
    if kind == "smooth-step":
        return amplitude.model_copy(update={"t0": amplitude.t0 / factor, "t1": amplitude.t1 / factor})
    if kind == "tabular":
        return amplitude.model_copy(update={"times": [t / factor for t in amplitude.times]})
    return amplitude.model_copy(update={"circular_frequency": amplitude.circular_frequency * factor,
                                        "start_time": amplitude.start_time / factor})


def scaled_scenario(scenario):
    """The scenario with its procedure compressed into solver time (identity for lambda = 1).

    Parameters
    ----------
    scenario : corneasim.scenarios._format.Scenario
        Validated scenario in physical time; ``scenario.solver.time_scaling`` is lambda.

    Returns
    -------
    Scenario
        A copy in solver time (the original is not modified); ``solver.time_scaling`` is kept
        so that results can be mapped back (t = lambda t_solver).
    """
    factor = scenario.solver.time_scaling
    if factor == 1.0:
        return scenario
    constraints = [c.model_copy(update={
        "amplitude": _amplitude(c.amplitude, factor),
        "value": c.value * factor if c.prescribed == "velocity" else c.value}) for c in scenario.constraints]
    pressures = [p.model_copy(update={"amplitude": _amplitude(p.amplitude, factor),
                                      "release_duration": p.release_duration / factor}) for p in scenario.pressures]
    update = {"constraints": constraints, "pressures": pressures,
              "solver": scenario.solver.model_copy(update={"end_time": scenario.solver.end_time / factor,
                                                           "damping": scenario.solver.damping * factor})}
    if scenario.preload is not None:
        update["preload"] = scenario.preload.model_copy(update={
            "duration": scenario.preload.duration / factor, "damping": scenario.preload.damping * factor})
    if scenario.instrument is not None:
        instrument = scenario.instrument
        motion = instrument.motion.model_copy(update={"insertion": _amplitude(instrument.motion.insertion, factor),
                                                      "rotation": _amplitude(instrument.motion.rotation, factor)})
        friction = instrument.contact.friction
        friction = friction.model_copy(update={"viscous_coefficient": friction.viscous_coefficient / factor,
                                               "minimum_valid_speed": friction.minimum_valid_speed * factor})
        contact = instrument.contact.model_copy(update={"friction": friction})
        update["instrument"] = instrument.model_copy(update={"motion": motion, "contact": contact})
    return scenario.model_copy(update=update)


def scaled_material(material: KernelMaterial, factor: float) -> KernelMaterial:
    """The material with every Prony relaxation time divided by ``factor`` (lambda), s."""
    if factor == 1.0 or not material.prony_tau:
        return material
    return dataclasses.replace(material, prony_tau=tuple(tau / factor for tau in material.prony_tau))
