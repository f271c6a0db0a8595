"""Reference element kernels: one element at a time, written to be read and tested.

Both kernels evaluate, per live element e with mean gradients b_a (and hoop weights h_a),

.. math::

    F = \\sum_a x_a \\otimes b_a, \\qquad
    f^{int}_a = V_e\\, (F S + q\\, \\mathrm{cof}\\, F)\\, b_a + k_e \\sum_\\alpha \\gamma_{\\alpha a} q_\\alpha,
    \\qquad q_\\alpha = \\sum_a \\gamma_{\\alpha a} u_a ,

with the bulk-viscous pressure q (driven by the volumetric rate of ``_rate``) and the
Flanagan-Belytschko hourglass stiffness k_e (``docs/elements.md``). The axisymmetric quad adds the hoop row
F_thth = sum_a r_a h_a, force V_e P_thth h_a on u_r.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.materials.kernel import VOIGT, cauchy_from_pk2, limit_ratio, von_mises
from corneasim.solver.elements._constitutive import cofactor
from corneasim.solver.elements._material_point import material_stress
from corneasim.solver.elements._rate import stored_volumetric_rate


@njit(cache=True)
def _gradient(cells, b, hoop, field, e, G):
    """G (3, 3) = sum_a field_a (x) b_a of element e (plus the hoop entry sum_a field_ra h_a
    when axisymmetric, dim == 2): with the displacement, F - I."""
    dim = b.shape[2]
    G[:] = 0.0
    for a in range(cells.shape[1]):
        n = cells[e, a]
        for i in range(dim):
            for j in range(dim):
                G[i, j] += field[n, i] * b[e, a, j]
        if dim == 2:
            G[2, 2] += field[n, 0] * hoop[e, a]


@njit(cache=True)
def _deformation_gradient(cells, b, hoop, u, e, F):
    """F = I + sum_a u_a (x) b_a (total-Lagrangian; sum_a X_a (x) b_a = I exactly)."""
    _gradient(cells, b, hoop, u, e, F)
    for i in range(3):
        F[i, i] += 1.0


@njit(cache=True)
def internal_forces_reference(points, cells, b, hoop, gamma, volume, hourglass_stiffness,
                              bulk_linear, bulk_quadratic, element_material, table, fibre_frame,
                              prony_a, prony_b, block_size, u, dt, alive, history,
                              f_int, failure_ratio, energy_rates):
    """Internal forces, Prony update, failure ratios and energies (see module doc).

    energy_rates: hourglass energy k_e sum_alpha |q_alpha|^2 / 2 (mJ), bulk-viscous and
    viscoelastic power (mJ/s). dt, s: the step just taken (0: evaluate without advancing).

    points (n_nodes, dim) mm; cells (n_e, n_nodes_e); b (n_e, n_nodes_e, dim) 1/mm;
    hoop (n_e, 4) 1/mm (axisymmetric) or (0, 0); gamma (n_e, n_modes, n_nodes_e);
    volume (n_e,) mm^3; hourglass_stiffness (n_e,) N/mm; bulk_linear (n_e,) MPa s
    (b1 rho c_d L); bulk_quadratic (n_e,) MPa s^2 (rho (b2 L)^2); fibre_frame (n_e, 6)
    the unit vectors (m, n) of each element's lamellar plane (``_material_point``).
    """
    dim = points.shape[1]
    n_e, n_per = cells.shape
    f_int[:] = 0.0
    energy_rates[:] = 0.0
    F = np.empty((3, 3))
    P = np.empty((3, 3))
    S = np.empty(6)
    sigma = np.empty(6)
    for e in range(n_e):
        failure_ratio[e] = 0.0
        if not alive[e]:
            continue
        m = element_material[e]
        _deformation_gradient(cells, b, hoop, u, e, F)
        J, dissipation = material_stress(F, table, m, prony_a, prony_b, history,
                                         e // block_size, e % block_size, np.bool_(True), S,
                                         4 if dim == 2 else 6, fibre_frame[e])
        cauchy_from_pk2(F, S, J, sigma)
        failure_ratio[e] = limit_ratio(
            von_mises(sigma[0], sigma[1], sigma[2], sigma[3], sigma[4], sigma[5]), table[m])
        rates = history.shape[1] - 2  # J^n - 1 and the last rate (_rate.volumetric_rate)
        blk, lane = e // block_size, e % block_size
        edot = stored_volumetric_rate(J, history, blk, lane, rates, dt)
        q = edot * (bulk_linear[e] + bulk_quadratic[e] * max(-edot, 0.0))
        cof = cofactor(F[0, 0], F[0, 1], F[0, 2], F[1, 0], F[1, 1], F[1, 2], F[2, 0], F[2, 1], F[2, 2])
        for i in range(3):  # P = F S + q cof F, written out (a matrix product compiles BLAS's dgemm)
            for j in range(3):
                P[i, j] = (F[i, 0] * S[VOIGT[0, j]] + F[i, 1] * S[VOIGT[1, j]]
                           + F[i, 2] * S[VOIGT[2, j]] + q * cof[3 * i + j])
        V = volume[e]
        for a in range(n_per):
            n = cells[e, a]
            for i in range(dim):
                s = 0.0
                for j in range(dim):
                    s += P[i, j] * b[e, a, j]
                if dim == 2 and i == 0:
                    s += P[2, 2] * hoop[e, a]
                f_int[n, i] += V * s
        k = hourglass_stiffness[e]
        for mode in range(gamma.shape[1]):
            for i in range(dim):
                qx = 0.0
                for a in range(n_per):
                    qx += gamma[e, mode, a] * u[cells[e, a], i]
                for a in range(n_per):
                    f_int[cells[e, a], i] += k * gamma[e, mode, a] * qx
                energy_rates[0] += 0.5 * k * qx * qx
        energy_rates[1] += q * edot * J * V
        energy_rates[2] += dissipation * V


@njit(cache=True)
def stress_reference(points, cells, b, hoop, element_material, table, fibre_frame, block_size, u,
                     history, cauchy):
    """Cauchy stress (n_e, 6) MPa from u and the stored Prony history (no update)."""
    F = np.empty((3, 3))
    S = np.empty(6)
    sigma = np.empty(6)
    prony = np.zeros((table.shape[0], 4))
    for e in range(cells.shape[0]):
        _deformation_gradient(cells, b, hoop, u, e, F)
        J, _ = material_stress(F, table, element_material[e], prony, prony, history,
                               e // block_size, e % block_size, np.bool_(False), S,
                               4 if b.shape[2] == 2 else 6, fibre_frame[e])
        cauchy_from_pk2(F, S, J, sigma)
        for i in range(6):  # element by element: a slice copy compiles a shape check's message
            cauchy[e, i] = sigma[i]


@njit(cache=True)
def jacobians_reference(points, cells, b, hoop, u, out):
    """det F at the element centre (mean gradient), (n_e,)."""
    F = np.empty((3, 3))
    for e in range(cells.shape[0]):
        _deformation_gradient(cells, b, hoop, u, e, F)
        if b.shape[2] == 3:  # cofactor expansion: np.linalg.det calls LAPACK per element
            out[e] = (F[0, 0] * (F[1, 1] * F[2, 2] - F[1, 2] * F[2, 1])
                      - F[0, 1] * (F[1, 0] * F[2, 2] - F[1, 2] * F[2, 0])
                      + F[0, 2] * (F[1, 0] * F[2, 1] - F[1, 1] * F[2, 0]))
        else:
            out[e] = F[2, 2] * (F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0])
