"""The failure criterion and the strain-energy densities of the distortion-energy theory.

All functions are ``@njit(cache=True)`` and take the Cauchy stress ``sigma``
(3x3, MPa).

The criterion is von Mises (distortion energy, needle paper eq. 15; trephination paper
eq. 10 with the shear terms): sigma_vm = sqrt(1/2 [(s11-s22)^2 + (s22-s33)^2 +
(s33-s11)^2] + 3 (s12^2 + s23^2 + s31^2)), MPa, the failure measure of ``_law``.

An element fails when ``sigma_vm >= limit`` (``failure_ratio >= 1``). Both papers'
flowcharts state the comparison the other way round (delta < [sigma] means failure);
that contradicts their own yield condition (eqs. 14-15 / 12-13) and is not followed.

The densities of needle paper eq. 11 use a small-strain elastic stand-in (E, nu)
(the paper takes E = 1.8 MPa, nu = 0.49): the distortion energy density
rho_D = (1 + nu) / (3 E) sigma_vm^2 and the volumetric density
rho_V = (1 - 2 nu) / (6 E) (tr sigma)^2, both mJ/mm^3 (= MPa); their sum is the
linear-elastic strain energy density of eq. 12.
"""

from __future__ import annotations

from numba import njit

from corneasim.materials._kernel_form import FAILURE_VON_MISES, P_FAILURE_CRITERION, P_FAILURE_LIMIT
from corneasim.materials._law import von_mises


@njit(cache=True)
def von_mises_stress(sigma):
    """Von Mises equivalent stress of a Cauchy stress tensor (shear terms included), MPa."""
    return von_mises(sigma[0, 0], sigma[1, 1], sigma[2, 2], 0.5 * (sigma[0, 1] + sigma[1, 0]),
                     0.5 * (sigma[1, 2] + sigma[2, 1]), 0.5 * (sigma[2, 0] + sigma[0, 2]))


@njit(cache=True)
def limit_ratio(von_mises_equivalent, record):
    """A von Mises stress (MPa) divided by the limit of a kernel flat record (0 without
    criterion or limit): the failure ratio of the reference kernels and of :func:`failure_ratio`."""
    limit = record[P_FAILURE_LIMIT]
    if limit <= 0.0 or int(record[P_FAILURE_CRITERION]) != FAILURE_VON_MISES:
        return 0.0
    return von_mises_equivalent / limit


@njit(cache=True)
def failure_ratio(sigma, record):
    """Von Mises stress divided by the limit of a kernel flat record (0 without criterion or limit).

    The material point has failed when the ratio is >= 1.
    """
    return limit_ratio(von_mises_stress(sigma), record)


@njit(cache=True)
def distortion_energy_density(sigma, youngs_modulus, poisson_ratio):
    """Distortion energy density rho_D of needle paper eq. 11, mJ/mm^3 (E in MPa)."""
    return (1.0 + poisson_ratio) / (3.0 * youngs_modulus) * von_mises_stress(sigma) ** 2


@njit(cache=True)
def volumetric_energy_density(sigma, youngs_modulus, poisson_ratio):
    """Volume-change energy density rho_V of needle paper eq. 11, mJ/mm^3 (E in MPa)."""
    trace = sigma[0, 0] + sigma[1, 1] + sigma[2, 2]
    return (1.0 - 2.0 * poisson_ratio) / (6.0 * youngs_modulus) * trace * trace


def distortion_energy_limit(limit_stress: float, youngs_modulus: float, poisson_ratio: float) -> float:
    """Limit distortion energy density rho_D0 = 2 (1 + nu) [sigma]^2 / (6 E) (needle eq. 13), mJ/mm^3."""
    return 2.0 * (1.0 + poisson_ratio) * limit_stress**2 / (6.0 * youngs_modulus)
