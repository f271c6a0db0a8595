"""Pointwise hyperelastic laws: strain energy and Cauchy stress of F.

``strain_energy(model, p, F)`` returns W in MPa (= mJ/mm^3) and ``cauchy_stress(model, p,
F)`` the Cauchy stress sigma (3x3, MPa) of a registered law with its flat parameter array
``p`` at a 3x3 deformation gradient ``F`` (dimensionless); ``kernel_energy``/``kernel_stress``
take a kernel record instead (``law_record`` makes one of a law's parameters). The
``kernel_*`` functions are ``@njit(cache=True)`` and can be called from other Numba kernels.

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
It is evaluated as the push-forward :math:`\\sigma = F S F^T / J` of the second
Piola-Kirchhoff stress that the element kernels evaluate (``_point``, ``_law``), so the
curves, the fitting and the kernels share one law. A fibre-reinforced law
(``holzapfel-gasser-ogden``) adds the energy and Cauchy stress of its two fibre families
(``_fibre_law``), whose directions lie in the e1-e2 plane of the frame F is given in, at
+-fibre_angle from e1.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.materials._kernel_form import (
    N_PARAMETERS, P_C01, P_C10, P_C20, P_C30, P_D1, P_FIBRE_ANGLE, P_FIBRE_K1, P_FIBRE_K2,
    P_FIBRE_KAPPA)
from corneasim.materials._law import volumetric_factor
from corneasim.materials._laws import family_constants, fibre_constants
from corneasim.materials._point import (
    POINT_FRAME, cauchy_from_pk2, elastic_energy, elastic_pk2, symmetric_matrix)


@njit(cache=True)
def kernel_energy(F, record):
    """Strain energy (MPa) of a :class:`KernelMaterial` flat record (``as_array()``), its
    fibre families in the (e1, e2) plane."""
    return elastic_energy(F, record, POINT_FRAME)


@njit(cache=True)
def kernel_stress_split(F, record):
    """Isochoric Cauchy stress (3x3, MPa, traceless) and pressure p (MPa) of a kernel flat
    record: sigma = sigma_iso + p I, p = K (J - 1) tensile positive."""
    J, _, iso = elastic_pk2(F, record, POINT_FRAME)
    sigma = np.empty(6)
    cauchy_from_pk2(F, iso, J, sigma)
    return symmetric_matrix(sigma), volumetric_factor(J, 2.0 / record[P_D1]) / J


@njit(cache=True)
def kernel_stress(F, record):
    """Instantaneous elastic Cauchy stress (3x3, MPa) of a :class:`KernelMaterial` flat record.

    This is exactly the law the element kernels evaluate (no viscoelastic relaxation), the
    fibre families in the (e1, e2) plane.

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
    sigma, p = kernel_stress_split(F, record)
    for i in range(3):
        sigma[i, i] += p
    return sigma


def law_record(model: str, parameters) -> np.ndarray:
    """The kernel flat record (``_kernel_form``) of the registered law ``model`` with its
    parameter array (density 0, no Prony terms, no failure criterion)."""
    p = np.asarray(parameters, dtype=np.float64)
    record = np.zeros(N_PARAMETERS)
    record[[P_C10, P_C01, P_C20, P_C30]] = family_constants(model, p)
    record[P_D1] = p[-1]
    fibres = fibre_constants(model, p)
    if fibres is not None:
        record[[P_FIBRE_K1, P_FIBRE_K2, P_FIBRE_KAPPA, P_FIBRE_ANGLE]] = fibres
    return record


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
    return float(kernel_energy(np.asarray(F, dtype=np.float64), law_record(model, parameters)))


def cauchy_stress(model: str, parameters, F) -> np.ndarray:
    """Cauchy stress (3x3, MPa) of the registered law ``model`` with its parameter array at F."""
    return kernel_stress(np.asarray(F, dtype=np.float64), law_record(model, parameters))
