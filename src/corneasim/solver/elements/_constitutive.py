"""Kinematic helpers of the fast element kernels (C = F^T F and cof F over scalars, cube
roots without libm) and the tangent shear modulus of the stable time step, through the law
of ``materials.kernel`` (whose ``kinematics`` and ``inverse_sym`` serve a 3x3 F).

Symmetric tensors travel as six scalars in the order (11, 22, 33, 12, 23, 31); for the
axisymmetric quad the axes are (r, z, theta) and the 23 and 31 entries are zero.
"""

from __future__ import annotations

from numba import njit

from corneasim.materials.kernel import isochoric_derivatives


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
def tangent_shear_modulus(I1b, c10, c01, c20, c30):
    """Estimate of the current shear stiffness, MPa, for the stable time step.

    ``2|W1| + 2|C01| Ibar1/3 + (8/3)|W11| (Ibar1^2 - 9)`` with W1 = dW/dIbar1 and W11 its
    derivative: mu_0 = 2 (C10 + C01) in the reference state; the last term bounds the
    stiffening 4 W11 |dev bbar|^2 of the Yeoh terms (|dev bbar|^2 <= (2/3)(Ibar1^2 - 9)).
    """
    W1, W11 = isochoric_derivatives(I1b, c10, c20, c30)
    return (2.0 * abs(W1) + 2.0 * abs(c01) * I1b / 3.0
            + 8.0 / 3.0 * abs(W11) * max(I1b * I1b - 9.0, 0.0))
