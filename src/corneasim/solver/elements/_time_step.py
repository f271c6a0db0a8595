"""Element stable time steps from the current geometry (a parallel kernel per element kind).

dt_e = (L_e / c_e)(sqrt(1 + b1^2) - b1), c_e = sqrt((K max(J, 1) + 4/3 mu_t) / rho) with the
instantaneous moduli (``docs/elements.md``). L_e = area / longest diagonal for the quad. For the
one-point hexahedron, L_e is the Flanagan-Belytschko bound of the largest eigenvalue,
omega_max^2 <= 2 c^2 sum_a |grad_x N_a|^2 (Flanagan & Belytschko 1981,
doi:10.1002/nme.1620170504), i.e.

    L_e = 1 / sqrt(2 sum_a |F^-T b_a|^2) = 1 / sqrt(2 tr(C^-1 sum_a b_a b_a^T)),

b_a the reference mean gradients: h / sqrt(3) for a cube of side h, the 3D Courant limit. The
earlier volume / largest face area (h for a cube) let a free cube diverge at 0.7 of its step.

**Fibres.** A fibre material adds the fibres' current tangent to the modulus,

    M_f = sum_(families) [4 Psi''_+(E) (tr hbar)^2 + 2 Psi'(E) tr hbar],
    tr hbar = kappa Ibar_1 + (1 - 3 kappa) Ibar_4,

with hbar = kappa Bbar + (1 - 3 kappa) abar (x) abar (``materials._fibre_law``): the family's
share of the acoustic tensor, (4 / J) Psi'' (hbar n)(hbar n) + (2 / J) Psi' (n . hbar n) in
the wave direction n, is bounded by M_f for every n (|hbar n| <= tr hbar, hbar positive
semi-definite; J ~ 1 for the nearly incompressible tissue). Psi''_+ is the tangent on the
stretched side (``fibre_tangent_bound``), also for a family at rest or compressed, so the
bound does not jump when a family crosses the switch: at rest M_f = 4 k1 per family, the
small-strain fibre modulus of uniaxial tension along an aligned family (kappa = 0).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from corneasim.materials.kernel import (
    P_C01, P_C10, P_C20, P_C30, P_D1, P_DENSITY, P_FIBRE_ANGLE, P_FIBRE_K1, P_FIBRE_K2,
    P_FIBRE_KAPPA, fibre_derivatives, fibre_strain, fibre_tangent_bound, inverse_sym)
from corneasim.solver.elements._constitutive import (
    cube_root, right_cauchy_green, tangent_shear_modulus)
from corneasim.solver.elements._schedule import active_threads, use_threads


@njit(cache=True)
def fibre_modulus(C11, C22, C33, C12, C23, C31, Jm23, row, frame):
    """M_f (MPa) of the two fibre families (module doc) at C, J^{-2/3} = Jm23, a material
    row and the element's fibre frame (6,)."""
    k1, k2, kappa = row[P_FIBRE_K1], row[P_FIBRE_K2], row[P_FIBRE_KAPPA]
    c, sn = np.cos(row[P_FIBRE_ANGLE]), np.sin(row[P_FIBRE_ANGLE])
    I1b = Jm23 * (C11 + C22 + C33)
    modulus = 0.0
    for sign in (1.0, -1.0):
        a1 = c * frame[0] + sign * sn * frame[3]
        a2 = c * frame[1] + sign * sn * frame[4]
        a3 = c * frame[2] + sign * sn * frame[5]
        I4b = Jm23 * (a1 * (C11 * a1 + C12 * a2 + C31 * a3) + a2 * (C12 * a1 + C22 * a2 + C23 * a3)
                      + a3 * (C31 * a1 + C23 * a2 + C33 * a3))
        E = fibre_strain(I1b, I4b, kappa)
        d, _ = fibre_derivatives(E, k1, k2)
        trace = kappa * I1b + (1.0 - 3.0 * kappa) * I4b
        modulus += 4.0 * fibre_tangent_bound(E, k1, k2) * trace * trace + 2.0 * d * trace
    return modulus


@njit(cache=True, inline="always")
def wave_modulus(F11, F12, F13, F21, F22, F23, F31, F32, F33, J, row, frame):
    """K max(J, 1) + 4/3 mu_t, plus the fibres' bound M_f for a fibre material (MPa; module
    doc), at F and J = det F, for a material row and the element's fibre frame (6,)."""
    I1 = (F11 * F11 + F12 * F12 + F13 * F13 + F21 * F21 + F22 * F22 + F23 * F23
          + F31 * F31 + F32 * F32 + F33 * F33)
    I1b = I1 / cube_root(J * J) if J > 0.0 else 3.0
    mu_t = tangent_shear_modulus(I1b, row[P_C10], row[P_C01], row[P_C20], row[P_C30])
    modulus = 2.0 / row[P_D1] * max(J, 1.0) + 4.0 / 3.0 * mu_t
    if row[P_FIBRE_K1] > 0.0:
        C = right_cauchy_green(F11, F12, F13, F21, F22, F23, F31, F32, F33)
        modulus += fibre_modulus(C[0], C[1], C[2], C[3], C[4], C[5],
                                 1.0 / cube_root(J * J) if J > 0.0 else 1.0, row, frame)
    return modulus


@njit(cache=True, inline="always")
def quad_length(points, u, cells, e):
    """L_e of a quadrilateral (mm): its area over its longest diagonal, at the positions
    points + u (read node by node: an array expression points + u would be a parallel loop
    of its own in a parallel kernel)."""
    n0, n1, n2, n3 = cells[e, 0], cells[e, 1], cells[e, 2], cells[e, 3]
    r0, z0 = points[n0, 0] + u[n0, 0], points[n0, 1] + u[n0, 1]
    r1, z1 = points[n1, 0] + u[n1, 0], points[n1, 1] + u[n1, 1]
    r2, z2 = points[n2, 0] + u[n2, 0], points[n2, 1] + u[n2, 1]
    r3, z3 = points[n3, 0] + u[n3, 0], points[n3, 1] + u[n3, 1]
    area = 0.5 * abs((r2 - r0) * (z3 - z1) - (r3 - r1) * (z2 - z0))
    diagonal = max(np.sqrt((r2 - r0) ** 2 + (z2 - z0) ** 2), np.sqrt((r3 - r1) ** 2 + (z3 - z1) ** 2))
    return area / diagonal


@njit(cache=True, parallel=True)
def quad_stable_time_steps(points, cells, b, hoop, element_material, table, fibre_frame, u, b1,
                           out, threads):
    """Fill out (n_e,) with the stable time steps of axisymmetric quads, s (fibre_frame (n_e, 6):
    ``ElementSet.fibre_frame``), on at most ``threads`` threads (``_schedule.use_threads``).
    One kernel per element kind: a kernel with both kinds behind a branch on the dimension
    compiles both for every run."""
    saved = active_threads()
    use_threads(min(threads, saved))
    factor = np.sqrt(1.0 + b1 * b1) - b1
    for e in prange(cells.shape[0]):
        G11 = G12 = G21 = G22 = G33 = 0.0
        for a in range(cells.shape[1]):
            n = cells[e, a]
            G11 += u[n, 0] * b[e, a, 0]
            G12 += u[n, 0] * b[e, a, 1]
            G21 += u[n, 1] * b[e, a, 0]
            G22 += u[n, 1] * b[e, a, 1]
            G33 += u[n, 0] * hoop[e, a]
        F11, F12, F21, F22, F33 = 1.0 + G11, G12, G21, 1.0 + G22, 1.0 + G33
        J = F11 * (F22 * F33) - F12 * (F21 * F33)  # the hexahedron's cofactor expansion
        m = element_material[e]
        modulus = wave_modulus(F11, F12, 0.0, F21, F22, 0.0, 0.0, 0.0, F33, J, table[m], fibre_frame[e])
        out[e] = quad_length(points, u, cells, e) / np.sqrt(modulus / table[m, P_DENSITY]) * factor
    use_threads(saved)


@njit(cache=True, parallel=True)
def hex_stable_time_steps(points, cells, b, element_material, table, fibre_frame, u, b1, out,
                          threads):
    """Fill out (n_e,) with the stable time steps of hexahedra, s (as
    :func:`quad_stable_time_steps`)."""
    saved = active_threads()
    use_threads(min(threads, saved))
    factor = np.sqrt(1.0 + b1 * b1) - b1
    for e in prange(cells.shape[0]):
        G11 = G12 = G13 = G21 = G22 = G23 = G31 = G32 = G33 = 0.0
        B11 = B22 = B33 = B12 = B13 = B23 = 0.0
        for a in range(cells.shape[1]):
            n = cells[e, a]
            B11 += b[e, a, 0] * b[e, a, 0]
            B22 += b[e, a, 1] * b[e, a, 1]
            B33 += b[e, a, 2] * b[e, a, 2]
            B12 += b[e, a, 0] * b[e, a, 1]
            B13 += b[e, a, 0] * b[e, a, 2]
            B23 += b[e, a, 1] * b[e, a, 2]
            b0, b1_, b2 = b[e, a, 0], b[e, a, 1], b[e, a, 2]
            G11 += u[n, 0] * b0
            G21 += u[n, 1] * b0
            G31 += u[n, 2] * b0
            G12 += u[n, 0] * b1_
            G22 += u[n, 1] * b1_
            G32 += u[n, 2] * b1_
            G13 += u[n, 0] * b2
            G23 += u[n, 1] * b2
            G33 += u[n, 2] * b2
        F11, F12, F13 = 1.0 + G11, G12, G13
        F21, F22, F23 = G21, 1.0 + G22, G23
        F31, F32, F33 = G31, G32, 1.0 + G33
        J = (F11 * (F22 * F33 - F23 * F32) - F12 * (F21 * F33 - F23 * F31)
             + F13 * (F21 * F32 - F22 * F31))
        C11, C22, C33, C12, C23, C31 = right_cauchy_green(F11, F12, F13, F21, F22, F23, F31, F32, F33)
        K11, K22, K33, K12, K23, K31 = inverse_sym(C11, C22, C33, C12, C23, C31, J * J)
        trace = K11 * B11 + K22 * B22 + K33 * B33 + 2.0 * (K12 * B12 + K31 * B13 + K23 * B23)
        length = 1.0 / np.sqrt(2.0 * trace)
        m = element_material[e]
        modulus = wave_modulus(F11, F12, F13, F21, F22, F23, F31, F32, F33, J, table[m], fibre_frame[e])
        out[e] = length / np.sqrt(modulus / table[m, P_DENSITY]) * factor
    use_threads(saved)
