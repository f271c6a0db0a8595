"""The pointwise material law: the one definition every evaluator of the material calls.

The element kernels (reference and fast), the Cauchy-stress functions of
``_hyperelastic``, the homogeneous test curves of ``_homogeneous`` (and with them the
fitting and the stability check) and the Prony update of ``_viscoelastic`` all evaluate
the functions below, so a change of the law is made here once. Every function is
``@njit(inline="always")`` over scalars: Numba copies its body into the calling loop,
where the caller's compiler flags apply, so the fast kernels keep their vector code.

The strain energy is that of the invariant family of ``_kernel_form`` (Holzapfel 2000,
*Nonlinear Solid Mechanics*, sec. 6.4-6.5, ISBN 978-0-471-82319-3):

.. math::

    W = \\underbrace{C_{10}(\\bar I_1 - 3) + C_{01}(\\bar I_2 - 3) + C_{20}(\\bar I_1 - 3)^2
        + C_{30}(\\bar I_1 - 3)^3}_{W_{iso}(\\bar I_1, \\bar I_2)}
        + \\underbrace{\\tfrac{K}{2}(J - 1)^2}_{W_{vol}(J)}, \\qquad K = 2 / D_1,

with the second Piola-Kirchhoff stress :math:`S = S_{iso} + S_{vol}`,

.. math::

    S_{iso} = J^{-2/3}\\left[\\bar S - \\tfrac13 (\\bar S : C)\\, C^{-1}\\right], \\quad
    \\bar S = 2 (W_1 + \\bar I_1 W_2)\\, I - 2 W_2 J^{-2/3} C, \\qquad
    S_{vol} = J K (J - 1)\\, C^{-1},

:math:`W_1 = \\partial W/\\partial\\bar I_1`, :math:`W_2 = \\partial W/\\partial\\bar I_2`
(:math:`\\bar S : C` is written with :math:`C` itself, the :math:`J^{-2/3}` factors
collected in front). The Prony series relaxes the isochoric part (Simo & Hughes 1998,
*Computational Inelasticity*, sec. 10.3; Taylor et al. 2009, doi:10.1002/cnm.1146):

.. math::

    h_i^{n+1} = a_i h_i^n + b_i (\\bar S_0^{n+1} - \\bar S_0^n), \\quad
    a_i = e^{-\\Delta t/\\tau_i}, \\; b_i = g_i \\frac{1 - a_i}{\\Delta t/\\tau_i},

and the failure measure is the von Mises equivalent of the Cauchy stress (needle paper
eq. 15 with the shear terms). Symmetric tensors travel as six scalars in the order
(11, 22, 33, 12, 23, 31); a plane or axisymmetric caller passes zeros for 23 and 31.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, inline="always")
def isochoric_derivatives(I1b, c10, c20, c30):
    """W_1 = dW/dI1bar (MPa) and W_11 = d^2W/dI1bar^2 (MPa); W_2 = C01 is constant."""
    e = I1b - 3.0
    return c10 + 2.0 * c20 * e + 3.0 * c30 * e * e, 2.0 * c20 + 6.0 * c30 * e


@njit(cache=True, inline="always")
def isochoric_energy(I1b, I2b, c10, c01, c20, c30):
    """W_iso(I1bar, I2bar), MPa (= mJ/mm^3)."""
    e1 = I1b - 3.0
    return c10 * e1 + c01 * (I2b - 3.0) + c20 * e1 * e1 + c30 * e1 * e1 * e1


@njit(cache=True, inline="always")
def volumetric_energy(J, bulk):
    """W_vol = K (J - 1)^2 / 2, MPa (K in MPa)."""
    return 0.5 * bulk * (J - 1.0) ** 2


@njit(cache=True, inline="always")
def volumetric_factor(J, bulk):
    """J K (J - 1), MPa: S_vol = this times C^-1 and the pressure is this / J (tension > 0)."""
    return J * bulk * (J - 1.0)


@njit(cache=True, inline="always")
def isochoric_pk2(C11, C22, C33, C12, C23, C31, i11, i22, i33, i12, i23, i31, Jm23,
                  c10, c01, c20, c30):
    """Isochoric second Piola-Kirchhoff stress S_iso (six components, MPa).

    C (six components) and its inverse C^-1 = i (six components) come from the caller,
    which computes the inverse in the way its kinematics allow; Jm23 = J^{-2/3}.
    """
    I1 = C11 + C22 + C33
    trC2 = C11 * C11 + C22 * C22 + C33 * C33 + 2.0 * (C12 * C12 + C23 * C23 + C31 * C31)
    I1b = Jm23 * I1
    W1, _ = isochoric_derivatives(I1b, c10, c20, c30)
    A = 2.0 * (W1 + I1b * c01)
    bW = 2.0 * c01 * Jm23
    t = (A * I1 - bW * trC2) * (1.0 / 3.0)
    return (Jm23 * (A - bW * C11 - t * i11), Jm23 * (A - bW * C22 - t * i22),
            Jm23 * (A - bW * C33 - t * i33), Jm23 * (-bW * C12 - t * i12),
            Jm23 * (-bW * C23 - t * i23), Jm23 * (-bW * C31 - t * i31))


@njit(cache=True, inline="always")
def prony_factors(dt, tau, g):
    """(a_i, b_i) of one Prony term over a step dt (s) with time tau (s) and weight g.

    For dt <= 0 the limits a = 1, b = g apply (an evaluation without time passing); below
    dt / tau = 1e-8 the quotient (1 - a) / x is replaced by its series 1 - x / 2.
    """
    x = dt / tau
    if x > 0.0:
        a = np.exp(-x)
        return a, (g * (1.0 - a) / x if x > 1e-8 else g * (1.0 - 0.5 * x))
    return 1.0, g


@njit(cache=True, inline="always")
def prony_step(a, b, h, d):
    """h_i^{n+1} = a_i h_i^n + b_i d with d = S0bar^{n+1} - S0bar^n (one component, MPa)."""
    return a * h + b * d


@njit(cache=True, inline="always")
def von_mises(s11, s22, s33, s12, s23, s31):
    """Von Mises equivalent stress of a symmetric stress, same unit (MPa)."""
    return np.sqrt(0.5 * ((s11 - s22) ** 2 + (s22 - s33) ** 2 + (s33 - s11) ** 2)
                   + 3.0 * (s12 * s12 + s23 * s23 + s31 * s31))
