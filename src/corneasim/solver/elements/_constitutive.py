"""Kinematic helpers of the element kernels (C = F^T F, its inverse, cube roots without
libm) and the two material quantities the solver needs beyond the stress: the strain-energy
density and the tangent shear modulus of the stable time step, both through the law of
``materials.kernel``.

Symmetric tensors travel as six scalars in the order (11, 22, 33, 12, 23, 31); for the
axisymmetric quad the axes are (r, z, theta) and the 23 and 31 entries are zero.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.materials.kernel import (
    P_FIBRE_ANGLE, P_FIBRE_K1, P_FIBRE_K2, P_FIBRE_KAPPA, fibre_energy, fibre_strain,
    isochoric_derivatives, isochoric_energy, volumetric_energy)


@njit(cache=True, fastmath=True, error_model="numpy")
def cube_root(x):
    """Cube root of x > 0 without libm: Pade start, then four Halley steps.

    Halley's iteration ``y <- y (y^3 + 2x) / (2 y^3 + x)`` converges cubically; from
    the start (2x + 1)/(x + 2) it reaches round-off for 0.05 <= x <= 20 (tested).
    """
    y = (2.0 * x + 1.0) / (x + 2.0)
    for _ in range(4):
        y3 = y * y * y
        y = y * (y3 + 2.0 * x) / (2.0 * y3 + x)
    return y


@njit(cache=True, inline="always")
def right_cauchy_green(F11, F12, F13, F21, F22, F23, F31, F32, F33):
    """C = F^T F as (C11, C22, C33, C12, C23, C31) (inlined into the vector loops)."""
    return (F11 * F11 + F21 * F21 + F31 * F31, F12 * F12 + F22 * F22 + F32 * F32,
            F13 * F13 + F23 * F23 + F33 * F33, F11 * F12 + F21 * F22 + F31 * F32,
            F12 * F13 + F22 * F23 + F32 * F33, F13 * F11 + F23 * F21 + F33 * F31)


@njit(cache=True, inline="always")
def cofactor(F11, F12, F13, F21, F22, F23, F31, F32, F33):
    """cof F = J F^{-T}, row by row (inlined into the vector loops)."""
    return (F22 * F33 - F23 * F32, F23 * F31 - F21 * F33, F21 * F32 - F22 * F31,
            F13 * F32 - F12 * F33, F11 * F33 - F13 * F31, F12 * F31 - F11 * F32,
            F12 * F23 - F13 * F22, F13 * F21 - F11 * F23, F11 * F22 - F12 * F21)


@njit(cache=True, inline="always")
def inverse_cube_root(J):
    """J^{-1/3} for the vector loops of the fast kernels: Newton's iteration
    y <- y (4 - J y^3) / 3 from the Pade start (J + 2) / (2 J + 1), five steps: round-off
    (relative error < 1e-15, measured 6e-16) for 0.104 < J < 7.5, 5e-11 at J = 10. No libm ``pow``, which
    would stop the vectorisation (inlined)."""
    y = (J + 2.0) / (2.0 * J + 1.0)
    for _ in range(5):
        y = y * (4.0 - J * y * y * y) * (1.0 / 3.0)
    return y


@njit(cache=True, fastmath=True, error_model="numpy")
def inverse_sym(C11, C22, C33, C12, C23, C31, det):
    """Inverse of a symmetric 3x3 tensor with determinant ``det`` (cofactor / det)."""
    inv = 1.0 / det
    return ((C22 * C33 - C23 * C23) * inv, (C11 * C33 - C31 * C31) * inv,
            (C11 * C22 - C12 * C12) * inv, (C23 * C31 - C12 * C33) * inv,
            (C12 * C31 - C11 * C23) * inv, (C12 * C23 - C22 * C31) * inv)


@njit(cache=True, fastmath=True, error_model="numpy")
def strain_energy_density(C11, C22, C33, C12, C23, C31, J, c10, c01, c20, c30, bulk):
    """W per unit reference volume (MPa = mJ/mm^3) of the family (``materials.kernel``)."""
    Jm23 = J ** (-2.0 / 3.0)
    I1 = C11 + C22 + C33
    trC2 = C11 * C11 + C22 * C22 + C33 * C33 + 2.0 * (C12 * C12 + C23 * C23 + C31 * C31)
    I1b = Jm23 * I1
    I2b = Jm23 * Jm23 * 0.5 * (I1 * I1 - trC2)
    return isochoric_energy(I1b, I2b, c10, c01, c20, c30) + volumetric_energy(J, bulk)


@njit(cache=True)
def fibre_energy_density(C, J, row, frame):
    """Energy of the two fibre families (MPa) at C (3, 3) for a material row and an element's
    fibre frame (6,) (``materials._fibre_law``); 0 for a material without fibres."""
    if row[P_FIBRE_K1] <= 0.0:
        return 0.0
    Jm23 = J ** (-2.0 / 3.0)
    I1b = Jm23 * (C[0, 0] + C[1, 1] + C[2, 2])
    c, sn = np.cos(row[P_FIBRE_ANGLE]), np.sin(row[P_FIBRE_ANGLE])
    W = 0.0
    for sign in (1.0, -1.0):
        a = c * frame[:3] + sign * sn * frame[3:]
        W += fibre_energy(fibre_strain(I1b, Jm23 * (a @ (C @ a)), row[P_FIBRE_KAPPA]),
                          row[P_FIBRE_K1], row[P_FIBRE_K2])
    return W


@njit(cache=True, fastmath=True, error_model="numpy")
def tangent_shear_modulus(I1b, c10, c01, c20, c30):
    """Estimate of the current shear stiffness, MPa, for the stable time step.

    ``2|W1| + 2|C01| Ibar1/3 + (8/3)|W11| (Ibar1^2 - 9)`` with W1 = dW/dIbar1 and W11 its
    derivative: mu_0 = 2 (C10 + C01) in the reference state; the last term bounds the
    stiffening 4 W11 |dev bbar|^2 of the Yeoh terms (|dev bbar|^2 <= (2/3)(Ibar1^2 - 9)).
    """
    W1, W11 = isochoric_derivatives(I1b, c10, c20, c30)
    return (2.0 * abs(W1) + 2.0 * abs(c01) * I1b / 3.0
            + 8.0 / 3.0 * abs(W11) * max(I1b * I1b - 9.0, 0.0))
