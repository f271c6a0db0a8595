"""The failure criterion and the strain-energy densities of the distortion-energy theory."""

import numpy as np
import pytest

from corneasim.materials import (
    KernelMaterial,
    distortion_energy_density,
    distortion_energy_limit,
    failure_ratio,
    volumetric_energy_density,
    von_mises_stress,
)
from corneasim.materials._kernel_form import FAILURE_CODES


def random_rotation(seed):
    Q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return Q


def test_von_mises_of_simple_states():
    assert von_mises_stress(np.diag([5.0, 0.0, 0.0])) == pytest.approx(5.0)
    assert von_mises_stress(np.diag([2.0, 2.0, 2.0])) == pytest.approx(0.0, abs=1e-14)
    tau = np.zeros((3, 3))
    tau[0, 1] = tau[1, 0] = 1.5
    assert von_mises_stress(tau) == pytest.approx(np.sqrt(3) * 1.5)


def test_von_mises_with_shear_terms_equals_principal_form():
    """Trephination eq. 10 (components) equals needle eq. 15 (principal stresses) in any frame."""
    principal = np.array([3.0, -1.0, 0.5])
    eq15 = np.sqrt(0.5 * ((3 + 1) ** 2 + (-1 - 0.5) ** 2 + (0.5 - 3) ** 2))
    for seed in range(5):
        Q = random_rotation(seed)
        sigma = Q @ np.diag(principal) @ Q.T
        assert von_mises_stress(sigma) == pytest.approx(eq15, rel=1e-12)


def test_energy_densities_sum_to_linear_elastic_energy():
    """rho_V + rho_D of eq. 11 equal the total strain energy density of eq. 12."""
    E, nu = 1.8, 0.49
    s1, s2, s3 = 2.0, -0.7, 0.4
    sigma = random_rotation(3) @ np.diag([s1, s2, s3]) @ random_rotation(3).T
    total = (s1**2 + s2**2 + s3**2 - 2 * nu * (s1 * s2 + s2 * s3 + s3 * s1)) / (2 * E)
    rho_d = distortion_energy_density(sigma, E, nu)
    rho_v = volumetric_energy_density(sigma, E, nu)
    assert rho_d + rho_v == pytest.approx(total, rel=1e-12)
    assert rho_d == pytest.approx((1 + nu) / (6 * E) * ((s1 - s2) ** 2 + (s2 - s3) ** 2 + (s3 - s1) ** 2))


def test_distortion_limit_is_reached_at_the_uniaxial_limit_stress():
    E, nu, limit = 1.8, 0.49, 5.0
    assert distortion_energy_density(np.diag([limit, 0, 0]), E, nu) == pytest.approx(
        distortion_energy_limit(limit, E, nu))


@pytest.mark.parametrize("criterion, expected", [("von-mises", 6.0 / 5.0), ("none", 0.0)])
def test_failure_ratio_codes(criterion, expected):
    record = KernelMaterial(density=1e-9, c10=1.0, failure_criterion=FAILURE_CODES[criterion],
                            failure_limit=5.0).as_array()
    sigma = np.diag([6.0, 0.0, 0.0])
    assert failure_ratio(sigma, record) == pytest.approx(expected)
