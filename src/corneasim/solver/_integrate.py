"""Central-difference time integration with lumped mass: the node-update kernels.

One step n -> n+1 (Belytschko, Liu & Moran, *Nonlinear Finite Elements*, 2000, box 6.1):

.. math::

    v^{n+1/2} = v^{n-1/2} + \\tfrac12(\\Delta t^{n-1/2} + \\Delta t^{n+1/2})\\, a^n, \\qquad
    u^{n+1} = u^n + \\Delta t^{n+1/2} v^{n+1/2}, \\qquad
    a^{n+1} = M^{-1}(f^{ext}_{n+1} - f^{int}_{n+1}) - \\alpha v^{n+1/2}

with α the optional mass-proportional damping (1/s, used to settle the preload). In a
model free to translate as a whole in some component (held by elastic supports), the
damping acts on v - v̄ there, v̄ = Σ m v / Σ m the mean velocity, so that it does not resist
the rigid translation (a mass-scaled body descending at speed w against its support would
otherwise feel the drag α M w). Energies
are accumulated with the trapezoidal rule on Δu = u^{n+1} - u^n:
W_int += Δu·(f^int_n + f^int_{n+1})/2, W_ext likewise with f^ext. Constrained dofs take
their imposed velocity; the reaction that imposes it, R^n = m (a_imposed - a^n) with
a_imposed = (v^{n+1/2} - v^{n-1/2}) / Δt_avg, works W_R += R^n (Δu^{n-1/2} + Δu^{n+1/2})/2.

The energy array (``ENERGY_*`` indices, mJ) is updated in place.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.solver._loads import DISPLACEMENT, FIXED
from corneasim.solver._amplitudes import evaluate

ENERGY_INTERNAL = 0
ENERGY_EXTERNAL = 1
ENERGY_REACTION = 2
ENERGY_HOURGLASS = 3
ENERGY_VISCOUS = 4
ENERGY_VISCOELASTIC = 5
ENERGY_DAMPING = 6
ENERGY_INITIAL_KINETIC = 7
N_ENERGIES = 8
NO_REFERENCE = np.zeros(3)
"""The damping's reference velocity when it acts on the absolute velocity, mm/s."""
ENERGY_NAMES = ("internal", "external", "reaction", "hourglass", "viscous", "viscoelastic",
                "damping", "initial_kinetic")


@njit(cache=True, fastmath=True, error_model="numpy")
def integrate_velocity_displacement(u, v, a, f_int, f_ext, dof_mass, dt, dt_previous, t,
                                    constraint_dof, constraint_kind, constraint_value,
                                    constraint_amplitude, amplitude_table, node_active,
                                    energies):
    """Advance v to t^{n+1/2} and u to t^{n+1}, impose constraints, book the first half-works.

    Parameters
    ----------
    u, v, a : ndarray (n_nodes, dim) float64
        In/out: u^n -> u^{n+1} (mm), v^{n-1/2} -> v^{n+1/2} (mm/s); in: a^n (mm/s^2, the
        unconstrained acceleration).
    f_int, f_ext : ndarray (n_nodes, dim) float64
        In: forces at t^n, N. ``f_ext`` is zeroed on return (ready for the new loads).
    dof_mass : ndarray (n_nodes * dim,) float64
        Lumped (scaled) masses repeated per dof, tonne.
    dt, dt_previous : float
        Δt^{n+1/2} and Δt^{n-1/2}, s (0 before the first step).
    t : float
        t^n, s.
    constraint_dof, constraint_kind, constraint_amplitude : ndarray (n_c,) int64
    constraint_value : ndarray (n_c,) float64
        The constraint table (``_loads.pack_constraints``).
    amplitude_table : ndarray (n_amp, width) float64
    node_active : ndarray (n_nodes,) uint8
        Released nodes (0) ignore their constraints.
    energies : ndarray (N_ENERGIES,) float64
        In/out, mJ.
    """
    dim = u.shape[1]
    n_dofs = u.size
    u_flat, v_flat, a_flat = u.reshape(n_dofs), v.reshape(n_dofs), a.reshape(n_dofs)
    fi, fe = f_int.reshape(n_dofs), f_ext.reshape(n_dofs)
    dt_average = 0.5 * (dt + dt_previous)
    half_work_internal = 0.0
    half_work_external = 0.0
    for k in range(n_dofs):
        v_flat[k] += dt_average * a_flat[k]
    work_reaction = 0.0
    for c in range(constraint_dof.shape[0]):
        dof = constraint_dof[c]
        node = dof // 2 if dim == 2 else dof // 3  # division by a constant: no integer divide
        if node_active[node] == 0:
            continue
        a_dof = a_flat[dof]
        v_old = v_flat[dof] - dt_average * a_dof
        kind = constraint_kind[c]
        if kind == FIXED:
            v_new = 0.0
        elif kind == DISPLACEMENT:
            target = constraint_value[c] * evaluate(amplitude_table[constraint_amplitude[c]], t + dt)[0]
            v_new = (target - u_flat[dof]) / dt
        else:
            v_new = constraint_value[c] * evaluate(amplitude_table[constraint_amplitude[c]],
                                                   t + 0.5 * dt)[0]
        reaction = dof_mass[dof] * ((v_new - v_old) / dt_average - a_dof)
        work_reaction += 0.5 * reaction * (dt_previous * v_old + dt * v_new)
        v_flat[dof] = v_new
    for k in range(n_dofs):
        du = dt * v_flat[k]
        u_flat[k] += du
        half_work_internal += fi[k] * du
        half_work_external += fe[k] * du
        fe[k] = 0.0
    half_work_internal *= 0.5
    half_work_external *= 0.5
    energies[ENERGY_INTERNAL] += half_work_internal
    energies[ENERGY_EXTERNAL] += half_work_external
    energies[ENERGY_REACTION] += work_reaction


@njit(cache=True)
def mean_velocity(v, dof_mass, components, out):
    """out[c] = sum m v_c / sum m over the nodes for the components with ``components[c]``
    (0 elsewhere), mm/s: the velocity of the centre of mass. ``v`` (n_nodes, dim) mm/s,
    ``dof_mass`` (n_nodes * dim,) tonne, ``components`` (dim,) uint8, ``out`` (dim,)."""
    dim = v.shape[1]
    for c in range(dim):
        out[c] = 0.0
        if components[c] == 0:
            continue
        momentum = 0.0
        mass = 0.0
        for i in range(v.shape[0]):
            m = dof_mass[i * dim + c]
            momentum += m * v[i, c]
            mass += m
        out[c] = momentum / mass if mass > 0.0 else 0.0


@njit(cache=True, fastmath=True, error_model="numpy")
def integrate_acceleration(v, f_int, f_ext, dof_inverse_mass, dof_mass, dt, damping, energy_rates,
                           a, energies, reference_velocity):
    """New acceleration a^{n+1} and the second half-works of the step.

    Parameters
    ----------
    v : ndarray (n_nodes, dim) float64
        v^{n+1/2}, mm/s.
    f_int, f_ext : ndarray (n_nodes, dim) float64
        Forces at t^{n+1}, N.
    dof_inverse_mass, dof_mass : ndarray (n_nodes * dim,) float64
        1/m (0 for massless nodes), 1/tonne, and m, tonne, repeated per dof.
    dt : float
        Δt^{n+1/2}, s.
    damping : float
        Mass-proportional damping α, 1/s (0 in the dynamic stage).
    energy_rates : ndarray (3,) float64
        From the element kernel: the hourglass energy (mJ, stored by the stiffness-type
        hourglass control, so it is copied, not integrated) and the bulk-viscous and
        viscoelastic power (mJ/s).
    a : ndarray (n_nodes, dim) float64
        Out: a^{n+1}, mm/s^2.
    energies : ndarray (N_ENERGIES,) float64
        In/out, mJ.
    reference_velocity : ndarray (dim,) float64
        v̄, mm/s: the damping acts on v - v̄ (zeros: on v).
    """
    dim = v.shape[1]
    n_dofs = v.size
    v_flat, a_flat = v.reshape(n_dofs), a.reshape(n_dofs)
    fi, fe = f_int.reshape(n_dofs), f_ext.reshape(n_dofs)
    half_work_internal = 0.0
    half_work_external = 0.0
    work_damping = 0.0
    if damping == 0.0:  # the dynamic stage: no damping work, one array fewer to stream
        for k in range(n_dofs):
            velocity = v_flat[k]
            half_work_internal += fi[k] * velocity
            half_work_external += fe[k] * velocity
            a_flat[k] = (fe[k] - fi[k]) * dof_inverse_mass[k]
    elif not reference_velocity.any():  # damping of absolute velocities (a preload): one flat loop
        for k in range(n_dofs):
            velocity = v_flat[k]
            half_work_internal += fi[k] * velocity
            half_work_external += fe[k] * velocity
            a_flat[k] = (fe[k] - fi[k]) * dof_inverse_mass[k] - damping * velocity
            work_damping += dof_mass[k] * velocity * velocity
    else:
        for i in range(n_dofs // dim):
            for c in range(dim):
                k = i * dim + c
                velocity = v_flat[k]
                relative = velocity - reference_velocity[c]
                half_work_internal += fi[k] * velocity
                half_work_external += fe[k] * velocity
                a_flat[k] = (fe[k] - fi[k]) * dof_inverse_mass[k] - damping * relative
                work_damping += dof_mass[k] * relative * velocity
    energies[ENERGY_INTERNAL] += 0.5 * dt * half_work_internal
    energies[ENERGY_EXTERNAL] += 0.5 * dt * half_work_external
    energies[ENERGY_DAMPING] += damping * dt * work_damping
    energies[ENERGY_HOURGLASS] = energy_rates[0]
    energies[ENERGY_VISCOUS] += energy_rates[1] * dt
    energies[ENERGY_VISCOELASTIC] += energy_rates[2] * dt


@njit(cache=True, fastmath=True, error_model="numpy")
def kinetic_energy(v, a, dof_mass, dt, dof_constrained, node_active):
    """Kinetic energy at t^{n+1}, mJ, in two forms: (reported, discrete).

    reported: sum m (v^{n+1})^2 / 2 with v^{n+1} = v^{n+1/2} + Δt/2 a^{n+1};
    discrete: sum m v^{n+1/2} v^{n+3/2} / 2 with v^{n+3/2} = v^{n+1/2} + Δt a^{n+1}, the
    kinetic energy that central differences conserve exactly together with the trapezoidal
    work (its increments equal Δu·(F^n + F^{n+1})/2 for a constant step); the two differ by
    Δt² a·M a / 8, large only for modes near the stability limit. Constrained dofs of active
    nodes use their imposed v^{n+1/2} in both forms. ``dof_mass`` (n_nodes * dim,) tonne;
    ``dof_constrained`` (n_nodes, dim) uint8; ``node_active`` (n_nodes,) uint8.
    """
    dim = v.shape[1]
    n_dofs = v.size
    v_flat, a_flat = v.reshape(n_dofs), a.reshape(n_dofs)
    constrained = dof_constrained.reshape(n_dofs)
    reported = 0.0
    discrete = 0.0
    for k in range(n_dofs):
        w = v_flat[k]
        free = constrained[k] == 0 or node_active[k // dim] == 0
        step = dt * a_flat[k] if free else 0.0
        reported += dof_mass[k] * (w + 0.5 * step) * (w + 0.5 * step)
        discrete += dof_mass[k] * w * (w + step)
    return 0.5 * reported, 0.5 * discrete


@njit(cache=True)
def all_finite(x):
    """True when every entry of the 2D array ``x`` is finite (no NaN or infinity)."""
    for i in range(x.shape[0]):
        for j in range(x.shape[1]):
            value = x[i, j]
            if value - value != 0.0:
                return False
    return True
