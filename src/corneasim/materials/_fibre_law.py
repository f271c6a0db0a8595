"""The fibre term of the Holzapfel-Gasser-Ogden law with dispersion, pointwise.

A family of collagen fibres with mean reference direction :math:`a_0` (unit vector) and
dispersion :math:`\\kappa \\in [0, 1/3]` has the generalised structure tensor
:math:`H = \\kappa I + (1 - 3\\kappa)\\, a_0 \\otimes a_0` and the strain-like invariant
(Gasser, Ogden & Holzapfel 2006, doi:10.1098/rsif.2005.0073, eqs. 2.5, 2.11; used for the
cornea by Pandolfi & Holzapfel 2008, doi:10.1115/1.2982251)

.. math::

    E = H : \\bar C - 1 = \\kappa (\\bar I_1 - 3) + (1 - 3\\kappa)(\\bar I_4 - 1), \\qquad
    \\bar I_4 = a_0 \\cdot \\bar C a_0,

with the energy of the family

.. math::

    \\Psi(E) = \\frac{k_1}{2 k_2}\\left[e^{k_2 E^2} - 1\\right] \\text{ for } E > 0, \\qquad
    \\Psi = 0 \\text{ for } E \\le 0

(:math:`k_1` in MPa, :math:`k_2` dimensionless; :math:`k_2 = 0` is the limit
:math:`k_1 E^2 / 2`). **Compression switch**: the family contributes only while
:math:`E > 0`, the rule of FEBio's implementation of this law. It makes the energy
:math:`C^1` (:math:`\\Psi'(0) = 0`), so the stress is continuous across the switch, which an
explicit integration and a Newton iteration both need; a switch on :math:`\\bar I_4 > 1`
alone would make the stress jump by :math:`2\\Psi'(\\kappa(\\bar I_1 - 3))` when
:math:`\\kappa > 0`. With :math:`\\kappa = 0` the two rules coincide; with
:math:`\\kappa > 0` a family compressed along :math:`a_0` still resists once the isotropic
share of its dispersion is stretched enough (:math:`E > 0`).

Its isochoric second Piola-Kirchhoff stress, with :math:`\\partial E/\\partial\\bar C = H`
and the isochoric projection of ``_law`` (Holzapfel 2000, eq. 6.91):

.. math::

    S_f = J^{-2/3}\\left[\\bar S_f - \\tfrac13 (\\bar S_f : C)\\, C^{-1}\\right], \\quad
    \\bar S_f = 2 \\Psi'(E)\\, H, \\quad
    \\bar S_f : C = 2 \\Psi'(E) \\left[\\kappa I_1 + (1 - 3\\kappa) I_4\\right],

and its Cauchy stress :math:`\\sigma_f = \\frac{2}{J}\\Psi'(E)\\, \\mathrm{dev}\\,\\bar h`,
:math:`\\bar h = \\bar F H \\bar F^T = \\kappa \\bar B + (1 - 3\\kappa)\\,\\bar a \\otimes \\bar a`,
:math:`\\bar a = \\bar F a_0`, :math:`\\bar F = J^{-1/3} F`. The scalar functions are
``@njit(inline="always")`` like those of ``_law``; symmetric tensors are six scalars in the
order (11, 22, 33, 12, 23, 31).
"""

from __future__ import annotations

import numpy as np
from numba import njit

@njit(cache=True, inline="always")
def fibre_strain(I1b, I4b, kappa):
    """E = kappa (I1bar - 3) + (1 - 3 kappa)(I4bar - 1), dimensionless."""
    return kappa * (I1b - 3.0) + (1.0 - 3.0 * kappa) * (I4b - 1.0)


_EXP_ARGUMENT_LIMIT = 709.0
"""Largest argument of :func:`exp_nonnegative` (exp(709) = 8.2e307, near the largest float64)."""


@njit(cache=True, inline="always")
def exp_nonnegative(x):
    """e^x for 0 <= x <= 709 in branch-free arithmetic that vectorises (no libm call).

    Cody-Waite reduction x = n ln 2 + r with n = floor(x / ln 2 + 1/2), |r| <= ln 2 / 2
    (ln 2 split into a short head and a tail, Cephes' constants, so that n ln 2 is exact),
    the Taylor polynomial of e^r to degree 13 (remainder < 5e-18 relative) and
    2^n = prod_k (2^(2^k))^(bit k of n) over the ten bits of n <= 1023, each bit from
    ``floor``. Relative error a few 1e-16 (tested against ``np.exp``); above 709 the result
    is inf, the overflow of e^x (a select, not a branch). Numba calls libm's ``exp`` for
    ``np.exp``, which keeps a loop scalar unless Intel's SVML is installed; this function
    keeps the fibre term of the fast kernels in SIMD lanes (``docs/performance.md``,
    "Kernel design").
    """
    overflow = x > _EXP_ARGUMENT_LIMIT
    x = min(x, _EXP_ARGUMENT_LIMIT)
    n = np.floor(x * 1.4426950408889634 + 0.5)
    r = (x - n * 0.693145751953125) - n * 1.4286068203094173e-06
    p = 1.0 / 6227020800.0
    p = p * r + 1.0 / 479001600.0
    p = p * r + 1.0 / 39916800.0
    p = p * r + 1.0 / 3628800.0
    p = p * r + 1.0 / 362880.0
    p = p * r + 1.0 / 40320.0
    p = p * r + 1.0 / 5040.0
    p = p * r + 1.0 / 720.0
    p = p * r + 1.0 / 120.0
    p = p * r + 1.0 / 24.0
    p = p * r + 1.0 / 6.0
    p = p * r + 0.5
    p = p * r + 1.0
    p = p * r + 1.0
    q = n
    power = 2.0
    for _ in range(10):  # unrolled by LLVM: ten compile-time iterations
        half = np.floor(0.5 * q)
        p *= 1.0 + (q - 2.0 * half) * (power - 1.0)
        q = half
        power *= power
    return np.inf if overflow else p


@njit(cache=True, inline="always")
def fibre_energy(E, k1, k2):
    """Psi(E) = k1 / (2 k2) (exp(k2 E^2) - 1) for E > 0, else 0; MPa (k1 in MPa)."""
    if E <= 0.0:
        return 0.0
    if k2 > 0.0:
        return 0.5 * k1 / k2 * np.expm1(k2 * E * E)
    return 0.5 * k1 * E * E


@njit(cache=True, inline="always")
def fibre_derivatives(E, k1, k2):
    """Psi'(E) = k1 E exp(k2 E^2) and Psi''(E) = k1 (1 + 2 k2 E^2) exp(k2 E^2), MPa; 0 for E <= 0.

    Branch-free (E+ = max(E, 0) and a select), so that it vectorises in the kernels.
    """
    Ep = max(E, 0.0)
    x = exp_nonnegative(k2 * Ep * Ep)
    return k1 * Ep * x, (k1 * (1.0 + 2.0 * k2 * Ep * Ep) * x if E > 0.0 else 0.0)


@njit(cache=True, inline="always")
def fibre_tangent_bound(E, k1, k2):
    """k1 (1 + 2 k2 E+^2) exp(k2 E+^2), MPa, E+ = max(E, 0): Psi'' on the stretched side.

    The stable time step uses it for every E: at E <= 0 it is the stiffness k1 the family
    takes as soon as it is stretched (the switch makes Psi'' jump from 0 to k1 at E = 0),
    so that the step does not depend on which side of the switch a family is.
    """
    Ep = max(E, 0.0)
    return k1 * (1.0 + 2.0 * k2 * Ep * Ep) * exp_nonnegative(k2 * Ep * Ep)


@njit(cache=True, inline="always")
def fibre_pk2(C11, C22, C33, C12, C23, C31, i11, i22, i33, i12, i23, i31, Jm23,
              a1, a2, a3, k1, k2, kappa):
    """Isochoric second Piola-Kirchhoff stress S_f of one family (six components, MPa).

    C and C^-1 = i as in ``_law.isochoric_pk2``, Jm23 = J^{-2/3}, (a1, a2, a3) the unit
    reference direction of the family.
    """
    Ca1 = C11 * a1 + C12 * a2 + C31 * a3
    Ca2 = C12 * a1 + C22 * a2 + C23 * a3
    Ca3 = C31 * a1 + C23 * a2 + C33 * a3
    I1 = C11 + C22 + C33
    I4 = a1 * Ca1 + a2 * Ca2 + a3 * Ca3
    E = fibre_strain(Jm23 * I1, Jm23 * I4, kappa)
    d, _ = fibre_derivatives(E, k1, k2)
    g = 2.0 * d
    b = (1.0 - 3.0 * kappa) * g
    t = g * (kappa * I1 + (1.0 - 3.0 * kappa) * I4) * (1.0 / 3.0)
    return (Jm23 * (g * kappa + b * a1 * a1 - t * i11), Jm23 * (g * kappa + b * a2 * a2 - t * i22),
            Jm23 * (g * kappa + b * a3 * a3 - t * i33), Jm23 * (b * a1 * a2 - t * i12),
            Jm23 * (b * a2 * a3 - t * i23), Jm23 * (b * a3 * a1 - t * i31))
