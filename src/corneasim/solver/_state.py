"""The changing state of a simulation: a plain container of arrays a checkpoint can save.

Time levels follow the central-difference scheme: displacement, forces and acceleration
at t^n, velocity at the half step t^{n-1/2}.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from corneasim.solver import elements as element_kernels
from corneasim.solver._deletion import update_node_activity
from corneasim.solver._integrate import ENERGY_INITIAL_KINETIC, N_ENERGIES
from corneasim.solver._pressure import eval_pressure_forces


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

    def copy(self) -> State:
        """A deep copy (arrays copied)."""
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        return State(**{name: np.copy(value) if isinstance(value, np.ndarray) else value
                        for name, value in values.items()})

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
        deleted_time=np.zeros(0), damage=np.zeros((model.n_elements, 3)))
    update_node_activity(model.mesh.cells, state.alive, state.node_active, state.a)
    element_kernels.eval_internal_forces(model.elements, state.u, 0.0, state.alive,
                                         state.history, state.f_int, state.failure_ratio,
                                         state.energy_rates)
    eval_pressure_forces(model.mesh.points, state.u, model.pressure_face_nodes,
                         model.pressure_face_element, model.pressure_value, model.pressure_amplitude,
                         model.pressure_amplitude_table, state.alive, state.time, state.f_ext)
    state.a[:] = (state.f_ext - state.f_int) * model.dof_inverse_mass.reshape(state.a.shape)
    state.energies[ENERGY_INITIAL_KINETIC] = 0.5 * float(np.sum(model.mass[:, None] * v * v))
    return state
