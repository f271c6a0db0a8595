"""Crack-band softening: a failed element dissipates a fracture energy before it is deleted.

Without a fracture energy an element dies as soon as its failure ratio (criterion / limit)
reaches 1 (:mod:`corneasim.solver._deletion`): a brittle, mesh-dependent rule that releases
the element's whole stored energy at once. With a fracture energy G_f (N/mm = mJ/mm^2) per
block, an element whose criterion is met softens instead. It loses its shear (distortion)
capacity but keeps its bulk modulus, as the needle paper's distortion-energy criterion
suggests and as torn, water-filled tissue still carries pressure: its isochoric stress
(and its Prony stresses, which are isochoric) is that of the intact material times (1 - D),
its volumetric stress is unchanged. The scalar damage D is driven by the largest undamaged
failure ratio reached so far, kappa = max_t r/(1 - D) (the von Mises stress is isochoric,
so r/(1 - D) is exactly the intact ratio). The softening law is the linear one of the crack
band model (Z. P. Bazant and B. H. Oh, "Crack band theory for fracture of concrete",
Materiaux et Constructions 16 (1983) 155-177):

.. math::

    (1 - D)\\,\\kappa = \\frac{\\kappa_u - \\kappa}{\\kappa_u - 1}, \\qquad 1 \\le \\kappa \\le \\kappa_u,
    \\qquad \\kappa_u = \\frac{G_f}{h_e\\, w_0},

so the deviatoric stress falls linearly from the failure stress (kappa = 1) to zero
(kappa = kappa_u). w_0 is the element's isochoric strain-energy density at the onset (MPa =
mJ/mm^3, instantaneous, scaled back to r = 1 as w(r)/r^2) and h_e its size (sqrt of the area
in (r, z), cbrt of the volume). For a linear-elastic element loaded proportionally, the
deviatoric stress and strain grow with kappa, and the deviatoric work per unit volume until
the stress vanishes is the area of the triangle, w_0 kappa_u = G_f / h_e: the element
dissipates G_f per unit area of a band one element wide, whatever the mesh. An element too
large for its fracture energy (kappa_u <= 1: the branch would snap back) fails brittle. The
element is deleted when its deviatoric stress is below ``RESIDUAL`` of the failure stress.

Implementation: the element kernels are not changed; instead a softening element gets a
material row of its own in the kernel material table, with C10, C01, C20 and C30 times
(1 - D). The isochoric stress of the kernels' hyperelastic family is linear in these
constants, so it is exactly (1 - D) times the intact one at the same deformation. The
element's Prony stress history is scaled by the same factor whenever D grows. The bulk
modulus, the bulk viscosity and the hourglass stiffness keep their intact values (the
hourglass control keeps a damaged element from folding). The damage and the rows are part of
the :class:`~corneasim.solver.State` (:class:`SofteningRows`; the model's element set is not
changed); a checkpoint saves the damage and :func:`restore_softening_rows` rebuilds the rows.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numba import njit

from corneasim.materials.kernel import (
    M_C10, M_C30, M_DISSIPATION, M_FIBRE_K1, MAX_PRONY_TERMS, P_C01, P_C10, P_C20, P_C30,
    P_FIBRE_K1, isochoric_strain_energy)
from corneasim.solver.elements._reference import _deformation_gradient

RESIDUAL = 0.01
"""A softening element is deleted when its stress is below this fraction of the failure stress."""

DAMAGE, DRIVER, ULTIMATE = 0, 1, 2
"""Columns of ``State.damage``: D, kappa (0 while intact) and kappa_u (dimensionless)."""


@njit(cache=True)
def update_damage(failure_ratio, fracture_energy, alive, damage, started, changed, factor,
                  deleted, count):
    """One step of the softening law for every live element (module notes).

    Parameters
    ----------
    failure_ratio : ndarray (n_elements,) float64
        Criterion / limit of the (damaged) stress.
    fracture_energy : ndarray (n_elements,) float64
        G_f, N/mm; 0: brittle (deleted when the criterion is met).
    alive : ndarray (n_elements,) uint8
        In/out.
    damage : ndarray (n_elements, 3) float64
        In/out: D, kappa, kappa_u.
    started, changed : ndarray (n_elements,) int64
        Out: elements whose criterion is met for the first time (their kappa_u is set by the
        caller), and elements whose D grew.
    factor : ndarray (n_elements,) float64
        Out: (1 - D_new) / (1 - D_old) of each ``changed`` element.
    deleted : ndarray (n_elements,) int64
        Out: entries ``count`` onwards receive the elements deleted now.
    count : int
        Entries of ``deleted`` already used.

    Returns
    -------
    (int, int, int)
        The new ``count``, the number of ``started`` and of ``changed`` elements.
    """
    n_started = 0
    n_changed = 0
    for e in range(alive.shape[0]):
        if alive[e] == 0:
            continue
        r = failure_ratio[e]
        kappa = damage[e, DRIVER]
        if kappa == 0.0:
            if r < 1.0:
                continue
            if fracture_energy[e] > 0.0:
                started[n_started] = e
                n_started += 1
                continue
            alive[e] = 0
            deleted[count] = e
            count += 1
            continue
        d_old = damage[e, DAMAGE]
        undamaged = r / (1.0 - d_old)
        if undamaged <= kappa:
            continue
        ultimate = damage[e, ULTIMATE]
        if undamaged >= ultimate - RESIDUAL * (ultimate - 1.0):
            alive[e] = 0
            damage[e, DRIVER] = undamaged
            deleted[count] = e
            count += 1
            continue
        damage[e, DRIVER] = undamaged
        d_new = 1.0 - (ultimate - undamaged) / ((ultimate - 1.0) * undamaged)
        if d_new > d_old:
            damage[e, DAMAGE] = d_new
            changed[n_changed] = e
            factor[n_changed] = (1.0 - d_new) / (1.0 - d_old)
            n_changed += 1
    return count, n_started, n_changed


@njit(cache=True)
def energy_densities(cells, b, hoop, u, element_material, table, fibre_frame, which, out):
    """Isochoric (distortion) part of the instantaneous strain-energy density (MPa = mJ/mm^3) of the
    elements ``which`` into ``out``: W(F) without the volumetric term K (J - 1)^2 / 2, with the
    fibre families' energy of a fibre material."""
    F = np.empty((3, 3))
    for k in range(which.shape[0]):
        e = which[k]
        _deformation_gradient(cells, b, hoop, u, e, F)
        out[k] = isochoric_strain_energy(F, table[element_material[e]], fibre_frame[e])


def ultimate_ratio(fracture_energy: float, size: float, onset_energy: float) -> float:
    """kappa_u = G_f / (h_e w_0) (dimensionless); G_f N/mm, h_e mm, w_0 mJ/mm^3."""
    return fracture_energy / (size * onset_energy) if onset_energy > 0.0 else np.inf


class Softening:
    """The static softening data of a model (part of the :class:`~corneasim.solver.Model`).

    Parameters
    ----------
    elements : ElementSet
        The model's element set (not changed: each run's softened rows live in its
        :class:`SofteningRows`).
    fracture_energy : ndarray (n_elements,) float64
        G_f per element, N/mm (0: brittle).
    size : ndarray (n_elements,) float64
        h_e, mm.
    """

    def __init__(self, elements, fracture_energy: np.ndarray, size: np.ndarray):
        self.fracture_energy = np.ascontiguousarray(fracture_energy, dtype=np.float64)
        self.size = np.ascontiguousarray(size, dtype=np.float64)
        self.parent = elements.element_material.copy()


class SofteningRows:
    """One run's material rows of its softening elements (part of the :class:`~corneasim.solver.State`).

    ``elements`` is a copy of the model's element set whose material table, element
    materials and fast material arrays are this run's own: a softening element gets a row of
    its own, appended when it starts to soften. Rebuilt from ``State.damage`` when a
    checkpoint is loaded (:func:`restore_softening_rows`), so it is not saved.

    Parameters
    ----------
    softening : Softening
        The model's static softening data.
    elements : ElementSet
        The model's element set.
    """

    def __init__(self, softening: Softening, elements):
        self.parent = softening.parent
        fast = elements.fast
        if fast is not None:
            fast = {**fast, "material": fast["material"].copy(),
                    "element_material": fast["element_material"].copy(),
                    "block_material": fast["block_material"].copy()}
        self.elements = dataclasses.replace(elements, element_material=elements.element_material.copy(),
                                            material_table=elements.material_table.copy(), fast=fast)
        n = elements.n_elements
        self.row = np.full(n, -1, np.int64)
        self.started = np.empty(n, np.int64)  # scratch of the failure check
        self.changed = np.empty(n, np.int64)
        self.factor = np.empty(n)

    def copy(self) -> SofteningRows:
        """An independent copy (its own tables and rows)."""
        twin = object.__new__(SofteningRows)
        twin.parent = self.parent
        fast = self.elements.fast
        if fast is not None:
            fast = {**fast, "material": fast["material"].copy(),
                    "element_material": fast["element_material"].copy(),
                    "block_material": fast["block_material"].copy()}
        twin.elements = dataclasses.replace(self.elements, element_material=self.elements.element_material.copy(),
                                            material_table=self.elements.material_table.copy(), fast=fast)
        twin.row = self.row.copy()
        twin.started, twin.changed, twin.factor = (np.empty_like(a) for a in (self.started, self.changed,
                                                                             self.factor))
        return twin

    def set_damage(self, which: np.ndarray, damage: np.ndarray) -> None:
        """Give the elements ``which`` the isochoric moduli of the intact material times (1 - damage)."""
        elements = self.elements
        fast = elements.fast
        which = np.asarray(which, dtype=np.int64)
        keep = 1.0 - np.asarray(damage, dtype=np.float64)
        parent = self.parent[which]
        new = which[self.row[which] < 0]
        if new.size:
            self.row[new] = elements.material_table.shape[0] + np.arange(new.size)
            elements.material_table = np.concatenate([elements.material_table,
                                                      elements.material_table[self.parent[new]]])
            elements.element_material[new] = self.row[new]
            if fast is not None:
                fast["material"] = np.concatenate([fast["material"], fast["material"][self.parent[new]]])
                block, lane = np.divmod(new, elements.block_size)
                fast["element_material"][block, lane] = self.row[new]
                fast["block_material"][block] = -1
        rows = self.row[which]
        table = elements.material_table[parent]
        table[:, [P_C10, P_C01, P_C20, P_C30, P_FIBRE_K1]] *= keep[:, None]
        elements.material_table[rows] = table
        if fast is not None:
            # kernel constants (``_kernel_form.packed_constants``): C10, C01, C20, C30 and the
            # fibre stiffness k1 scale with (1 - D), the Prony dissipation factors
            # 1 / (2 g_i mu_0 tau_i) with 1 / (1 - D); the rest (K, g_inf, 1 / limit, Prony
            # factors, the other fibre constants) is the parent's
            fields = fast["material"][parent]
            fields[:, M_C10:M_C30 + 1] *= keep[:, None]
            fields[:, M_FIBRE_K1] *= keep
            fields[:, M_DISSIPATION:M_DISSIPATION + MAX_PRONY_TERMS] /= keep[:, None]
            fast["material"][rows] = fields


def update_softening(model, state, deleted: np.ndarray, count: int) -> int:
    """The failure check of one step with softening; returns the new number of entries of ``deleted``.

    Elements without fracture energy are deleted when their criterion is met; the others
    start or continue softening (module notes).
    """
    softening = model.softening
    rows = state.softening_rows
    count, n_started, n_changed = update_damage(
        state.failure_ratio, softening.fracture_energy, state.alive, state.damage,
        rows.started, rows.changed, rows.factor, deleted, count)
    elements = state.elements
    if n_started:
        which = rows.started[:n_started].copy()
        energy = np.empty(n_started)
        energy_densities(elements.cells, elements.b, elements.hoop, state.u, elements.element_material,
                         elements.material_table, elements.fibre_frame, which, energy)
        for k, e in enumerate(which):
            r = state.failure_ratio[e]
            ultimate = ultimate_ratio(softening.fracture_energy[e], softening.size[e], energy[k] / r ** 2)
            if not (ultimate > 1.0 and (ultimate - r) / (ultimate - 1.0) > RESIDUAL):
                state.alive[e] = 0
                deleted[count] = e
                count += 1
                continue
            damage = 1.0 - (ultimate - r) / ((ultimate - 1.0) * r)
            state.damage[e] = damage, r, ultimate
            rows.changed[n_changed] = e
            rows.factor[n_changed] = 1.0 - damage
            n_changed += 1
    if n_changed:
        _scale_changed(state, n_changed)
    return count


def _scale_changed(state, n_changed: int) -> None:
    """New material rows for the elements whose damage grew; their stress history scaled to match."""
    rows = state.softening_rows
    elements = state.elements
    which = rows.changed[:n_changed].copy()
    rows.set_damage(which, state.damage[which, DAMAGE])
    block, lane = np.divmod(which, elements.block_size)
    stress_rows = np.arange(elements.n_history - 2)
    state.history[block[:, None], stress_rows[None, :], lane[:, None]] *= rows.factor[:n_changed, None]


def restore_softening_rows(state) -> None:
    """Rebuild the material rows of the softened live elements of a restored ``state``."""
    which = np.flatnonzero((state.damage[:, DAMAGE] > 0.0) & (state.alive != 0))
    if which.size:
        state.softening_rows.set_damage(which, state.damage[which, DAMAGE])
