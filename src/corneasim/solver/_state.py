"""The changing state of a simulation: a plain container of arrays a checkpoint can save.

Everything that changes during a run is here, so that the :class:`~corneasim.solver.Model`
stays as :func:`~corneasim.solver.build_model` made it and a checkpoint is the state (plus
the scenario that builds the model): the kinematics and forces, the element history,
deletion and softening damage, the masses that variable mass scaling changes, the pressure
amplitudes that a release replaces, the event times and the damping's reference velocity.
Two fields are derived, not saved (``DERIVED``): the element set the kernels read (the
model's, or a copy with the softening elements' material rows) and those rows' bookkeeping;
:func:`attach_derived` rebuilds them from the saved ones.

Time levels follow the central-difference scheme: displacement, forces and acceleration
at t^n, velocity at the half step t^{n-1/2}.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields

import numpy as np

from corneasim.solver import elements as element_kernels
from corneasim.solver._deletion import update_node_activity
from corneasim.solver._integrate import ENERGY_INITIAL_KINETIC, N_ENERGIES
from corneasim.solver._forces import eval_forces
from corneasim.solver._softening import SofteningRows, restore_softening_rows

DERIVED = {"derived": True}
"""Field metadata of the state's derived fields (rebuilt by :func:`attach_derived`, not saved)."""


@dataclass
class State:
    """Everything that changes during a run (units mm, s, N, tonne, mJ).

    Attributes
    ----------
    time : float
        t^n, s.
    step : int
        n, steps taken since the start of the analysis.
    time_step : float
        Δt^{n-1/2}, the last step taken, s (0 before the first step).
    next_time_step : float
        The step the next increment will take before clipping to output times, s.
    u : ndarray (n_nodes, dim) float64
        Displacement u^n, mm.
    v : ndarray (n_nodes, dim) float64
        Velocity v^{n-1/2}, mm/s.
    a : ndarray (n_nodes, dim) float64
        Unconstrained acceleration (f_ext - f_int) / m at t^n, mm/s^2.
    f_int, f_ext : ndarray (n_nodes, dim) float64
        Internal and external nodal forces at t^n, N (full ring when axisymmetric).
    history : ndarray float64
        Element history variables (layout owned by the element kernels).
    alive : ndarray (n_elements,) uint8
        1 alive, 0 deleted (irreversible).
    node_active : ndarray (n_nodes,) uint8
        1 when the node belongs to a live element; released nodes (0) are free and
        ignored by boundary conditions and contact.
    failure_ratio : ndarray (n_elements,) float64
        Failure criterion / limit at t^n (0 for dead elements or no criterion).
    energy_rates : ndarray (3,) float64
        Hourglass energy (mJ) and bulk-viscous and viscoelastic powers (mJ/s) at t^n.
    energies : ndarray (N_ENERGIES,) float64
        Accumulated energies, mJ (``_integrate.ENERGY_*`` indices).
    deleted_element : ndarray (n_deleted,) int64
        Deleted elements in order of deletion.
    deleted_time : ndarray (n_deleted,) float64
        Their deletion times, s.
    damage : ndarray (n_elements, 3) float64
        Softening state (``_softening``): damage D, the largest undamaged failure ratio
        kappa (0 while intact) and its value kappa_u at which the element is spent;
        dimensionless.
    density_scale : ndarray (n_elements,) float64
        Mass-scaling factor of each element's density, >= 1 (variable mass scaling raises it).
    mass : ndarray (n_nodes,) float64
        Lumped scaled nodal masses, tonne (full ring when axisymmetric).
    dof_mass, dof_inverse_mass : ndarray (n_nodes * dim,) float64
        The masses repeated per dof (tonne) and their inverses (0 for nodes in no element),
        1/tonne, for the flat node-update loops.
    added_mass_fraction : float
        (scaled mass - physical mass) / physical mass, dimensionless.
    reference_velocity : ndarray (3,) float64
        The velocity the damping acts relative to, mm/s: the model's mean velocity in its
        free-translation components (``Model.free_translation``), zeros elsewhere.
    pressure_amplitude_table : ndarray (n_amp, width) float64
        Packed amplitudes of the pressure loads (a released load's row is replaced,
        ``scenarios._pressure_release``).
    event_time : ndarray (N_EVENTS,) float64
        Solver times of the run's events (``EVENT_*``), s; NaN before they happen.
    crack : ndarray (n_band, 3) float64
        The cut band's radial cracks (``fracture._radial_cracks``): opening and largest opening
        (mm) and 1 once started; (0, 3) without a band.
    elements : ElementSet
        Derived: what the element kernels read, the model's or, with softening, a copy
        carrying the softened elements' own material rows.
    softening_rows : SofteningRows or None
        Derived: the bookkeeping of those rows (``_softening``).
    """

    time: float
    step: int
    time_step: float
    next_time_step: float
    u: np.ndarray
    v: np.ndarray
    a: np.ndarray
    f_int: np.ndarray
    f_ext: np.ndarray
    history: np.ndarray
    alive: np.ndarray
    node_active: np.ndarray
    failure_ratio: np.ndarray
    energy_rates: np.ndarray
    energies: np.ndarray
    deleted_element: np.ndarray
    deleted_time: np.ndarray
    damage: np.ndarray
    density_scale: np.ndarray
    mass: np.ndarray
    dof_mass: np.ndarray
    dof_inverse_mass: np.ndarray
    added_mass_fraction: float
    reference_velocity: np.ndarray
    pressure_amplitude_table: np.ndarray
    event_time: np.ndarray
    crack: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    elements: object = field(default=None, metadata=DERIVED)
    softening_rows: object = field(default=None, metadata=DERIVED)

    def copy(self) -> State:
        """A deep copy (arrays copied, the softening rows too)."""
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        state = State(**{name: np.copy(value) if isinstance(value, np.ndarray) else value
                         for name, value in values.items()})
        if self.softening_rows is not None:
            state.softening_rows = self.softening_rows.copy()
            state.elements = state.softening_rows.elements
        return state


EVENT_EPITHELIUM, EVENT_STROMA, EVENT_CORNEA, EVENT_RELEASE = range(4)
N_EVENTS = 4
"""Entries of ``State.event_time``: the cut passes the epithelium, enters the stroma and leaves
the cornea (the puncture events, ``scenarios._punctures``), and the pressures with
``release_on_puncture`` are released (``scenarios._pressure_release``)."""


def saved_fields() -> list[str]:
    """Names of the state's fields a checkpoint saves (all but the derived ones)."""
    return [item.name for item in fields(State) if not item.metadata.get("derived")]


def attach_derived(model, state: State) -> State:
    """Give ``state`` its derived fields: the element set of the kernels and, when the model
    softens, its own material rows rebuilt from ``state.damage``; returns ``state``."""
    if model.softening is None:
        state.elements, state.softening_rows = model.elements, None
        return state
    state.softening_rows = SofteningRows(model.softening, model.elements)
    state.elements = state.softening_rows.elements
    restore_softening_rows(state)
    return state

def new_state(model, velocity=None, time: float = 0.0) -> State:
    """Initial state at rest (or with an initial ``velocity`` (n_nodes, dim), mm/s) at ``time`` (s).

    Evaluates the internal forces and the pressures at ``time`` so the first step starts
    from the right acceleration; external-force hooks contribute from the first step on.
    """
    n_nodes, dim = model.n_nodes, model.dim
    zeros = np.zeros((n_nodes, dim))
    v = zeros.copy() if velocity is None else np.array(velocity, dtype=np.float64).reshape(n_nodes, dim)
    state = State(
        time=float(time), step=0, time_step=0.0, next_time_step=0.0, u=zeros.copy(), v=v,
        a=zeros.copy(), f_int=zeros.copy(), f_ext=zeros.copy(),
        history=element_kernels.new_history(model.elements),
        alive=np.ones(model.n_elements, np.uint8), node_active=np.zeros(n_nodes, np.uint8),
        failure_ratio=np.zeros(model.n_elements), energy_rates=np.zeros(3),
        energies=np.zeros(N_ENERGIES), deleted_element=np.zeros(0, np.int64),
        deleted_time=np.zeros(0), damage=np.zeros((model.n_elements, 3)),
        density_scale=model.density_scale.copy(), mass=model.mass.copy(), dof_mass=model.dof_mass.copy(),
        dof_inverse_mass=model.dof_inverse_mass.copy(), added_mass_fraction=model.added_mass_fraction,
        reference_velocity=np.zeros(3), pressure_amplitude_table=model.pressure_amplitude_table.copy(),
        event_time=np.full(N_EVENTS, np.nan),
        crack=model.radial_cracks.new_crack_state() if model.radial_cracks is not None else np.zeros((0, 3)))
    attach_derived(model, state)
    update_node_activity(model.mesh.cells, state.alive, state.node_active, state.a)
    eval_forces(model, state, 0.0, state.time)
    state.a[:] = (state.f_ext - state.f_int) * state.dof_inverse_mass.reshape(state.a.shape)
    state.energies[ENERGY_INITIAL_KINETIC] = 0.5 * float(np.sum(state.mass[:, None] * v * v))
    return state
