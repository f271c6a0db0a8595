"""History rows and field frames computed from a state (no file I/O here).

History columns (units in the names):

* ``time_s``, ``step``, ``time_step_s``;
* ``kinetic_energy_mJ``; ``internal_energy_mJ`` = ∫ f_int · du, the total work of the
  internal forces (elastic + hourglass + bulk-viscous + viscoelastic), with its parts
  ``hourglass_energy_mJ``, ``viscous_energy_mJ`` (bulk viscosity) and
  ``viscoelastic_dissipation_mJ``; ``damping_energy_mJ`` (mass-proportional damping of the
  preload and of ``solver.damping``);
* ``external_work_mJ`` = work of loads (pressure, hooks) + work of the constraint reactions;
* ``energy_balance_error`` = |E_kin + E_int + E_damp - W_ext - E_kin,0| / max(E_kin, E_int, W_ext)
  with the discrete kinetic energy of central differences in the numerator
  (Abaqus ETOTAL normalised; 0 while all energies are below ``ENERGY_FLOOR``);
* ``deleted_elements``; with a fracture energy (``_softening``) also ``softening_elements``,
  the live elements with damage > 0;
* ``reaction_<set>_<component>_N``: the sum over the set's constrained dofs of
  f_int - f_ext (the force the support exerts on the body is its negative; the inertia of
  the constrained nodes themselves is not included). Axisymmetric: full ring.
* the outputs of each external-force hook.
"""

from __future__ import annotations

import numpy as np

from corneasim.solver import elements as element_kernels
from corneasim.solver._integrate import (
    ENERGY_DAMPING, ENERGY_EXTERNAL, ENERGY_HOURGLASS, ENERGY_INITIAL_KINETIC, ENERGY_INTERNAL,
    ENERGY_REACTION, ENERGY_VISCOELASTIC, ENERGY_VISCOUS)


ENERGY_FLOOR = 1e-20
"""Energies below this (mJ) count as nothing has happened: the balance error is then 0."""


def component_names(model) -> str:
    return "rz" if model.mesh.axisymmetric else "xyz"


def reaction_forces(model, state) -> dict[str, float]:
    """Reaction force per constrained node set and component, N (see module notes)."""
    f_int, f_ext = state.f_int.ravel(), state.f_ext.ravel()
    names = component_names(model)
    totals = {}
    for name, component, dofs in model.reaction_groups:
        dofs = dofs[state.node_active[dofs // model.dim] != 0]
        totals[f"reaction_{name}_{names[component]}_N"] = float((f_int[dofs] - f_ext[dofs]).sum())
    return totals


def out_of_balance(model, state) -> float:
    """Relative out-of-balance force ||f_ext - f_int|| / ||f_ext|| at the state's time, dimensionless.

    Norms over the free dofs of active nodes; 0 without applied load. At static equilibrium it is
    0; in a damped settling stage the remainder is the damping and inertia force, so it measures
    how far from equilibrium the body still is (a creeping, overdamped body has little kinetic
    energy but a large remainder). A cyclic pair counts as the one node it stands for
    (``_cyclic``): its forces are combined as f_a + R^T f_b, R = diag(-1, -1, 1), on the master
    and its held components left out.
    """
    residual = state.f_ext - state.f_int
    applied = state.f_ext.copy()
    free = (model.dof_constrained == 0) & (state.node_active[:, None] != 0)
    if model.cyclic_master.size:
        rotation = np.array([-1.0, -1.0, 1.0])
        master, slave = model.cyclic_master, model.cyclic_slave
        for field in (residual, applied):
            field[master] += rotation * field[slave]
        free[slave] = False
        free[master] &= model.cyclic_held == 0
    norm = float(np.linalg.norm(applied[free]))
    if norm == 0.0:
        return 0.0
    return float(np.linalg.norm(residual[free])) / norm


def pending_reaction_work(model, state) -> float:
    """Reaction work of the last half step not yet booked by the integrator, mJ.

    The integrator books R^n (Δu^{n-1/2} + Δu^{n+1/2}) / 2 once v^{n+1/2} is known, so at
    t^{n+1} the trapezoid lacks R^{n+1} Δu^{n+1/2} / 2; R^{n+1} is estimated by f_int - f_ext
    on the constrained dofs (without the constrained nodes' own inertia).
    """
    dofs = model.constraint_dof[state.node_active[model.constraint_node] != 0]
    residual = state.f_int.ravel()[dofs] - state.f_ext.ravel()[dofs]
    return float(0.5 * state.time_step * np.dot(residual, state.v.ravel()[dofs]))


def energy_balance_error(kinetic: float, discrete_kinetic: float, energies, work: float) -> float:
    """|E_kin + E_int + E_damp - W_ext - E_kin,0| / max(E_kin, E_int, W_ext), dimensionless.

    The numerator uses the discrete kinetic energy of central differences
    (``_integrate.kinetic_energy``), with which the balance is exact for a linear problem at a
    constant step, so what remains measures genuine bookkeeping errors (a force whose work is
    not booked, a kick at deletion, contact); the scale uses the reported kinetic energy.
    Energies and ``work`` (external plus reaction work) in mJ.
    """
    total = discrete_kinetic + energies[ENERGY_INTERNAL] + energies[ENERGY_DAMPING] - work \
        - energies[ENERGY_INITIAL_KINETIC]
    scale = max(abs(kinetic), abs(energies[ENERGY_INTERNAL]), abs(work))
    return float(abs(total) / scale) if scale > ENERGY_FLOOR else 0.0


def history_row(model, state, kinetic: float, discrete_kinetic: float, hooks=()) -> dict[str, float]:
    """One history row (dict of column name to value) at the state's time.

    ``kinetic`` and ``discrete_kinetic`` (mJ) from ``_integrate.kinetic_energy``.
    """
    e = state.energies
    work = float(e[ENERGY_EXTERNAL] + e[ENERGY_REACTION]) + pending_reaction_work(model, state)
    row = {
        "time_s": float(state.time),
        "step": int(state.step),
        "time_step_s": float(state.time_step),
        "kinetic_energy_mJ": float(kinetic),
        "internal_energy_mJ": float(e[ENERGY_INTERNAL]),
        "hourglass_energy_mJ": float(e[ENERGY_HOURGLASS]),
        "viscous_energy_mJ": float(e[ENERGY_VISCOUS]),
        "viscoelastic_dissipation_mJ": float(e[ENERGY_VISCOELASTIC]),
        "damping_energy_mJ": float(e[ENERGY_DAMPING]),
        "external_work_mJ": work,
        "energy_balance_error": energy_balance_error(kinetic, discrete_kinetic, e, work),
        "deleted_elements": int(state.deleted_element.size),
    }
    if model.softening is not None:
        row["softening_elements"] = int(np.count_nonzero((state.damage[:, 0] > 0.0) & (state.alive != 0)))
    row.update(reaction_forces(model, state))
    for hook in hooks:
        row.update(hook.outputs())
    return row


def field_output(model, state) -> dict[str, np.ndarray]:
    """Field arrays at the state's time.

    Returns
    -------
    dict
        Point data ``displacement`` (n_nodes, dim) mm, ``velocity`` (n_nodes, dim) mm/s
        (at t^{n-1/2}), ``node_active`` (n_nodes,) uint8; cell data ``cauchy_stress``
        (n_elements, 6) MPa ([xx, yy, zz, xy, yz, zx]; axisymmetric [rr, zz, θθ, rz, 0, 0]),
        ``von_mises`` (n_elements,) MPa, ``failure_ratio`` (n_elements,), ``alive``
        (n_elements,) uint8, ``block`` (n_elements,) int64; with a fracture energy also
        ``damage`` (n_elements,), the softening damage D (``_softening``); with a cut band
        ``crack_opening`` (n_elements,) mm (``fracture._radial_cracks``; the band's stress is
        that of its material, F_e). Dead elements report zero stress.
    """
    sigma = element_kernels.element_stress(state.elements, state.u, state.history)
    if model.radial_cracks is not None:
        model.radial_cracks.stress(state, sigma)
    sigma = sigma * (state.alive != 0)[:, None]
    s11, s22, s33, s12, s23, s31 = sigma.T
    von_mises = np.sqrt(0.5 * ((s11 - s22) ** 2 + (s22 - s33) ** 2 + (s33 - s11) ** 2)
                        + 3.0 * (s12 ** 2 + s23 ** 2 + s31 ** 2))
    fields = {
        "displacement": state.u.copy(),
        "velocity": state.v.copy(),
        "node_active": state.node_active.copy(),
        "cauchy_stress": sigma,
        "von_mises": von_mises,
        "failure_ratio": state.failure_ratio.copy(),
        "alive": state.alive.copy(),
        "block": model.mesh.element_block.astype(np.int64),
    }
    if model.softening is not None:
        fields["damage"] = state.damage[:, 0].copy()
    if model.radial_cracks is not None:
        fields["crack_opening"] = model.radial_cracks.opening(state)
    return fields
