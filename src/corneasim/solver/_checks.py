"""Robustness checks that stop a run which has gone wrong, with one clear message.

At every history row and every ``check_every`` steps the loop checks, in this order:

1. all accelerations are finite (no NaN or infinity), else names a node and an element on it;
2. (every ``check_every`` steps only) every live element has J = det F > 0 at its centre
   (``element_jacobians``), else names the element with the smallest J;
3. the kinetic energy is below ``runaway_factor`` times the energy put in
   (external work + reaction work + initial kinetic energy, at least ``energy_floor``):
   a stable run cannot create kinetic energy, so a large excess means instability.

A failed check raises :class:`SimulationError`. Checks run *before* a checkpoint is taken
at the same step, so the last checkpoint on disk is always of a good state.
"""

from __future__ import annotations

import numpy as np

from corneasim.solver import elements as element_kernels
from corneasim.solver._integrate import (
    ENERGY_EXTERNAL, ENERGY_INITIAL_KINETIC, ENERGY_REACTION, all_finite)


class SimulationError(RuntimeError):
    """A run stopped because its state became invalid; the message is one line.

    Attributes
    ----------
    time : float
        Simulated time of the failed check, s.
    element : int
        The offending element (-1 if none could be named).
    block : str
        Its block name ('' if none).
    """

    def __init__(self, message: str, time: float, element: int = -1, block: str = ""):
        super().__init__(" ".join(message.split()))
        self.time = time
        self.element = element
        self.block = block


def _fail(model, state, what: str, element: int):
    block = model.block_of(element) if element >= 0 else ""
    where = f"element {element} (block '{block}')" if element >= 0 else "no element identified"
    raise SimulationError(f"simulation stopped at t = {state.time:.6g} s (step {state.step}): "
                          f"{what} in {where}", state.time, element, block)


def check_state(model, state, kinetic_energy: float, runaway_factor: float = 10.0,
                energy_floor: float = 1e-9, geometry: bool = True) -> None:
    """Raise :class:`SimulationError` if the state has NaN/Inf, an inverted element or runaway energy.

    Parameters
    ----------
    kinetic_energy : float
        Current kinetic energy, mJ.
    runaway_factor : float
        Allowed ratio of kinetic energy to the energy put in, dimensionless.
    energy_floor : float
        Smallest energy input considered, mJ (guards runs that start at rest with no load).
    geometry : bool
        Also check J > 0 (a pass over all elements, as costly as a force evaluation); the
        loop asks for it every ``check_every`` steps, not at every history row.
    """
    if not (all_finite(state.a) and all_finite(state.u)):
        bad = np.flatnonzero(~np.isfinite(state.a).all(axis=1) | ~np.isfinite(state.u).all(axis=1))
        node = int(bad[0])
        owners = np.flatnonzero((model.mesh.cells == node).any(axis=1))
        live = owners[state.alive[owners] != 0]
        element = int(live[0]) if live.size else (int(owners[0]) if owners.size else -1)
        _fail(model, state, f"non-finite displacement or acceleration at node {node}", element)
    jacobians = np.zeros(0)
    if geometry:
        jacobians = element_kernels.element_jacobians(model.elements, state.u)
        jacobians = np.where(state.alive != 0, jacobians, np.inf)
    if jacobians.size:
        element = int(np.argmin(np.nan_to_num(jacobians, nan=-np.inf)))
        J = jacobians[element]
        if not J > 0.0:
            _fail(model, state, f"inverted element (J = {J:.3g})", element)
    energy_in = max(state.energies[ENERGY_EXTERNAL] + state.energies[ENERGY_REACTION]
                    + state.energies[ENERGY_INITIAL_KINETIC], energy_floor)
    if kinetic_energy > runaway_factor * energy_in:
        if not jacobians.size:
            jacobians = element_kernels.element_jacobians(model.elements, state.u)
        element = int(np.argmax(np.where(state.alive != 0, -jacobians, -np.inf))) if jacobians.size else -1
        _fail(model, state, f"runaway kinetic energy ({kinetic_energy:.3g} mJ > {runaway_factor:g} x "
              f"energy input {energy_in:.3g} mJ), most compressed", element)
