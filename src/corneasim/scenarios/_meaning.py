"""Checks that a valid scenario also means something, before any file is written.

The schema (:mod:`corneasim.scenarios._format`, strict types, finite numbers) accepts every
value of the right type and range; some combinations still describe no experiment. These
checks refuse them with one :class:`~corneasim.errors.InputError` naming the key, or warn:

* :func:`check_scenario` (the scenario alone): an instrument pushed at a constant rate must
  move into the tissue (a rate <= 0 never reaches it); the time step (``solver.time_step``
  or the mass-scaling target ``solver.target_time_step``) must resolve every stage with at
  least :data:`MIN_STEPS_PER_STAGE` steps. A larger step is no stable explicit
  integration of the stage at all: at ``target_time_step = 1`` s mass scaling makes every
  element "stable", yet the needle jumps through the cornea in one step and the run ends
  in runaway kinetic energy.
* :func:`check_setup` (the built model): mass scaling adding more than
  :data:`ADDED_MASS_WARNING` times the physical mass is reported as a warning of the run
  (``summary.json`` ``run.warnings``), naming the densest element's block: inertia then
  dominates whatever the model was meant to show (a 1e-7 mm epithelium made the eye
  2.3e7 times heavier).
"""

from __future__ import annotations

import numpy as np

from corneasim.errors import InputError

MIN_STEPS_PER_STAGE = 10
"""Fewest time steps a stage (the preload, the procedure) may take."""

ADDED_MASS_WARNING = 1.0e6
"""Added mass (a multiple of the physical mass) above which a run warns. The built-in scenarios'
presets add 6.3e2 to 1.4e3 (needle) and 8.4e4 to 2.4e5 (trephine, whose thin epithelium under a
time-scaled procedure takes most of it)."""


def check_scenario(scenario) -> None:
    """InputError for a valid scenario that describes no run (module notes)."""
    instrument = scenario.instrument
    if instrument is not None:
        insertion = instrument.motion.insertion
        if getattr(insertion, "type", None) == "linear" and not insertion.rate > 0.0:
            raise InputError(f"instrument.motion.insertion.rate: expected a rate > 0 mm/s (into the tissue), "
                             f"got {insertion.rate!r}: the instrument would never reach it")
    solver = scenario.solver
    stages = [("solver.end_time", solver.end_time / solver.time_scaling)]
    if scenario.preload is not None:
        stages.append(("preload.duration", scenario.preload.duration))
    for key in ("time_step", "target_time_step"):
        step = getattr(solver, key)
        if step is None:
            continue
        for stage, length in stages:
            if step * MIN_STEPS_PER_STAGE > length:
                raise InputError(f"solver.{key}: {step:g} s leaves fewer than {MIN_STEPS_PER_STAGE} steps in "
                                 f"{stage} ({length:g} s in solver time); expected at most "
                                 f"{length / MIN_STEPS_PER_STAGE:.3g} s")


def check_setup(setup) -> None:
    """Warnings (``setup.warnings``) for a built model that runs but hardly means what was meant."""
    model = setup.model
    added = float(model.added_mass_fraction)
    if added > ADDED_MASS_WARNING:
        densest = int(np.argmax(model.density_scale))
        setup.warnings.append(
            f"mass scaling (solver.target_time_step = {setup.scenario.solver.target_time_step:g} s) adds "
            f"{added:.3g} times the physical mass, up to {float(model.density_scale[densest]):.3g} times the "
            f"density in block '{model.block_of(densest)}' (element {densest}): inertia dominates the "
            "response; check the mesh's smallest elements or lower the target")
