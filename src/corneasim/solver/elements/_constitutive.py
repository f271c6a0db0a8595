"""Pointwise laws the element kernels inline: stress of the strain-energy family,
cube root, largest eigenvalue of a symmetric 3x3 tensor, failure value.

Symmetric tensors travel as six scalars in the order (11, 22, 33, 12, 23, 31); for the
axisymmetric quad the axes are (r, z, theta) and the 23 and 31 entries are zero.

The strain-energy family (``materials/_kernel_form.py``) is

.. math::

    W = C_{10}(\\bar I_1 - 3) + C_{01}(\\bar I_2 - 3) + C_{20}(\\bar I_1 - 3)^2
        + C_{30}(\\bar I_1 - 3)^3 + \\tfrac{K}{2}(J - 1)^2, \\qquad K = 2 / D_1 ,

whose second Piola-Kirchhoff stress splits into (Holzapfel 2000, sec. 6.4,
ISBN 978-0-471-82319-3)

.. math::

    S_{vol} = J p C^{-1}, \\quad p = K (J - 1), \\qquad
    S_{iso} = J^{-2/3}\\left[\\bar S - \\tfrac13 (\\bar S : C) C^{-1}\\right], \\quad
    \\bar S = 2 (W_1 + \\bar I_1 W_2) I - 2 W_2 \\bar C .
"""

from __future__ import annotations

import numpy as np
from numba import njit

SQRT_EPS = 1e-300


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
def inverse_cube_root(J):
    """J^{-1/3} for the vector loops of the fast kernels: Newton's iteration
    y <- y (4 - J y^3) / 3 from the Pade start (J + 2) / (2 J + 1), five steps: round-off
    (relative error < 4e-16) for 0.104 < J < 7.5, 5e-11 at J = 10. No libm ``pow``, which
    would stop the vectorisation (inlined)."""
    y = (J + 2.0) / (2.0 * J + 1.0)
    for _ in range(5):
        y = y * (4.0 - J * y * y * y) * (1.0 / 3.0)
    return y


@njit(cache=True, fastmath=True, error_model="numpy")
def max_eigenvalue(a11, a22, a33, a12, a23, a31):
    """Largest eigenvalue of a symmetric 3x3 tensor, branch-free and without libm.

    With the deviator s, J2 = s:s/2, J3 = det s and x = (3 sqrt(3)/2) J3 / J2^{3/2},
    the largest eigenvalue is m + 2 sqrt(J2/3) c where c = cos(arccos(x)/3) is the
    largest root of 4c^3 - 3c = x. Newton's method starts above that root at
    c0 = 1/2 + sqrt((1 + x)/6) (exact to leading order at the double root x = -1)
    and descends monotonically.
    """
    m = (a11 + a22 + a33) / 3.0
    s11 = a11 - m
    s22 = a22 - m
    s33 = a33 - m
    j2 = 0.5 * (s11 * s11 + s22 * s22 + s33 * s33) + a12 * a12 + a23 * a23 + a31 * a31
    j3 = (s11 * (s22 * s33 - a23 * a23) - a12 * (a12 * s33 - a23 * a31)
          + a31 * (a12 * a23 - s22 * a31))
    root = np.sqrt(j2 / 3.0)
    x = 0.5 * j3 / (root * root * root + SQRT_EPS)
    x = min(1.0, max(-1.0, x))
    c = 0.5 + np.sqrt((1.0 + x) / 6.0)
    for _ in range(6):
        c = c - (4.0 * c * c * c - 3.0 * c - x) / max(12.0 * c * c - 3.0, 1e-10)
    return m + 2.0 * root * c


@njit(cache=True, fastmath=True, error_model="numpy")
def inverse_sym(C11, C22, C33, C12, C23, C31, det):
    """Inverse of a symmetric 3x3 tensor with determinant ``det`` (cofactor / det)."""
    inv = 1.0 / det
    return ((C22 * C33 - C23 * C23) * inv, (C11 * C33 - C31 * C31) * inv,
            (C11 * C22 - C12 * C12) * inv, (C23 * C31 - C12 * C33) * inv,
            (C12 * C31 - C11 * C23) * inv, (C12 * C23 - C22 * C31) * inv)


@njit(cache=True, fastmath=True, error_model="numpy")
def isochoric_stress(C11, C22, C33, C12, C23, C31, Jm23, c10, c01, c20, c30):
    """Isochoric second Piola-Kirchhoff stress S_iso and I1bar for C, J^{-2/3}.

    Returns the six components of S_iso (MPa) followed by the factor
    ``-(Sbar:C)/3 * J^{-2/3}`` that multiplies C^{-1} (already included).
    """
    I1 = C11 + C22 + C33
    trC2 = C11 * C11 + C22 * C22 + C33 * C33 + 2.0 * (C12 * C12 + C23 * C23 + C31 * C31)
    I1b = Jm23 * I1
    e = I1b - 3.0
    W1 = c10 + 2.0 * c20 * e + 3.0 * c30 * e * e
    a = 2.0 * (W1 + I1b * c01)
    bW = 2.0 * c01 * Jm23
    SbC = a * I1 - bW * trC2
    det = (C11 * (C22 * C33 - C23 * C23) - C12 * (C12 * C33 - C23 * C31)
           + C31 * (C12 * C23 - C22 * C31))
    i11, i22, i33, i12, i23, i31 = inverse_sym(C11, C22, C33, C12, C23, C31, det)
    t = SbC / 3.0
    return (Jm23 * (a - bW * C11 - t * i11), Jm23 * (a - bW * C22 - t * i22),
            Jm23 * (a - bW * C33 - t * i33), Jm23 * (-bW * C12 - t * i12),
            Jm23 * (-bW * C23 - t * i23), Jm23 * (-bW * C31 - t * i31))


@njit(cache=True, fastmath=True, error_model="numpy")
def volumetric_stress(C11, C22, C33, C12, C23, C31, J, bulk):
    """Volumetric second Piola-Kirchhoff stress S_vol = J K (J - 1) C^{-1}, MPa."""
    i11, i22, i33, i12, i23, i31 = inverse_sym(C11, C22, C33, C12, C23, C31, J * J)
    f = J * bulk * (J - 1.0)
    return f * i11, f * i22, f * i33, f * i12, f * i23, f * i31


@njit(cache=True, fastmath=True, error_model="numpy")
def strain_energy_density(C11, C22, C33, C12, C23, C31, J, c10, c01, c20, c30, bulk):
    """W per unit reference volume (MPa = mJ/mm^3) of the family."""
    Jm23 = J ** (-2.0 / 3.0)
    I1 = C11 + C22 + C33
    trC2 = C11 * C11 + C22 * C22 + C33 * C33 + 2.0 * (C12 * C12 + C23 * C23 + C31 * C31)
    e1 = Jm23 * I1 - 3.0
    e2 = Jm23 * Jm23 * 0.5 * (I1 * I1 - trC2) - 3.0
    return (c10 * e1 + c01 * e2 + c20 * e1 * e1 + c30 * e1 * e1 * e1
            + 0.5 * bulk * (J - 1.0) ** 2)


@njit(cache=True, fastmath=True, error_model="numpy")
def tangent_shear_modulus(I1b, c10, c01, c20, c30):
    """Estimate of the current shear stiffness, MPa, for the stable time step.

    ``2|W1| + 2|C01| Ibar1/3 + (8/3)|W11| (Ibar1^2 - 9)`` with W1 = dW/dIbar1 and W11 its
    derivative: mu_0 = 2 (C10 + C01) in the reference state; the last term bounds the
    stiffening 4 W11 |dev bbar|^2 of the Yeoh terms (|dev bbar|^2 <= (2/3)(Ibar1^2 - 9)).
    """
    e = I1b - 3.0
    W1 = c10 + 2.0 * c20 * e + 3.0 * c30 * e * e
    W11 = 2.0 * c20 + 6.0 * c30 * e
    return (2.0 * abs(W1) + 2.0 * abs(c01) * I1b / 3.0
            + 8.0 / 3.0 * abs(W11) * max(I1b * I1b - 9.0, 0.0))
