"""Variable mass scaling: keep the step at the target as elements are crushed.

Mass scaling in the reference configuration (``_timestep.density_scale_for_target``) is not
enough when an instrument crushes elements: their stable step falls with their size and the
whole run slows to it (the needle's coarse run fell from 1.4e-5 s to 1e-7 s). Abaqus/Explicit
re-applies the scaling "throughout the step"; here it is re-applied whenever the stable step
is recomputed. The density scale of an element only grows:

.. math::

    s_e \\leftarrow \\max\\left(s_e, \\left(\\frac{\\Delta t^*}{\\alpha\\,\\Delta t_e(u)}\\right)^2\\right)

with Δt_e(u) the element's stable step in the deformed geometry and α the safety factor.
Mass added to a moving node takes momentum from it (a perfectly inelastic accretion):
v ← v m_old / m_new on the free dofs, and the kinetic energy this removes,
½ m_old v² (1 - m_old / m_new), is booked with the dissipated (damping) energy so that the
energy balance stays closed. The added mass is reported (``added_mass_fraction``).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.solver import elements as element_kernels
from corneasim.solver._integrate import ENERGY_DAMPING
from corneasim.solver._stable_step import density_scale_for_target


@njit(cache=True)
def transfer_momentum(v, dof_mass_old, dof_mass_new, dof_constrained):
    """v <- v m_old / m_new on free dofs; return the kinetic energy removed, mJ.

    ``v`` (n_dofs,) mm/s, masses (n_dofs,) tonne, ``dof_constrained`` (n_dofs,) uint8.
    """
    lost = 0.0
    for k in range(v.size):
        if dof_constrained[k] != 0 or dof_mass_new[k] <= 0.0:
            continue
        ratio = dof_mass_old[k] / dof_mass_new[k]
        lost += 0.5 * dof_mass_old[k] * v[k] * v[k] * (1.0 - ratio)
        v[k] *= ratio
    return lost


def rescale_masses(model, state, element_dt: np.ndarray) -> int:
    """Scale the live elements whose current stable step is below the target; return how many.

    Parameters
    ----------
    model : Model
        The target step, the safety factor and the element set.
    state : State
        Its ``density_scale``, masses and ``added_mass_fraction``, half-step velocity and
        dissipated energy are updated in place.
    element_dt : ndarray (n_elements,) float64
        Unscaled element stable steps in the current geometry, s.
    """
    if not model.variable_mass_scaling:
        return 0
    needed = density_scale_for_target(element_dt, model.target_time_step, model.safety_factor)
    grow = (needed > state.density_scale) & (state.alive != 0)
    count = int(np.count_nonzero(grow))
    if count == 0:
        return 0
    scale = state.density_scale.copy()
    scale[grow] = needed[grow]
    dof_mass_before = state.dof_mass.copy()
    set_density_scale(model, state, scale)
    state.energies[ENERGY_DAMPING] += transfer_momentum(
        state.v.reshape(-1), dof_mass_before, state.dof_mass, model.dof_constrained.reshape(-1))
    return count


def set_density_scale(model, state, scale: np.ndarray) -> None:
    """Give ``state`` the element density scales ``scale`` (n_elements,) and the lumped masses they imply.

    Updates ``density_scale``, ``mass``, ``dof_mass``, ``dof_inverse_mass`` and
    ``added_mass_fraction`` of ``state`` in place.
    """
    state.density_scale[:] = scale
    mass = element_kernels.lumped_masses(model.elements, state.density_scale)
    dof_mass = np.repeat(mass, model.mesh.dim)
    state.mass[:] = mass
    state.dof_mass[:] = dof_mass
    state.dof_inverse_mass[:] = np.divide(1.0, dof_mass, out=np.zeros_like(dof_mass), where=dof_mass > 0)
    state.added_mass_fraction = float((mass.sum() - model.physical_mass_total) / model.physical_mass_total)
