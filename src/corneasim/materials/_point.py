"""The law at one material point: energy and stress of a 3 x 3 deformation gradient.

Every evaluator of a material at a given F, the reference element kernels and the solver's
energy checks as well as the Cauchy stress, the energy and the Prony update of the
material curves (``_hyperelastic``, ``_viscoelastic``), computes the kinematics here and the
stress from the scalar law of ``_law`` and ``_fibre_law``, the functions the fast kernels
evaluate in their vector passes. With C = F^T F, J = det F and the instantaneous isochoric
stress S0bar of the invariant family and the fibre families,

.. math::

    S = S_{vol} + \\bar S_0, \\qquad S_{vol} = J K (J - 1)\\, C^{-1}, \\qquad
    \\sigma = \\frac{1}{J} F S F^T

(Holzapfel 2000, *Nonlinear Solid Mechanics*, eqs. 6.89-6.91 and 3.67). The fibre families
lie in the plane of an element's fibre frame (m, n) at +-angle from m; a material point
without an element uses the frame (e1, e2) (:data:`POINT_FRAME`). Everything is written
element by element: ``np.linalg.det`` and the matrix product of 3 x 3 arrays compile
LAPACK's LU and BLAS's ``dgemm``, seconds of compilation at a first run.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.materials._fibre_law import fibre_energy, fibre_pk2, fibre_strain
from corneasim.materials._kernel_form import (
    P_C01, P_C10, P_C20, P_C30, P_D1, P_FIBRE_ANGLE, P_FIBRE_K1, P_FIBRE_K2, P_FIBRE_KAPPA)
from corneasim.materials._law import (
    isochoric_energy, isochoric_pk2, volumetric_energy, volumetric_factor)

VOIGT = np.array([[0, 3, 5], [3, 1, 4], [5, 4, 2]])
"""Index of S_ij in a symmetric tensor's six entries (11, 22, 33, 12, 23, 31)."""

VOIGT_PAIRS = np.array([[0, 0], [1, 1], [2, 2], [0, 1], [1, 2], [2, 0]])
"""(i, j) of each of the six entries: the inverse of :data:`VOIGT`."""

POINT_FRAME = np.array([1.0, 0.0, 0.0, 0.0, 1.0, 0.0])
"""The fibre frame (m, n) = (e1, e2) of a material point evaluated without an element."""


@njit(cache=True)
def kinematics(F):
    """(C11, C22, C33, C12, C23, C31) of C = F^T F and J = det F (cofactor expansion)."""
    C11 = F[0, 0] ** 2 + F[1, 0] ** 2 + F[2, 0] ** 2
    C22 = F[0, 1] ** 2 + F[1, 1] ** 2 + F[2, 1] ** 2
    C33 = F[0, 2] ** 2 + F[1, 2] ** 2 + F[2, 2] ** 2
    C12 = F[0, 0] * F[0, 1] + F[1, 0] * F[1, 1] + F[2, 0] * F[2, 1]
    C23 = F[0, 1] * F[0, 2] + F[1, 1] * F[1, 2] + F[2, 1] * F[2, 2]
    C31 = F[0, 2] * F[0, 0] + F[1, 2] * F[1, 0] + F[2, 2] * F[2, 0]
    J = (F[0, 0] * (F[1, 1] * F[2, 2] - F[1, 2] * F[2, 1])
         - F[0, 1] * (F[1, 0] * F[2, 2] - F[1, 2] * F[2, 0])
         + F[0, 2] * (F[1, 0] * F[2, 1] - F[1, 1] * F[2, 0]))
    return C11, C22, C33, C12, C23, C31, J


@njit(cache=True, fastmath=True, error_model="numpy")
def inverse_sym(C11, C22, C33, C12, C23, C31, det):
    """Inverse of a symmetric 3x3 tensor with determinant ``det`` (cofactor / det)."""
    inv = 1.0 / det
    return ((C22 * C33 - C23 * C23) * inv, (C11 * C33 - C31 * C31) * inv,
            (C11 * C22 - C12 * C12) * inv, (C23 * C31 - C12 * C33) * inv,
            (C12 * C31 - C11 * C23) * inv, (C12 * C23 - C22 * C31) * inv)


@njit(cache=True)
def _family_direction(row, frame, sign):
    """Reference direction a = cos(angle) m + sign sin(angle) n of one fibre family."""
    c, sn = np.cos(row[P_FIBRE_ANGLE]), np.sin(row[P_FIBRE_ANGLE])
    return (c * frame[0] + sign * sn * frame[3], c * frame[1] + sign * sn * frame[4],
            c * frame[2] + sign * sn * frame[5])


@njit(cache=True)
def elastic_pk2(F, row, frame):
    """J, S_vol and S0bar (six entries each, MPa) at F for a kernel record ``row``.

    ``frame`` (6,) is the fibre frame (m, n); it is read only when the material has fibres
    (k1 > 0), which without it is a ValueError. The instantaneous stress is S_vol + S0bar;
    the Prony series relaxes S0bar (``_kernel_form``).
    """
    C11, C22, C33, C12, C23, C31, J = kinematics(F)
    Jm23 = np.cbrt(J) ** -2
    i11, i22, i33, i12, i23, i31 = inverse_sym(C11, C22, C33, C12, C23, C31, J * J)
    iso = isochoric_pk2(C11, C22, C33, C12, C23, C31, i11, i22, i33, i12, i23, i31, Jm23,
                        row[P_C10], row[P_C01], row[P_C20], row[P_C30])
    k1 = row[P_FIBRE_K1]
    if k1 > 0.0:
        if frame is None:
            raise ValueError("elastic_pk2: a fibre material needs the element's fibre frame")
        for sign in (1.0, -1.0):
            a1, a2, a3 = _family_direction(row, frame, sign)
            fibre = fibre_pk2(C11, C22, C33, C12, C23, C31, i11, i22, i33, i12, i23, i31, Jm23,
                              a1, a2, a3, k1, row[P_FIBRE_K2], row[P_FIBRE_KAPPA])
            iso = (iso[0] + fibre[0], iso[1] + fibre[1], iso[2] + fibre[2], iso[3] + fibre[3],
                   iso[4] + fibre[4], iso[5] + fibre[5])
    pv = volumetric_factor(J, 2.0 / row[P_D1])
    return J, (pv * i11, pv * i22, pv * i33, pv * i12, pv * i23, pv * i31), iso


@njit(cache=True)
def _energy_parts(F, row, frame):
    """W_iso + W_fibres (MPa) and J at F."""
    C11, C22, C33, C12, C23, C31, J = kinematics(F)
    Jm23 = J ** (-2.0 / 3.0)
    I1 = C11 + C22 + C33
    trC2 = C11 * C11 + C22 * C22 + C33 * C33 + 2.0 * (C12 * C12 + C23 * C23 + C31 * C31)
    I1b = Jm23 * I1
    I2b = Jm23 * Jm23 * 0.5 * (I1 * I1 - trC2)
    W = isochoric_energy(I1b, I2b, row[P_C10], row[P_C01], row[P_C20], row[P_C30])
    if row[P_FIBRE_K1] > 0.0:
        if frame is None:
            raise ValueError("material energy: a fibre material needs the element's fibre frame")
        for sign in (1.0, -1.0):
            a1, a2, a3 = _family_direction(row, frame, sign)
            I4 = (a1 * (C11 * a1 + C12 * a2 + C31 * a3) + a2 * (C12 * a1 + C22 * a2 + C23 * a3)
                  + a3 * (C31 * a1 + C23 * a2 + C33 * a3))
            W += fibre_energy(fibre_strain(I1b, Jm23 * I4, row[P_FIBRE_KAPPA]),
                              row[P_FIBRE_K1], row[P_FIBRE_K2])
    return W, J


@njit(cache=True)
def isochoric_strain_energy(F, row, frame):
    """W_iso(I1bar, I2bar) plus the fibre families' energy, MPa (= mJ/mm^3), at F for a
    kernel record ``row`` (``frame`` as in :func:`elastic_pk2`)."""
    return _energy_parts(F, row, frame)[0]


@njit(cache=True)
def elastic_energy(F, row, frame):
    """Strain energy W = W_iso + W_fibres + K (J - 1)^2 / 2, MPa (= mJ/mm^3), at F."""
    W, J = _energy_parts(F, row, frame)
    return W + volumetric_energy(J, 2.0 / row[P_D1])


@njit(cache=True)
def cauchy_from_pk2(F, S, J, sigma):
    """sigma = F S F^T / J into sigma (6,) in the order (11, 22, 33, 12, 23, 31)."""
    for c in range(6):
        i, j = VOIGT_PAIRS[c, 0], VOIGT_PAIRS[c, 1]
        total = 0.0
        for k in range(3):
            total += F[i, k] * (S[VOIGT[k, 0]] * F[j, 0] + S[VOIGT[k, 1]] * F[j, 1]
                                + S[VOIGT[k, 2]] * F[j, 2])
        sigma[c] = total / J


@njit(cache=True)
def symmetric_matrix(v):
    """The 3 x 3 array of a symmetric tensor's six entries (11, 22, 33, 12, 23, 31)."""
    out = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            out[i, j] = v[VOIGT[i, j]]
    return out
