"""Pointwise isotropic hyperelastic laws: strain energy and Cauchy stress of F.

``strain_energy(model, p, F)`` returns W in MPa (= mJ/mm^3) and ``cauchy_stress(model, p,
F)`` the Cauchy stress sigma (3x3, MPa) of a registered law with its flat parameter array
``p`` at a 3x3 deformation gradient ``F`` (dimensionless); ``kernel_energy``/``kernel_stress``
take a kernel record instead. The ``invariant_*`` and ``kernel_*`` functions are
``@njit(cache=True)`` and can be called from other Numba kernels.

Parameter arrays (MPa for moduli, 1/MPa for D1):

==================  ==============================================================
law                 ``p``
==================  ==============================================================
neo-Hooke           ``[C10, D1]``
Mooney-Rivlin       ``[C10, C01, D1]``
Yeoh                ``[C10, C20, C30, D1]``
HGO                 ``[C10, C01, k1, k2, kappa, fibre_angle, D1]`` (k1 MPa, k2 and kappa
                    dimensionless, fibre_angle in degrees from the bisector e1)
kernel family       the flat record of :class:`~corneasim.materials.KernelMaterial`
==================  ==============================================================

The named laws are registered in ``_laws.py`` (their parameter arrays and how they map
onto the family).

Notes
-----
All laws are members of the kernel family (see ``_kernel_form.py``)

.. math::

    W = C_{10}(\\bar I_1-3) + C_{01}(\\bar I_2-3) + C_{20}(\\bar I_1-3)^2
        + C_{30}(\\bar I_1-3)^3 + (J-1)^2/D_1,

with :math:`\\bar B = J^{-2/3} F F^T`, :math:`\\bar I_1 = \\mathrm{tr}\\,\\bar B`,
:math:`\\bar I_2 = \\tfrac12(\\bar I_1^2 - \\mathrm{tr}\\,\\bar B^2)`. Its Cauchy stress
(Holzapfel 2000, *Nonlinear Solid Mechanics*, sec. 6.5) is

.. math::

    \\sigma = \\frac{2}{J}\\,\\mathrm{dev}\\big[(W_1 + \\bar I_1 W_2)\\bar B - W_2 \\bar B^2\\big]
              + \\frac{2}{D_1}(J-1)\\,I,

:math:`W_1 = \\partial W/\\partial\\bar I_1`, :math:`W_2 = \\partial W/\\partial\\bar I_2`. This
corrects eq. 10 of the needle paper and eq. 6 of the trephination paper (docs/materials.md).
:math:`W_1`, :math:`W_2` and the energy are those of ``_law``, the law the element kernels
evaluate. A fibre-reinforced law (``holzapfel-gasser-ogden``) adds the energy and Cauchy
stress of its two fibre families (``_fibre_law``), whose directions lie in the e1-e2 plane
of the frame F is given in, at +-fibre_angle from e1.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.materials._fibre_law import fibre_cauchy_3d, fibre_energy_3d
from corneasim.materials._kernel_form import P_C01, P_C10, P_C20, P_C30, P_D1
from corneasim.materials._law import (
    isochoric_derivatives, isochoric_energy, volumetric_energy, volumetric_factor)
from corneasim.materials._laws import family_constants, fibre_constants


@njit(cache=True)
def _isochoric_b(F):
    """Return (J, Bbar, I1bar, I2bar, Bbar @ Bbar) of a deformation gradient."""
    J = np.linalg.det(F)
    Bbar = J ** (-2.0 / 3.0) * (F @ F.T)
    Bbar2 = Bbar @ Bbar
    I1bar = Bbar[0, 0] + Bbar[1, 1] + Bbar[2, 2]
    I2bar = 0.5 * (I1bar * I1bar - (Bbar2[0, 0] + Bbar2[1, 1] + Bbar2[2, 2]))
    return J, Bbar, I1bar, I2bar, Bbar2


@njit(cache=True)
def invariant_energy(F, c10, c01, c20, c30, d1):
    """Strain energy of the kernel family, MPa (constants in MPa, d1 in 1/MPa)."""
    J, Bbar, I1bar, I2bar, Bbar2 = _isochoric_b(F)
    return isochoric_energy(I1bar, I2bar, c10, c01, c20, c30) + volumetric_energy(J, 2.0 / d1)


@njit(cache=True)
def invariant_stress_split(F, c10, c01, c20, c30, d1):
    """Isochoric Cauchy stress (3x3, MPa, traceless) and pressure p (MPa) of the kernel family.

    The total Cauchy stress is ``sigma_iso + p * I``; p = 2 (J - 1) / D1 is tensile positive.
    """
    J, Bbar, I1bar, I2bar, Bbar2 = _isochoric_b(F)
    W1, _ = isochoric_derivatives(I1bar, c10, c20, c30)
    W2 = c01
    A = (W1 + I1bar * W2) * Bbar - W2 * Bbar2
    trace_third = (A[0, 0] + A[1, 1] + A[2, 2]) / 3.0
    sigma_iso = (2.0 / J) * (A - trace_third * np.eye(3))
    return sigma_iso, volumetric_factor(J, 2.0 / d1) / J


@njit(cache=True)
def invariant_stress(F, c10, c01, c20, c30, d1):
    """Cauchy stress of the kernel family, 3x3, MPa."""
    sigma_iso, p = invariant_stress_split(F, c10, c01, c20, c30, d1)
    return sigma_iso + p * np.eye(3)


@njit(cache=True)
def kernel_energy(F, record):
    """Strain energy (MPa) of a :class:`KernelMaterial` flat record (``as_array()``)."""
    return invariant_energy(F, record[P_C10], record[P_C01], record[P_C20], record[P_C30], record[P_D1])


@njit(cache=True)
def kernel_stress(F, record):
    """Instantaneous elastic Cauchy stress (3x3, MPa) of a :class:`KernelMaterial` flat record.

    This is exactly the law the element kernels evaluate (no viscoelastic relaxation).

    Examples
    --------
    >>> import numpy as np
    >>> from corneasim.materials import KernelMaterial
    >>> record = KernelMaterial(density=1e-9, c10=0.5, d1=0.01).as_array()
    >>> F = np.diag([1.1, 1.1 ** -0.5, 1.1 ** -0.5])
    >>> s = kernel_stress(F, record)
    >>> round(float(s[0, 0] - s[1, 1]), 6)  # 2 C10 (lambda^2 - 1/lambda)
    0.300909
    """
    return invariant_stress(F, record[P_C10], record[P_C01], record[P_C20], record[P_C30], record[P_D1])


@njit(cache=True)
def kernel_stress_split(F, record):
    """Isochoric Cauchy stress (3x3, MPa) and pressure (MPa) of a kernel flat record."""
    return invariant_stress_split(F, record[P_C10], record[P_C01], record[P_C20], record[P_C30], record[P_D1])


def linear_elastic_to_neo_hooke(youngs_modulus: float, poisson_ratio: float) -> tuple[float, float]:
    """Compressible neo-Hooke constants with the same small-strain response as (E, nu).

    Parameters
    ----------
    youngs_modulus : float
        Young's modulus E, MPa.
    poisson_ratio : float
        Poisson's ratio nu (dimensionless, -1 < nu < 0.5).

    Returns
    -------
    (c10, d1) : tuple of float
        C10 = mu / 2 in MPa with mu = E / (2 (1 + nu)); D1 = 2 / K in 1/MPa with
        K = E / (3 (1 - 2 nu)).

    Examples
    --------
    >>> c10, d1 = linear_elastic_to_neo_hooke(3.08, 0.49)  # the sclera
    >>> round(c10, 4), round(d1, 5)
    (0.5168, 0.03896)
    """
    shear_modulus = youngs_modulus / (2.0 * (1.0 + poisson_ratio))
    bulk_modulus = youngs_modulus / (3.0 * (1.0 - 2.0 * poisson_ratio))
    return 0.5 * shear_modulus, 2.0 / bulk_modulus


def strain_energy(model: str, parameters, F) -> float:
    """Strain energy W (MPa) of the registered law ``model`` with its parameter array at F."""
    p = np.asarray(parameters, dtype=np.float64)
    F = np.asarray(F, dtype=np.float64)
    c10, c01, c20, c30 = (float(c) for c in family_constants(model, p))
    W = float(invariant_energy(F, c10, c01, c20, c30, float(p[-1])))
    fibres = fibre_constants(model, p)
    return W if fibres is None else W + float(fibre_energy_3d(F, *fibres))


def cauchy_stress(model: str, parameters, F) -> np.ndarray:
    """Cauchy stress (3x3, MPa) of the registered law ``model`` with its parameter array at F."""
    p = np.asarray(parameters, dtype=np.float64)
    F = np.asarray(F, dtype=np.float64)
    c10, c01, c20, c30 = (float(c) for c in family_constants(model, p))
    sigma = invariant_stress(F, c10, c01, c20, c30, float(p[-1]))
    fibres = fibre_constants(model, p)
    return sigma if fibres is None else sigma + fibre_cauchy_3d(F, *fibres)
