"""The time loop: a generator of frames that writers, progress bars and tests consume.

::

    state = new_state(model)
    for frame in run(model, state, end_time=0.1, history_every=100, field_times=[0.05, 0.1]):
        if frame.history: writer.append(frame.history)
        if frame.checkpoint_due: save_checkpoint(path, model, frame.state)

Each step is a short table of contents of kernels (:func:`advance`); everything else in
the loop is bookkeeping done every k steps. The loop yields a :class:`Frame` whenever
something is due (history row, field output, checkpoint) and at the end. The state in a
frame is the live state: copy what you keep.

External-force hooks (e.g. rigid-instrument contact) are objects with

* ``name`` (str);
* ``add_forces(model, state, time, time_step, f_ext)``: add forces (N) at ``time`` into
  ``f_ext`` (n_nodes, dim), with ``state.u`` already at that time and ``state.v`` the
  half-step velocity; released nodes have ``state.node_active == 0``;
* ``outputs()`` -> dict of history columns (e.g. the force on the tool, N);
* optional ``checkpoint()`` -> dict of arrays and ``restore(arrays)``;
* optional ``cut_ratios()`` -> (elements, ratios) or None: a cutting rule's failure ratios of
  the step, which the loop merges into ``state.failure_ratio`` before the failure check.

Their work enters the external work of the energy balance.

Event terms (e.g. the puncture events and the pressure release of a scenario) are objects
with ``update(model, state) -> list of str``, called in every step that deleted elements,
after the deletion: they read the state, record their event times in ``state.event_time``
and act on the state (a released pressure); the names they return reach the consumers with
the next frame (``Frame.events``). Events are thus independent of how often frames are
yielded; the consumers only record.
"""

from __future__ import annotations

import math
import time as wallclock
from dataclasses import dataclass, field

import numpy as np

from corneasim.errors import InputError
from corneasim.solver import elements as element_kernels
from corneasim.solver._checks import SimulationError, check_state
from corneasim.solver._cyclic import couple_cyclic_pairs
from corneasim.solver._deletion import delete_elements
from corneasim.solver._integrate import (
    ENERGY_DAMPING, NO_REFERENCE, integrate_acceleration, integrate_velocity_displacement, kinetic_energy,
    mean_velocity)
from corneasim.solver._mass_scaling import rescale_masses
from corneasim.solver._outputs import field_output, history_row
from corneasim.solver._forces import eval_forces
from corneasim.solver._stable_step import stable_time_step


@dataclass
class Frame:
    """What the loop hands to its consumers.

    Attributes
    ----------
    time : float
        Simulated time, s.
    step : int
        Step number.
    state : State
        The live state (do not modify; copy to keep).
    history : dict or None
        A history row when one is due (columns: ``_outputs``).
    fields : dict or None
        Field arrays when a field output time was reached (``_outputs.field_output``).
    deletions : list of (float, int, str)
        Elements deleted since the previous frame: (time s, element, block).
    events : list of str
        Events the event terms reported since the previous frame (module notes).
    checkpoint_due : bool
        True when the consumer should save a checkpoint now (the state passed its checks).
    done : bool
        True for the last frame of the run.
    first_step_clock : float or None
        ``time.perf_counter()`` when this call's first step (and its failure check) ended, its
        kernels loaded (None in the frame before it): where a run's start-up ends.
    """

    time: float
    step: int
    state: object
    history: dict | None = None
    fields: dict | None = None
    deletions: list = field(default_factory=list)
    events: list = field(default_factory=list)
    checkpoint_due: bool = False
    done: bool = False
    first_step_clock: float | None = None


def damping_reference(model, state, damping: float, free_translation: bool) -> np.ndarray:
    """The velocity (mm/s) the step's damping acts relative to: the model's mean velocity
    (``state.reference_velocity``, which :func:`advance` updates every step) where it may
    translate freely and ``free_translation`` asks to spare that, else zeros."""
    if damping > 0.0 and free_translation and model.free_translation is not None:
        return state.reference_velocity
    return NO_REFERENCE


def advance(model, state, dt: float, hooks=(), damping: float = 0.0, relaxed: bool = False,
            free_translation: bool = True) -> None:
    """Take one central-difference step of size ``dt`` (s), updating ``state`` in place
    (``relaxed``: the Prony terms relax fully within the step; ``free_translation``: the
    damping spares the model's translation where it has one, :func:`run`)."""
    state.energies[ENERGY_DAMPING] += couple_cyclic_pairs(model, state)
    integrate_velocity_displacement(
        state.u, state.v, state.a, state.f_int, state.f_ext, state.dof_mass, dt, state.time_step,
        state.time, model.constraint_dof, model.constraint_kind, model.constraint_value,
        model.constraint_amplitude, model.amplitude_table, state.node_active, state.energies)
    time = state.time + dt
    eval_forces(model, state, dt, time, relaxed)
    for hook in hooks:
        hook.add_forces(model, state, time, dt, state.f_ext)
    for hook in hooks:  # cutting rules: the elements an instrument cuts fail as by their criterion
        cut = getattr(hook, "cut_ratios", None)
        failed = cut() if cut is not None else None
        if failed is not None:
            elements, ratios = failed
            state.failure_ratio[elements] = np.maximum(state.failure_ratio[elements], ratios)
    reference = damping_reference(model, state, damping, free_translation)
    if reference is not NO_REFERENCE:
        mean_velocity(state.v, state.dof_mass, model.free_translation, reference)
    integrate_acceleration(state.v, state.f_int, state.f_ext, state.dof_inverse_mass, state.dof_mass,
                           dt, damping, state.energy_rates, state.a, state.energies, reference)
    couple_cyclic_pairs(model, state, velocities=False)
    state.time = time
    state.step += 1
    state.time_step = dt


MINIMUM_STEP_RATIO = 1e-4
"""A stable step below this fraction of the smallest unscaled stable step of the reference mesh
stops the run: a crushed element (J > 0, but a sliver) would otherwise make the run take ever
smaller steps without end (LS-DYNA's TSMIN termination works the same way)."""


def update_time_step(model, state) -> None:
    """Set ``state.next_time_step`` from the current geometry (or check the fixed step)."""
    element_dt = element_kernels.stable_time_steps(state.elements, state.u)
    if model.radial_cracks is not None:  # a cut band's open cracks hold no material
        model.radial_cracks.stable_time_steps(state, element_dt)
    rescale_masses(model, state, element_dt)
    stable, element = stable_time_step(element_dt, state.density_scale, state.alive,
                                       model.safety_factor)
    if model.time_step is None:
        if not math.isfinite(stable):
            bad = np.flatnonzero((state.alive != 0) & ~np.isfinite(element_dt))
            if bad.size:
                element = int(bad[0])
                block = model.block_of(element)
                raise SimulationError(
                    f"simulation stopped at t = {state.time:.6g} s (step {state.step}): non-finite "
                    f"geometry (NaN or infinite displacement) in element {element} (block '{block}'); "
                    f"{bad.size} element(s) affected", state.time, element, block)
            raise SimulationError(f"simulation stopped at t = {state.time:.6g} s: no stable time "
                                  "step (no live element)", state.time)
        floor = MINIMUM_STEP_RATIO * model.safety_factor * float(np.min(model.element_time_step))
        if stable < floor:
            block = model.block_of(element)
            raise SimulationError(
                f"simulation stopped at t = {state.time:.6g} s (step {state.step}): the stable time "
                f"step fell to {stable:.3g} s, below {MINIMUM_STEP_RATIO:g} of the reference mesh's "
                f"{floor / MINIMUM_STEP_RATIO:.3g} s, in element {element} (block '{block}'): the "
                "element is crushed (solver.distortion_limit erodes such elements)",
                state.time, element, block)
        state.next_time_step = stable
        return
    limit = stable / model.safety_factor
    if model.time_step > limit:
        block = model.block_of(element)
        raise SimulationError(
            f"simulation stopped at t = {state.time:.6g} s (step {state.step}): the fixed time step "
            f"{model.time_step:.4g} s exceeds the stable limit {limit:.4g} s of element {element} "
            f"(block '{block}') in the deformed geometry", state.time, element, block)
    state.next_time_step = model.time_step


RECOMPUTE_AFTER_DELETION_EVERY = 5
"""Steps between stable-step updates during the ``time_step_every`` steps after a deletion."""


def _recent_deletion(model, state) -> bool:
    """True every ``RECOMPUTE_AFTER_DELETION_EVERY`` steps within ``time_step_every`` steps after a deletion.

    A deletion releases the stored energy of the dead elements; their neighbours then deform
    fast enough that a stable step (and variable mass scaling) ``time_step_every`` steps old
    is exceeded by 30-200% before the next update, which folds elements and blows the run up
    (docs/solver.md, "Element deletion and distortion control"). The step is therefore
    recomputed more often for a while after each deletion. Derived from the state, so a
    resumed run takes the same steps.
    """
    return (state.step % RECOMPUTE_AFTER_DELETION_EVERY == 0 and state.deleted_time.size > 0
            and state.time - state.deleted_time[-1] <= model.time_step_every * state.time_step)


def _check_positive_int(name, value):
    if value is not None and (int(value) != value or value < 1):
        raise InputError(f"{name}: expected an integer >= 1, got {value}")


def run(model, state, end_time: float, *, history_every: int = 100, field_times=(),
        checkpoint_every: int | None = None, deletion_every: int = 1, check_every: int = 100,
        hooks=(), events=(), damping: float = 0.0, runaway_factor: float = 10.0, relaxed: bool = False,
        free_translation: bool = True):
    """Integrate from ``state.time`` to ``end_time`` (s), yielding :class:`Frame` objects.

    Parameters
    ----------
    model : Model
    state : State
        Advanced in place (from :func:`new_state` or a checkpoint).
    end_time : float
        Time to stop at, s (the last step is shortened to land on it).
    history_every : int
        Steps between history rows (also at the start when ``state.step == 0`` and at the end).
    field_times : sequence of float
        Times (s) at which field frames are produced: at the first step reaching each time.
    checkpoint_every : int, optional
        Steps between ``checkpoint_due`` frames (None: never).
    deletion_every : int
        Steps between failure checks (element deletion), default every step.
    check_every : int
        Steps between robustness checks (NaN/Inf, J <= 0, runaway kinetic energy).
    hooks : sequence
        External-force hooks (module notes).
    events : sequence
        Event terms, updated in every step with deletions (module notes).
    damping : float
        Mass-proportional damping α, 1/s (0 for dynamics; > 0 to settle a quasi-static preload).
    runaway_factor : float
        Kinetic energy above this multiple of the energy input stops the run.
    relaxed : bool
        Every Prony term relaxes fully within each step (long-term stress), as in a load
        held for much longer than the relaxation times (a preload: :func:`preload`).
    free_translation : bool
        The damping acts on the velocity relative to the model's mean velocity in the
        components where it may translate as a whole (``Model.free_translation``, set by
        elastic supports), so that it does not resist that translation; False: on the
        absolute velocity everywhere (a preload settles the translation too).

    Raises
    ------
    SimulationError
        When a check fails (after the frames up to the previous good state were yielded).
    """
    for name, value in (("history_every", history_every), ("checkpoint_every", checkpoint_every),
                        ("deletion_every", deletion_every), ("check_every", check_every)):
        _check_positive_int(name, value)
    if not damping >= 0.0:
        raise InputError(f"damping: expected a rate >= 0 1/s, got {damping}")
    pending_fields = sorted(float(t) for t in field_times if t > state.time or (t == state.time == 0.0))
    deleted = np.empty(model.n_elements, np.int64)
    new_deletions: list = []
    new_events: list = []
    if state.step == 0:
        update_time_step(model, state)
        kinetic = kinetic_energy(state.v, state.a, state.dof_mass, state.time_step, model.dof_constrained,
                                 state.node_active)
        fields = None
        if pending_fields and pending_fields[0] <= state.time:
            pending_fields.pop(0)
            fields = field_output(model, state)
        yield Frame(state.time, state.step, state, history_row(model, state, *kinetic, hooks), fields)
    tolerance = 1e-9 * max(abs(end_time), 1e-30)
    reference = damping_reference(model, state, damping, free_translation)
    first_step_clock = None
    while end_time - state.time > tolerance:
        if (state.step % model.time_step_every == 0 or state.next_time_step <= 0.0
                or _recent_deletion(model, state)):
            update_time_step(model, state)
        dt = min(state.next_time_step, end_time - state.time)
        try:
            advance(model, state, dt, hooks, damping, relaxed, free_translation)
        except (ArithmeticError, np.linalg.LinAlgError) as error:
            check_state(model, state, 0.0, math.inf)
            raise SimulationError(f"simulation stopped at t = {state.time:.6g} s (step {state.step}): "
                                  f"force evaluation failed ({error})", state.time) from None
        step = state.step
        if step % deletion_every == 0:
            deletions = delete_elements(model, state, deleted, damping, reference)
            if deletions:
                new_deletions += deletions
                for term in events:
                    new_events += term.update(model, state)
        if first_step_clock is None:
            first_step_clock = wallclock.perf_counter()
        done = end_time - state.time <= tolerance
        history_due = step % history_every == 0 or done
        fields_due = bool(pending_fields) and pending_fields[0] <= state.time + tolerance
        checkpoint_due = checkpoint_every is not None and step % checkpoint_every == 0
        if not (history_due or fields_due or checkpoint_due or step % check_every == 0):
            continue
        kinetic = kinetic_energy(state.v, state.a, state.dof_mass, state.time_step, model.dof_constrained,
                                 state.node_active)
        check_state(model, state, kinetic[0], runaway_factor, geometry=step % check_every == 0)
        if not (history_due or fields_due or checkpoint_due or done):
            continue
        fields = None
        if fields_due:
            while pending_fields and pending_fields[0] <= state.time + tolerance:
                pending_fields.pop(0)
            fields = field_output(model, state)
        yield Frame(state.time, step, state,
                    history_row(model, state, *kinetic, hooks) if history_due else None,
                    fields, new_deletions, new_events, checkpoint_due, done, first_step_clock)
        new_deletions, new_events = [], []


def preload(model, state, duration: float, damping: float, **options):
    """Quasi-static preload stage: :func:`run` for ``duration`` (s) with mass-proportional damping.

    The loads (e.g. the intraocular pressure, given a smooth-step amplitude that rises over
    the first part of ``duration`` and then stays at 1) build up and the damping ``damping``
    (α, 1/s; about twice the lowest natural angular frequency of the eye damps it
    critically) removes the kinetic energy so the next stage starts from a settled state.
    Instruments should be kept out of contact (their motion starts after the preload).
    The damping acts on the absolute velocity, the model's translation on elastic supports
    included (``run``'s ``free_translation=False``).
    With ``relaxed=True`` (passed on to :func:`run`) the Prony terms relax within each step,
    so the stage ends in the equilibrium of loads held long before the procedure, as in an
    eye kept at its intraocular pressure, and nothing creeps afterwards under those loads.
    """
    yield from run(model, state, state.time + duration, damping=damping, free_translation=False, **options)
