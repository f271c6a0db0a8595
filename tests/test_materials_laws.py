"""Pointwise hyperelastic laws against closed forms, finite differences of W and objectivity."""

import numpy as np
import pytest

from corneasim.materials import (
    KernelMaterial,
    cauchy_stress,
    kernel_energy,
    kernel_stress,
    linear_elastic_to_neo_hooke,
    strain_energy,
    homogeneous_cauchy_stress,
)

LAWS = {
    "neo-hooke": [0.4, 0.05],
    "mooney-rivlin": [0.3, 0.12, 0.05],
    "yeoh": [0.2, 0.5, 0.3, 0.05],
}


def law(name):
    return name, np.array(LAWS[name])


def random_F(rng, amplitude=0.3):
    F = np.eye(3) + amplitude * rng.uniform(-1, 1, (3, 3))
    return F if np.linalg.det(F) > 0.3 else np.eye(3) + 0.1 * rng.uniform(-1, 1, (3, 3))


def random_rotation(rng):
    Q, R = np.linalg.qr(rng.normal(size=(3, 3)))
    Q = Q @ np.diag(np.sign(np.diag(R)))
    return Q if np.linalg.det(Q) > 0 else -Q


@pytest.mark.parametrize("name", LAWS)
def test_stress_is_derivative_of_energy(name):
    """sigma = (1/J) dW/dF F^T by central finite differences at random F."""
    model, p = law(name)
    rng = np.random.default_rng(1)
    for _ in range(5):
        F = random_F(rng)
        dWdF = np.zeros((3, 3))
        h = 1e-6
        for i in range(3):
            for j in range(3):
                E = np.zeros((3, 3))
                E[i, j] = h
                dWdF[i, j] = (strain_energy(model, p, F + E) - strain_energy(model, p, F - E)) / (2 * h)
        expected = dWdF @ F.T / np.linalg.det(F)
        np.testing.assert_allclose(cauchy_stress(model, p, F), expected, atol=2e-7 * max(1, np.abs(expected).max()))


@pytest.mark.parametrize("name", LAWS)
def test_objectivity_and_symmetry(name):
    model, p = law(name)
    rng = np.random.default_rng(2)
    for _ in range(5):
        F, Q = random_F(rng), random_rotation(rng)
        sigma = cauchy_stress(model, p, F)
        np.testing.assert_allclose(sigma, sigma.T, atol=1e-12)
        np.testing.assert_allclose(cauchy_stress(model, p, Q @ F), Q @ sigma @ Q.T, atol=1e-10)


@pytest.mark.parametrize("name", LAWS)
def test_zero_stress_and_energy_at_identity(name):
    model, p = law(name)
    assert np.abs(cauchy_stress(model, p, np.eye(3))).max() < 1e-14
    assert abs(strain_energy(model, p, np.eye(3))) < 1e-14


def incompressible_closed_form(model, p, mode, lam):
    """Textbook incompressible Cauchy stress of each test (Holzapfel 2000)."""
    padded = np.append(p, [0.0, 0.0])
    c10, c01, c20, c30 = {"neo-hooke": (p[0], 0, 0, 0), "mooney-rivlin": (p[0], p[1], 0, 0),
                          "yeoh": (p[0], 0, padded[1], padded[2])}[model]
    if mode == "uniaxial":
        I1, factor, w2 = lam**2 + 2 / lam, 2 * (lam**2 - 1 / lam), 1 / lam
    elif mode == "equibiaxial":
        I1, factor, w2 = 2 * lam**2 + lam**-4, 2 * (lam**2 - lam**-4), lam**2
    else:
        I1, factor, w2 = lam**2 + 1 + lam**-2, 2 * (lam**2 - lam**-2), 1.0
    W1 = c10 + 2 * c20 * (I1 - 3) + 3 * c30 * (I1 - 3) ** 2
    return factor * (W1 + w2 * c01)


@pytest.mark.parametrize("name", LAWS)
@pytest.mark.parametrize("mode", ["uniaxial", "equibiaxial", "planar"])
def test_homogeneous_tests_match_closed_forms(name, mode):
    """Incompressible test curves and the 3D compressible law at J = 1 both match the closed form."""
    model, p = law(name)
    p_stiff = p.copy()
    p_stiff[-1] = 1e-9  # D1 -> 0: nearly incompressible
    for lam in (0.5, 0.8, 1.0, 1.3, 2.0):
        expected = incompressible_closed_form(model, p, mode, lam)
        assert homogeneous_cauchy_stress(model, p, mode, [lam])[0] == pytest.approx(expected, rel=1e-12, abs=1e-13)
        F = {"uniaxial": np.diag([lam, lam**-0.5, lam**-0.5]), "equibiaxial": np.diag([lam, lam, lam**-2]),
             "planar": np.diag([lam, 1.0, 1 / lam])}[mode]
        sigma = cauchy_stress(model, p_stiff, F)
        assert sigma[0, 0] - sigma[2, 2] == pytest.approx(expected, rel=1e-9, abs=1e-9)
        if mode == "uniaxial":
            assert sigma[1, 1] - sigma[2, 2] == pytest.approx(0.0, abs=1e-9)


def test_kernel_family_matches_each_law_and_record_layout():
    rng = np.random.default_rng(3)
    material = KernelMaterial(density=1e-9, c10=0.2, c01=0.07, c20=0.5, c30=0.3, d1=0.05,
                              prony_g=(0.3,), prony_tau=(10.0,))
    record = material.as_array()
    F = random_F(rng)
    # independent energy: written out from the definition in _kernel_form.py
    J = np.linalg.det(F)
    Bb = J ** (-2 / 3) * F @ F.T
    I1, I2 = np.trace(Bb), 0.5 * (np.trace(Bb) ** 2 - np.trace(Bb @ Bb))
    W = 0.2 * (I1 - 3) + 0.07 * (I2 - 3) + 0.5 * (I1 - 3) ** 2 + 0.3 * (I1 - 3) ** 3 + (J - 1) ** 2 / 0.05
    assert kernel_energy(F, record) == pytest.approx(W, rel=1e-13)
    mr = KernelMaterial(density=1e-9, c10=0.3, c01=0.12, d1=0.05).as_array()
    np.testing.assert_allclose(kernel_stress(F, mr), cauchy_stress("mooney-rivlin", [0.3, 0.12, 0.05], F), rtol=1e-13)


def test_paper_equation_10_is_not_the_derivative():
    """The printed C01 term of needle eq. 10 (4/3 Bb T - T^2/3 I - Bb^2) disagrees with the derived stress."""
    F = np.diag([1.2, 1 / 1.2**0.5, 1 / 1.2**0.5])
    Bb = F @ F.T
    T = np.trace(Bb)
    printed = 2 * (4 / 3 * Bb * T - T * T / 3 * np.eye(3) - Bb @ Bb)
    derived = cauchy_stress("mooney-rivlin", [0.0, 1.0, 1.0], F)
    assert abs((printed - derived)[0, 0]) > 0.1


def test_linear_elastic_small_strain_mapping():
    """Neo-Hooke from (E, nu) gives E and nu back under small uniaxial stress."""
    E, nu = 3.08, 0.49
    p = np.array(linear_elastic_to_neo_hooke(E, nu))
    eps = 1e-6
    # solve for the lateral stretch with zero lateral stress by Newton on sigma_22
    lateral = 1.0
    for _ in range(30):
        s = cauchy_stress("neo-hooke", p, np.diag([1 + eps, lateral, lateral]))[1, 1]
        ds = (cauchy_stress("neo-hooke", p, np.diag([1 + eps, lateral + 1e-9, lateral + 1e-9]))[1, 1] - s) / 1e-9
        lateral -= s / ds
    sigma = cauchy_stress("neo-hooke", p, np.diag([1 + eps, lateral, lateral]))
    assert sigma[0, 0] / eps == pytest.approx(E, rel=1e-4)
    assert -(lateral - 1) / eps == pytest.approx(nu, rel=1e-4)
