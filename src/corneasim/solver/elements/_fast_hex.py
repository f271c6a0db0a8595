"""Fast hexahedron kernel: SIMD across a block's elements, Walsh-Hadamard formulation.

With the nodes in binary order (bit 0: xi, bit 1: eta, bit 2: zeta) the 8 x 8 matrix
H[k, a] = prod_{bit b in k} sign_b(a) has rows 1, xi, eta, xi eta, zeta, xi zeta,
eta zeta, xi eta zeta, and H H^T = 8 I. One butterfly gives all projections
u_hat = H u at once; with Bt = H b / 8 (21 numbers, the constant row is zero) and
c_alpha = H_alpha X (12 numbers, alpha in the four hourglass rows 3, 5, 6, 7):

.. math::

    F - I = \\sum_{k=1}^{7} \\hat u_k \\otimes \\hat b_k, \\qquad
    Q_\\alpha = \\hat u_\\alpha - (F - I)\\, c_\\alpha = 8 q_\\alpha,

    f = H^T g, \\quad g_k = M \\hat b_k + \\tfrac{k_e}{64} Q_k [k \\in \\{3,5,6,7\\}], \\quad
    M = V_e P - \\tfrac{k_e}{64} \\sum_\\alpha Q_\\alpha \\otimes c_\\alpha ,

which is the reference kernel's f_a = V P b_a + k_e sum_alpha gamma_alpha,a q_alpha
(gamma_alpha = (h_alpha - sum_j c_alpha,j b_j)/8, q_alpha = gamma_alpha . u) rewritten in
the Hadamard basis (``docs/performance.md``); the hourglass energy is
k_e sum |q_alpha|^2 / 2 = (k_e / 64) sum |Q_alpha|^2 / 2. The per-element geometry is 37
numbers, with k_e / 64 in place of k_e (the amplitudes are used unscaled: no 1/8 per lane);
the deformation pass stores (k_e / 64) Q_alpha, which is all the later passes need.
Memory layout, masking and the inlined material law (``materials.kernel``) as in
``_fast_quad``.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from corneasim.materials.kernel import (
    M_BULK, M_C01, M_C10, M_C20, M_C30, M_DISSIPATION, M_FIBRE_COS, M_FIBRE_K1, M_FIBRE_K2,
    M_FIBRE_KAPPA, M_FIBRE_SIN, M_INVERSE_LIMIT, M_LONG_TERM, M_PRONY_A, M_PRONY_B, N_PACKED,
    fibre_pk2, isochoric_pk2, prony_step, volumetric_factor, von_mises)
from corneasim.solver.elements._constitutive import cofactor, inverse_cube_root, right_cauchy_green
from corneasim.solver.elements._geometry import HEX_CORNERS
from corneasim.solver.elements._layout import HEX_BLOCK_SIZE as B
from corneasim.solver.elements._rate import volumetric_rate
from corneasim.solver.elements._schedule import active_threads, claim_part, use_threads

BINARY_ORDER = np.array([0, 1, 3, 2, 4, 5, 7, 6])  # binary index -> VTK node
HOURGLASS_ROWS = (3, 5, 6, 7)
N_GEOMETRY = 37  # Bt (3 x 7) c (4 x 3) V k/64 bv1 bv2
N_FRAME = 6  # fibre frame rows: the unit vectors m and n of the lamellar plane
N_HISTORY = 32  # S0bar (6), h_1..h_4 (6 each), J^n - 1, edot
HJ, HEDOT = 30, 31  # history rows of the volumetric rate (``_rate.volumetric_rate``)
UX, MASK = 0, 24  # u: row 8 i + a (component i, binary node a)
MAT = 25  # N_PACKED rows: the material row (``_kernel_form.M_*``) with this step's Prony factors
RATIO = MAT + N_PACKED
KF = RATIO + 1  # pass results: F (9, row by row), Q_alpha (12), J, J^-2/3, 1/J, S (6)
KQ = KF + 9
KJ, KJM23, KIJ = KQ + 12, KQ + 13, KQ + 14
KS = KQ + 15
KM = KS + 6  # M of the force pass (9, row by row)
N_SCRATCH = KM + 9
FX = UX  # forces overwrite u (same lane, after its last read): row 8 i + a
BT, CH, VOL, KHG, BV1, BV2 = 0, 21, 33, 34, 35, 36


def hadamard_matrix():
    """H (8, 8) in binary node order."""
    signs = HEX_CORNERS[BINARY_ORDER]  # (8, 3) corner signs in binary order
    H = np.ones((8, 8))
    for k in range(8):
        for bit in range(3):
            if k >> bit & 1:
                H[k] *= signs[:, bit]
    return H


def hadamard_geometry(elements):
    """Per-element rows (n_e, N_GEOMETRY) and the cells in binary node order."""
    H = hadamard_matrix()
    b = elements.b[:, BINARY_ORDER, :]  # (n_e, 8, 3)
    X = elements.points[elements.cells[:, BINARY_ORDER]]  # (n_e, 8, 3)
    Bt = np.einsum("ka,eaj->ejk", H, b)[:, :, 1:] / 8.0  # (n_e, 3, 7)
    c = np.einsum("ka,eaj->ekj", H[list(HOURGLASS_ROWS)], X)  # (n_e, 4, 3)
    rows = np.concatenate([Bt.reshape(-1, 21), c.reshape(-1, 12),
                           np.stack([elements.volume, elements.hourglass_stiffness / 64.0,
                                     elements.bulk_linear, elements.bulk_quadratic], axis=1)],
                          axis=1)
    return rows, np.ascontiguousarray(elements.cells[:, BINARY_ORDER])


@njit(cache=True, inline="always")
def _butterfly(x0, x1, x2, x3, x4, x5, x6, x7):
    """(H x)_k for k = 1..7 (the constant row is not needed)."""
    a0, a1, a2, a3 = x0 + x1, x1 - x0, x2 + x3, x3 - x2
    a4, a5, a6, a7 = x4 + x5, x5 - x4, x6 + x7, x7 - x6
    b0, b1, b2, b3 = a0 + a2, a1 + a3, a2 - a0, a3 - a1
    b4, b5, b6, b7 = a4 + a6, a5 + a7, a6 - a4, a7 - a5
    return b1 + b5, b2 + b6, b3 + b7, b4 - b0, b5 - b1, b6 - b2, b7 - b3


@njit(cache=True, inline="always")
def _inverse_butterfly(g1, g2, g3, g4, g5, g6, g7):
    """x_a = sum_k H[k, a] g_k with g_0 = 0."""
    b0, b4 = -g4, g4
    b1, b5 = g1 - g5, g1 + g5
    b2, b6 = g2 - g6, g2 + g6
    b3, b7 = g3 - g7, g3 + g7
    a0, a2 = b0 - b2, b0 + b2
    a1, a3 = b1 - b3, b1 + b3
    a4, a6 = b4 - b6, b4 + b6
    a5, a7 = b5 - b7, b5 + b7
    return a0 - a1, a0 + a1, a2 - a3, a2 + a3, a4 - a5, a4 + a5, a6 - a7, a6 + a7


@njit(cache=True, inline="always")
def _butterfly_row(s, row, l):
    """``_butterfly`` of the eight scratch rows starting at ``row``, lane l."""
    return _butterfly(s[row * B + l], s[(row + 1) * B + l], s[(row + 2) * B + l],
                      s[(row + 3) * B + l], s[(row + 4) * B + l], s[(row + 5) * B + l],
                      s[(row + 6) * B + l], s[(row + 7) * B + l])


@njit(cache=True, inline="always")
def _contract7(h1, h2, h3, h4, h5, h6, h7, g, row, l):
    """sum_k h_k Bt[row, k] over k = 1..7 (row = BT + 7 j)."""
    return (h1 * g[row * B + l] + h2 * g[(row + 1) * B + l] + h3 * g[(row + 2) * B + l]
            + h4 * g[(row + 3) * B + l] + h5 * g[(row + 4) * B + l]
            + h6 * g[(row + 5) * B + l] + h7 * g[(row + 6) * B + l])


@njit(cache=True, inline="always")
def _forces_row(s, g, row, l, Ma, Mb, Mc, ha, hb, hc, hd):
    """Nodal forces of one component: f = H^T g with g_k = M . Bt_k (+ k Q / 64 on rows
    3, 5, 6, 7), written to the eight scratch rows starting at ``row``."""
    r1 = Ma * g[BT * B + l] + Mb * g[(BT + 7) * B + l] + Mc * g[(BT + 14) * B + l]
    r2 = Ma * g[(BT + 1) * B + l] + Mb * g[(BT + 8) * B + l] + Mc * g[(BT + 15) * B + l]
    r3 = Ma * g[(BT + 2) * B + l] + Mb * g[(BT + 9) * B + l] + Mc * g[(BT + 16) * B + l] + ha
    r4 = Ma * g[(BT + 3) * B + l] + Mb * g[(BT + 10) * B + l] + Mc * g[(BT + 17) * B + l]
    r5 = Ma * g[(BT + 4) * B + l] + Mb * g[(BT + 11) * B + l] + Mc * g[(BT + 18) * B + l] + hb
    r6 = Ma * g[(BT + 5) * B + l] + Mb * g[(BT + 12) * B + l] + Mc * g[(BT + 19) * B + l] + hc
    r7 = Ma * g[(BT + 6) * B + l] + Mb * g[(BT + 13) * B + l] + Mc * g[(BT + 20) * B + l] + hd
    f0, f1, f2, f3, f4, f5, f6, f7 = _inverse_butterfly(r1, r2, r3, r4, r5, r6, r7)
    s[row * B + l] = f0
    s[(row + 1) * B + l] = f1
    s[(row + 2) * B + l] = f2
    s[(row + 3) * B + l] = f3
    s[(row + 4) * B + l] = f4
    s[(row + 5) * B + l] = f5
    s[(row + 6) * B + l] = f6
    s[(row + 7) * B + l] = f7


@njit(cache=True, inline="always")
def _load_f(s, l):
    """The nine entries of F stored by ``_deformation``, row by row."""
    return (s[KF * B + l], s[(KF + 1) * B + l], s[(KF + 2) * B + l],
            s[(KF + 3) * B + l], s[(KF + 4) * B + l], s[(KF + 5) * B + l],
            s[(KF + 6) * B + l], s[(KF + 7) * B + l], s[(KF + 8) * B + l])


@njit(cache=True, inline="always")
def _hourglass_amplitude(w1, w2, w3, G, g, row, l):
    """The unscaled hourglass amplitude Q_alpha = w_alpha - G c_alpha (8 q_alpha) from the
    projections w of one hourglass row of H, G = F - I (a 9-tuple, row by row) and
    c_alpha = g[row .. row + 2]."""
    G11, G12, G13, G21, G22, G23, G31, G32, G33 = G
    c1, c2, c3 = g[row * B + l], g[(row + 1) * B + l], g[(row + 2) * B + l]
    return (w1 - G11 * c1 - G12 * c2 - G13 * c3, w2 - G21 * c1 - G22 * c2 - G23 * c3,
            w3 - G31 * c1 - G32 * c2 - G33 * c3)


@njit(cache=True, fastmath=True, error_model="numpy")
def _deformation(s, g):
    """Pass 1: F (dead lanes: identity), J and the hourglass amplitudes into ``s``, each
    scaled by the lane's k / 64 (0 for a dead lane): (k / 64) Q_alpha is what the force and
    resultant passes use.

    F - I = sum_k u_hat_k (x) Bt_k and Q_alpha = u_hat_alpha - (F - I) c_alpha = 8 q_alpha.
    Returns the hourglass energy (k / 64) sum_alpha |Q_alpha|^2 / 2, mJ (stiffness-type hourglass
    control stores it).
    """
    e_hg = 0.0
    for l in range(B):
        m = s[MASK * B + l]
        x1, x2, x3, x4, x5, x6, x7 = _butterfly_row(s, UX, l)
        y1, y2, y3, y4, y5, y6, y7 = _butterfly_row(s, UX + 8, l)
        z1, z2, z3, z4, z5, z6, z7 = _butterfly_row(s, UX + 16, l)
        G11 = m * _contract7(x1, x2, x3, x4, x5, x6, x7, g, BT, l)
        G12 = m * _contract7(x1, x2, x3, x4, x5, x6, x7, g, BT + 7, l)
        G13 = m * _contract7(x1, x2, x3, x4, x5, x6, x7, g, BT + 14, l)
        G21 = m * _contract7(y1, y2, y3, y4, y5, y6, y7, g, BT, l)
        G22 = m * _contract7(y1, y2, y3, y4, y5, y6, y7, g, BT + 7, l)
        G23 = m * _contract7(y1, y2, y3, y4, y5, y6, y7, g, BT + 14, l)
        G31 = m * _contract7(z1, z2, z3, z4, z5, z6, z7, g, BT, l)
        G32 = m * _contract7(z1, z2, z3, z4, z5, z6, z7, g, BT + 7, l)
        G33 = m * _contract7(z1, z2, z3, z4, z5, z6, z7, g, BT + 14, l)
        G = (G11, G12, G13, G21, G22, G23, G31, G32, G33)
        a1, a2, a3 = _hourglass_amplitude(x3, y3, z3, G, g, CH, l)
        b1, b2, b3 = _hourglass_amplitude(x5, y5, z5, G, g, CH + 3, l)
        c1, c2, c3 = _hourglass_amplitude(x6, y6, z6, G, g, CH + 6, l)
        d1, d2, d3 = _hourglass_amplitude(x7, y7, z7, G, g, CH + 9, l)
        kq = m * g[KHG * B + l]
        s[KQ * B + l], s[(KQ + 1) * B + l], s[(KQ + 2) * B + l] = kq * a1, kq * a2, kq * a3
        s[(KQ + 3) * B + l], s[(KQ + 4) * B + l], s[(KQ + 5) * B + l] = kq * b1, kq * b2, kq * b3
        s[(KQ + 6) * B + l], s[(KQ + 7) * B + l], s[(KQ + 8) * B + l] = kq * c1, kq * c2, kq * c3
        s[(KQ + 9) * B + l], s[(KQ + 10) * B + l], s[(KQ + 11) * B + l] = kq * d1, kq * d2, kq * d3
        e_hg += 0.5 * kq * (a1 * a1 + a2 * a2 + a3 * a3 + b1 * b1 + b2 * b2 + b3 * b3 + c1 * c1
                            + c2 * c2 + c3 * c3 + d1 * d1 + d2 * d2 + d3 * d3)
        F11, F12, F13 = 1.0 + G11, G12, G13
        F21, F22, F23 = G21, 1.0 + G22, G23
        F31, F32, F33 = G31, G32, 1.0 + G33
        s[KF * B + l], s[(KF + 1) * B + l], s[(KF + 2) * B + l] = F11, F12, F13
        s[(KF + 3) * B + l], s[(KF + 4) * B + l], s[(KF + 5) * B + l] = F21, F22, F23
        s[(KF + 6) * B + l], s[(KF + 7) * B + l], s[(KF + 8) * B + l] = F31, F32, F33
        s[KJ * B + l] = (F11 * (F22 * F33 - F23 * F32) + F12 * (F23 * F31 - F21 * F33)
                         + F13 * (F21 * F32 - F22 * F31))
    return e_hg


@njit(cache=True, fastmath=True, error_model="numpy")
def _cube_root(s):
    """Pass 2: J^{-2/3} = y^2 and 1/J = y^3 into ``s`` (``_fast_quad._cube_root``)."""
    for l in range(B):
        y = inverse_cube_root(s[KJ * B + l])
        s[KJM23 * B + l] = y * y
        s[KIJ * B + l] = y * y * y


@njit(cache=True, fastmath=True, error_model="numpy")
def _stress(s, g, h, fr, viscous):
    """Pass 3: second Piola-Kirchhoff stress with the Prony update (``_fast_quad._stress``,
    also for ``viscous``), into ``s``; returns the viscoelastic dissipation power, mJ/s.
    ``fr``, the block's fibre frame rows (None for a mesh without fibre materials), adds to
    S0 the two fibre families a_(1,2) = c m +- s n (lanes without fibres have k1 = 0)."""
    e_ve = 0.0
    for l in range(B):
        m = s[MASK * B + l]
        F11, F12, F13, F21, F22, F23, F31, F32, F33 = _load_f(s, l)
        J = s[KJ * B + l]
        iJ = s[KIJ * B + l]
        Jm23 = s[KJM23 * B + l]
        C11, C22, C33, C12, C23, C31 = right_cauchy_green(F11, F12, F13, F21, F22, F23, F31, F32,
                                                          F33)
        c10 = s[(MAT + M_C10) * B + l]
        c01 = s[(MAT + M_C01) * B + l]
        c20 = s[(MAT + M_C20) * B + l]
        c30 = s[(MAT + M_C30) * B + l]
        Kb = s[(MAT + M_BULK) * B + l]
        ginf = s[(MAT + M_LONG_TERM) * B + l]
        iJ2 = iJ * iJ  # C^{-1} = cof(C) / J^2
        i11 = (C22 * C33 - C23 * C23) * iJ2
        i22 = (C11 * C33 - C31 * C31) * iJ2
        i33 = (C11 * C22 - C12 * C12) * iJ2
        i12 = (C23 * C31 - C12 * C33) * iJ2
        i23 = (C12 * C31 - C11 * C23) * iJ2
        i31 = (C12 * C23 - C22 * C31) * iJ2
        S0_11, S0_22, S0_33, S0_12, S0_23, S0_31 = isochoric_pk2(
            C11, C22, C33, C12, C23, C31, i11, i22, i33, i12, i23, i31, Jm23, c10, c01, c20, c30)
        if fr is not None:  # pruned by Numba when fr is None: the isotropic code
            c = s[(MAT + M_FIBRE_COS) * B + l]
            sn = s[(MAT + M_FIBRE_SIN) * B + l]
            k1 = s[(MAT + M_FIBRE_K1) * B + l]
            k2 = s[(MAT + M_FIBRE_K2) * B + l]
            kappa = s[(MAT + M_FIBRE_KAPPA) * B + l]
            cm1, cm2, cm3 = c * fr[l], c * fr[B + l], c * fr[2 * B + l]
            sn1, sn2, sn3 = sn * fr[3 * B + l], sn * fr[4 * B + l], sn * fr[5 * B + l]
            f11, f22, f33, f12, f23, f31 = fibre_pk2(
                C11, C22, C33, C12, C23, C31, i11, i22, i33, i12, i23, i31, Jm23,
                cm1 + sn1, cm2 + sn2, cm3 + sn3, k1, k2, kappa)
            g11, g22, g33, g12, g23, g31 = fibre_pk2(
                C11, C22, C33, C12, C23, C31, i11, i22, i33, i12, i23, i31, Jm23,
                cm1 - sn1, cm2 - sn2, cm3 - sn3, k1, k2, kappa)
            S0_11 += f11 + g11
            S0_22 += f22 + g22
            S0_33 += f33 + g33
            S0_12 += f12 + g12
            S0_23 += f23 + g23
            S0_31 += f31 + g31
        pv = volumetric_factor(J, Kb)
        S11 = pv * i11 + ginf * S0_11
        S22 = pv * i22 + ginf * S0_22
        S33 = pv * i33 + ginf * S0_33
        S12 = pv * i12 + ginf * S0_12
        S23 = pv * i23 + ginf * S0_23
        S31 = pv * i31 + ginf * S0_31
        d11 = S0_11 - h[l]
        d22 = S0_22 - h[B + l]
        d33 = S0_33 - h[2 * B + l]
        d12 = S0_12 - h[3 * B + l]
        d23 = S0_23 - h[4 * B + l]
        d31 = S0_31 - h[5 * B + l]
        h[l] += m * d11
        h[B + l] += m * d22
        h[2 * B + l] += m * d33
        h[3 * B + l] += m * d12
        h[4 * B + l] += m * d23
        h[5 * B + l] += m * d31
        hh = 0.0
        if viscous:  # loop-invariant: LLVM unswitches the loop
            for i in range(4):
                a_i = 1.0 + m * (s[(MAT + M_PRONY_A + i) * B + l] - 1.0)  # a dead lane keeps h_i
                b_i = m * s[(MAT + M_PRONY_B + i) * B + l]
                r = 6 * (i + 1) * B + l
                p11, p22, p33 = h[r], h[r + B], h[r + 2 * B]
                p12, p23, p31 = h[r + 3 * B], h[r + 4 * B], h[r + 5 * B]
                n11 = prony_step(a_i, b_i, p11, d11)
                n22 = prony_step(a_i, b_i, p22, d22)
                n33 = prony_step(a_i, b_i, p33, d33)
                n12 = prony_step(a_i, b_i, p12, d12)
                n23 = prony_step(a_i, b_i, p23, d23)
                n31 = prony_step(a_i, b_i, p31, d31)
                h[r], h[r + B], h[r + 2 * B] = n11, n22, n33
                h[r + 3 * B], h[r + 4 * B], h[r + 5 * B] = n12, n23, n31
                S11 += n11
                S22 += n22
                S33 += n33
                S12 += n12
                S23 += n23
                S31 += n31
                hh += s[(MAT + M_DISSIPATION + i) * B + l] * (
                    n11 * n11 + n22 * n22 + n33 * n33 + 2.0 * (n12 * n12 + n23 * n23 + n31 * n31))
        s[KS * B + l], s[(KS + 1) * B + l], s[(KS + 2) * B + l] = S11, S22, S33
        s[(KS + 3) * B + l], s[(KS + 4) * B + l], s[(KS + 5) * B + l] = S12, S23, S31
        e_ve += m * g[VOL * B + l] * hh
    return e_ve


@njit(cache=True, fastmath=True, error_model="numpy")
def _stress_resultant(s, g, h, rate_factor):
    """Pass 4: M = V (P + q cof F) - sum_alpha (k / 64) Q_alpha (x) c_alpha into ``s`` (the
    amplitudes come scaled from ``_deformation``) and the failure measure (the von Mises
    stress, divided by the limit in ``_scatter``). Returns the bulk-viscous power, mJ/s."""
    e_bv = 0.0
    for l in range(B):
        m = s[MASK * B + l]
        F11, F12, F13, F21, F22, F23, F31, F32, F33 = _load_f(s, l)
        K11, K12, K13, K21, K22, K23, K31, K32, K33 = cofactor(F11, F12, F13, F21, F22, F23,
                                                                F31, F32, F33)
        S11, S22, S33 = s[KS * B + l], s[(KS + 1) * B + l], s[(KS + 2) * B + l]
        S12, S23, S31 = s[(KS + 3) * B + l], s[(KS + 4) * B + l], s[(KS + 5) * B + l]
        J = s[KJ * B + l]
        iJ = s[KIJ * B + l]
        edot = volumetric_rate(J, h, HJ * B + l, HEDOT * B + l, m, rate_factor)
        q = edot * (g[BV1 * B + l] + g[BV2 * B + l] * max(-edot, 0.0))
        Pm11 = F11 * S11 + F12 * S12 + F13 * S31
        Pm12 = F11 * S12 + F12 * S22 + F13 * S23
        Pm13 = F11 * S31 + F12 * S23 + F13 * S33
        Pm21 = F21 * S11 + F22 * S12 + F23 * S31
        Pm22 = F21 * S12 + F22 * S22 + F23 * S23
        Pm23 = F21 * S31 + F22 * S23 + F23 * S33
        Pm31 = F31 * S11 + F32 * S12 + F33 * S31
        Pm32 = F31 * S12 + F32 * S22 + F33 * S23
        Pm33 = F31 * S31 + F32 * S23 + F33 * S33
        mV = m * g[VOL * B + l]
        qa1, qa2, qa3 = s[KQ * B + l], s[(KQ + 1) * B + l], s[(KQ + 2) * B + l]
        qb1, qb2, qb3 = s[(KQ + 3) * B + l], s[(KQ + 4) * B + l], s[(KQ + 5) * B + l]
        qc1, qc2, qc3 = s[(KQ + 6) * B + l], s[(KQ + 7) * B + l], s[(KQ + 8) * B + l]
        qd1, qd2, qd3 = s[(KQ + 9) * B + l], s[(KQ + 10) * B + l], s[(KQ + 11) * B + l]
        ca1, ca2, ca3 = g[CH * B + l], g[(CH + 1) * B + l], g[(CH + 2) * B + l]
        cb1, cb2, cb3 = g[(CH + 3) * B + l], g[(CH + 4) * B + l], g[(CH + 5) * B + l]
        cc1, cc2, cc3 = g[(CH + 6) * B + l], g[(CH + 7) * B + l], g[(CH + 8) * B + l]
        cd1, cd2, cd3 = g[(CH + 9) * B + l], g[(CH + 10) * B + l], g[(CH + 11) * B + l]
        s[KM * B + l] = mV * (Pm11 + q * K11) - (qa1 * ca1 + qb1 * cb1 + qc1 * cc1 + qd1 * cd1)
        s[(KM + 1) * B + l] = mV * (Pm12 + q * K12) - (qa1 * ca2 + qb1 * cb2 + qc1 * cc2
                                                            + qd1 * cd2)
        s[(KM + 2) * B + l] = mV * (Pm13 + q * K13) - (qa1 * ca3 + qb1 * cb3 + qc1 * cc3
                                                            + qd1 * cd3)
        s[(KM + 3) * B + l] = mV * (Pm21 + q * K21) - (qa2 * ca1 + qb2 * cb1 + qc2 * cc1
                                                            + qd2 * cd1)
        s[(KM + 4) * B + l] = mV * (Pm22 + q * K22) - (qa2 * ca2 + qb2 * cb2 + qc2 * cc2
                                                            + qd2 * cd2)
        s[(KM + 5) * B + l] = mV * (Pm23 + q * K23) - (qa2 * ca3 + qb2 * cb3 + qc2 * cc3
                                                            + qd2 * cd3)
        s[(KM + 6) * B + l] = mV * (Pm31 + q * K31) - (qa3 * ca1 + qb3 * cb1 + qc3 * cc1
                                                            + qd3 * cd1)
        s[(KM + 7) * B + l] = mV * (Pm32 + q * K32) - (qa3 * ca2 + qb3 * cb2 + qc3 * cc2
                                                            + qd3 * cd2)
        s[(KM + 8) * B + l] = mV * (Pm33 + q * K33) - (qa3 * ca3 + qb3 * cb3 + qc3 * cc3
                                                            + qd3 * cd3)
        e_bv += mV * q * edot * J
        # Kirchhoff stress of the material (no bulk viscosity) tau = P F^T = J sigma; von Mises
        t11 = Pm11 * F11 + Pm12 * F12 + Pm13 * F13
        t22 = Pm21 * F21 + Pm22 * F22 + Pm23 * F23
        t33 = Pm31 * F31 + Pm32 * F32 + Pm33 * F33
        t12 = Pm11 * F21 + Pm12 * F22 + Pm13 * F23
        t23 = Pm21 * F31 + Pm22 * F32 + Pm23 * F33
        t31 = Pm31 * F11 + Pm32 * F12 + Pm33 * F13
        s[RATIO * B + l] = iJ * von_mises(t11, t22, t33, t12, t23, t31)  # of sigma = tau / J
    return e_bv


@njit(cache=True, fastmath=True, error_model="numpy")
def _forces(s, g):
    """Pass 5: nodal forces f = H^T g (stress, bulk viscosity, hourglass) from M and the
    hourglass amplitudes, over the displacement rows of ``s``. A pass of its own so that
    the 21 gradient rows, M and the twelve amplitudes stay in registers."""
    for l in range(B):
        _forces_row(s, g, FX, l, s[KM * B + l], s[(KM + 1) * B + l], s[(KM + 2) * B + l],
                    s[KQ * B + l], s[(KQ + 3) * B + l], s[(KQ + 6) * B + l], s[(KQ + 9) * B + l])
        _forces_row(s, g, FX + 8, l, s[(KM + 3) * B + l], s[(KM + 4) * B + l],
                    s[(KM + 5) * B + l], s[(KQ + 1) * B + l], s[(KQ + 4) * B + l],
                    s[(KQ + 7) * B + l], s[(KQ + 10) * B + l])
        _forces_row(s, g, FX + 16, l, s[(KM + 6) * B + l], s[(KM + 7) * B + l],
                    s[(KM + 8) * B + l], s[(KQ + 2) * B + l], s[(KQ + 5) * B + l],
                    s[(KQ + 8) * B + l], s[(KQ + 11) * B + l])


@njit(cache=True, fastmath=True, error_model="numpy")
def _lanes(s, g, h, fr, rate_factor, viscous):
    """One block's element computations in five vector passes (``_fast_quad._lanes``).

    Returns the hourglass energy (mJ), the bulk-viscous and the viscoelastic power (mJ/s).
    """
    e_hg = _deformation(s, g)
    _cube_root(s)
    e_ve = _stress(s, g, h, fr, viscous)
    e_bv = _stress_resultant(s, g, h, rate_factor)
    _forces(s, g)
    return e_hg, e_bv, e_ve


@njit(cache=True, fastmath=True, error_model="numpy")
def _gather(blk, n_e, u, alive, cells, material, block_material, mat, s, loaded):
    """Nodal displacements (``u`` flat, node-major, 3 per node), alive mask and material
    rows into ``s``. The node indices are unsigned: a signed index costs the scalar gather
    Numba's negative-index wraparound (quad kernel 4-10% slower in an A/B timing).

    ``loaded`` is the material whose rows ``s`` already holds (-1: none); returns the
    material now held (-1 after a mixed block)."""
    for a in range(8):
        for l in range(B):
            k = np.uint64(3) * np.uint64(cells[blk, a, l])
            s[(UX + a) * B + l] = u[k]
            s[(UX + 8 + a) * B + l] = u[k + np.uint64(1)]
            s[(UX + 16 + a) * B + l] = u[k + np.uint64(2)]
    base = blk * B
    for l in range(B):
        e = base + l
        s[MASK * B + l] = float(alive[min(e, n_e - 1)]) * (1.0 if e < n_e else 0.0)
    uniform = block_material[blk]
    if uniform >= 0:
        if uniform != loaded:
            for row in range(N_PACKED):
                value = material[uniform, row]
                for l in range(B):
                    s[(MAT + row) * B + l] = value
    else:
        for row in range(N_PACKED):
            for l in range(B):
                s[(MAT + row) * B + l] = material[mat[blk, l], row]
    return uniform


@njit(cache=True, fastmath=True, error_model="numpy")
def _scatter(blk, n_e, cells_target, s, row_forces, failure_ratio):
    """Failure ratios (von Mises stress / limit; 0 for dead lanes) out, forces into the force
    rows."""
    base = blk * B
    for l in range(min(B, n_e - base)):
        failure_ratio[base + l] = (s[RATIO * B + l] * s[MASK * B + l]
                                   * s[(MAT + M_INVERSE_LIMIT) * B + l])
    for l in range(B):
        for a in range(8):
            k = np.uint64(3) * np.uint64(cells_target[blk, a, l])
            row_forces[k] += s[(FX + a) * B + l]
            row_forces[k + np.uint64(1)] += s[(FX + 8 + a) * B + l]
            row_forces[k + np.uint64(2)] += s[(FX + 16 + a) * B + l]


@njit(cache=True, parallel=True, fastmath=True, error_model="numpy")
def hex_internal_forces(u, rate_factor, alive, cells, cells_target, geom, material,
                        block_material, mat, history, part_block, viscous_blocks, fibre_frame,
                        row_forces, scratch, part_energy, failure_ratio):
    """As ``_fast_quad.quad_internal_forces`` for hexahedra (cells in binary node order)."""
    n_e = alive.shape[0]
    nt = scratch.shape[0]
    n_parts = part_energy.shape[0]
    u_flat = u.reshape(u.size)
    saved = active_threads()
    use_threads(min(nt, saved))
    claimed = np.empty((nt + 1) // 2, np.int64)
    for r in range(claimed.size):  # not np.zeros: a parallel kernel makes that a parallel region
        claimed[r] = 0
    for t in prange(nt):
        s = scratch[t]
        loaded = np.int64(-1)
        for taken in range(n_parts):
            p = claim_part(claimed, t, nt, n_parts, taken)
            if p < 0:
                break
            e0 = 0.0
            e1 = 0.0
            e2 = 0.0
            for blk in range(part_block[p], part_block[p + 1]):
                loaded = _gather(blk, n_e, u_flat, alive, cells, material, block_material, mat, s,
                                 loaded)
                g = geom[blk * N_GEOMETRY * B:(blk + 1) * N_GEOMETRY * B]
                h = history[blk * N_HISTORY * B:(blk + 1) * N_HISTORY * B]
                if fibre_frame is None:  # pruned by Numba: a mesh without fibre materials
                    r0, r1, r2 = _lanes(s, g, h, None, rate_factor, viscous_blocks[blk] != 0)
                else:
                    r0, r1, r2 = _lanes(s, g, h, fibre_frame[blk * N_FRAME * B:(blk + 1) * N_FRAME * B],
                                        rate_factor, viscous_blocks[blk] != 0)
                _scatter(blk, n_e, cells_target, s, row_forces, failure_ratio)
                e0 += r0
                e1 += r1
                e2 += r2
            part_energy[p, 0] = e0
            part_energy[p, 1] = e1
            part_energy[p, 2] = e2
    use_threads(saved)
