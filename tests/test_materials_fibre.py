"""The Holzapfel-Gasser-Ogden stroma law against closed forms and an independently written W.

Law (``materials/_fibre_law.py``): W = C10 (I1b - 3) + C01 (I2b - 3) + sum_i Psi(E_i)
+ (J - 1)^2 / D1, Psi(E) = k1 / (2 k2) (exp(k2 E^2) - 1) for E > 0 (else 0),
E_i = kappa (I1b - 3) + (1 - 3 kappa)(I4i_b - 1), families a_0 = (cos t, +-sin t, 0).

Closed forms (incompressible, J = 1, sigma = -p I + 2 W1 b + 2 W2 (I1 b - b^2)
+ sum_i 2 Psi'(E_i) h_i, h_i = kappa b + (1 - 3 kappa) a_i (x) a_i, a_i = F a_0i):

* uniaxial along the fibres (t = 0, both families along e1, so the law is transversely
  isotropic about e1 and the lateral stretches are lambda^-1/2): b = diag(l^2, 1/l, 1/l),
  a = (l, 0, 0), I1 = l^2 + 2/l, I4 = l^2, and sigma_11 - sigma_22 =
  2 (l^2 - 1/l)(C10 + C01 / l) + 4 Psi'(E) [kappa (l^2 - 1/l) + (1 - 3 kappa) l^2];
* uniaxial across the fibres with kappa = 0 (load along e2): the fibres lie along the
  contracting lateral axis, I4 = l1^2 < 1 gives E < 0, the fibres are idle, the response is
  the isotropic matrix, 2 (l^2 - 1/l)(C10 + C01 / l);
* equibiaxial in the fibre plane, F = diag(l, l, l^-2): both families have I4 = l^2 and
  sigma_11 - sigma_33 = 2 (l^2 - l^-4)(C10 + C01 l^2)
  + 4 Psi'(E) [kappa (l^2 - l^-4) + (1 - 3 kappa) l^2 cos^2 t], sigma_22 with sin^2 t.

Where no closed form exists (uniaxial along the bisector at t = 45 deg, across with
kappa > 0, along one family of an oblique pair) the reference is the uniaxial state of the
independent W below: for F = [[l, F12, 0], [0, F22, 0], [0, 0, 1/(l F22)]] the lateral
faces are traction-free exactly where W is stationary in (F12, F22) at fixed l, and then
the nominal stress is P_11 = dW*/dl of the minimised energy W*(l) (envelope theorem),
sigma_11 = l P_11.
"""

import numpy as np
import pytest
from scipy.optimize import minimize

from corneasim.errors import InputError
from corneasim.materials import (
    cauchy_stress, check_stability, homogeneous_cauchy_stress, load_material, strain_energy)
from corneasim.materials._fibre_homogeneous import DIRECTIONS, directional_cauchy_stress
from corneasim.materials._fibre_law import fibre_pk2
from corneasim.materials._homogeneous import drucker_minimum_eigenvalue
from corneasim.materials._law import isochoric_pk2, volumetric_factor

HGO = "holzapfel-gasser-ogden"
C10, C01, K1, K2, KAPPA, D1 = 0.03, 0.01, 0.2, 20.0, 0.1, 0.02


def parameters(angle=45.0, kappa=KAPPA, c01=C01, k1=K1, k2=K2):
    return np.array([C10, c01, k1, k2, kappa, angle, D1])


def energy(F, p, fibre_angles=None):
    """W written from the definition, valid for complex F (complex-step differentiation).

    ``fibre_angles`` (radians, in the e1-e2 plane) replace the law's +-angle when given.
    """
    c10, c01, k1, k2, kappa, angle, d1 = p
    if fibre_angles is None:
        fibre_angles = (np.deg2rad(angle), -np.deg2rad(angle))
    J = np.linalg.det(F)
    C = J ** (-2.0 / 3.0) * (F.T @ F)
    I1 = np.trace(C)
    I2 = 0.5 * (I1 * I1 - np.trace(C @ C))
    W = c10 * (I1 - 3.0) + c01 * (I2 - 3.0) + (J - 1.0) ** 2 / d1
    for t in fibre_angles:
        a = np.array([np.cos(t), np.sin(t), 0.0])
        E = kappa * (I1 - 3.0) + (1.0 - 3.0 * kappa) * (a @ C @ a - 1.0)
        if E.real > 0.0:
            W = W + k1 / (2.0 * k2) * (np.exp(k2 * E * E) - 1.0)
    return W


def psi_prime(E, k1=K1, k2=K2):
    return np.where(E > 0.0, k1 * E * np.exp(k2 * E * E), 0.0)


def uniaxial_reference(p, stretch, fibre_angles, load_axis=0):
    """sigma_11 of the uniaxial state of the independent W (module docstring).

    The load acts along e1 (``load_axis`` 0) or e2 (1: the deformation's axes 1 and 2 swap).
    """
    swap = np.eye(3)[[1, 0, 2]] if load_axis == 1 else np.eye(3)

    def minimised(lam, start):
        def w(x):
            F = np.array([[lam, x[1], 0.0], [0.0, np.exp(x[0]), 0.0], [0.0, 0.0, np.exp(-x[0]) / lam]])
            return energy(swap @ F @ swap, p, fibre_angles)

        result = minimize(w, start, method="BFGS", options={"gtol": 1e-14, "xrtol": 1e-14})
        return result.fun, result.x

    out = []
    for lam in np.atleast_1d(stretch):
        _, x = minimised(lam, np.array([-0.5 * np.log(lam), 0.0]))
        h = 1e-5 * lam
        upper, _ = minimised(lam + h, x)
        lower, _ = minimised(lam - h, x)
        out.append(lam * (upper - lower) / (2.0 * h))
    return np.array(out)


def random_F(rng, amplitude=0.15):
    return np.eye(3) + amplitude * rng.uniform(-1.0, 1.0, (3, 3))


def random_rotation(rng):
    Q, R = np.linalg.qr(rng.normal(size=(3, 3)))
    Q = Q @ np.diag(np.sign(np.diag(R)))
    return Q if np.linalg.det(Q) > 0 else -Q


TENSION = np.array([1.02, 1.05, 1.1, 1.2, 1.3])


def test_uniaxial_along_the_fibres_closed_form():
    p = parameters(angle=0.0)
    lam = TENSION
    I1 = lam**2 + 2.0 / lam
    E = KAPPA * (I1 - 3.0) + (1.0 - 3.0 * KAPPA) * (lam**2 - 1.0)
    expected = (2.0 * (lam**2 - 1.0 / lam) * (C10 + C01 / lam)
                + 4.0 * psi_prime(E) * (KAPPA * (lam**2 - 1.0 / lam) + (1.0 - 3.0 * KAPPA) * lam**2))
    np.testing.assert_allclose(homogeneous_cauchy_stress(HGO, p, "uniaxial", lam), expected, rtol=1e-12)
    for direction in ("bisector", "along"):
        np.testing.assert_allclose(directional_cauchy_stress(HGO, p, "uniaxial", lam, direction), expected,
                                   rtol=1e-9)
    for stretch, value in zip(lam, expected):
        sigma = cauchy_stress(HGO, p, np.diag([stretch, stretch**-0.5, stretch**-0.5]))
        assert sigma[0, 0] - sigma[1, 1] == pytest.approx(value, rel=1e-12)
        assert sigma[1, 1] == pytest.approx(sigma[2, 2], abs=1e-15)


def test_uniaxial_across_the_fibres_closed_form_and_independent_solution():
    lam = TENSION
    matrix = 2.0 * (lam**2 - 1.0 / lam) * (C10 + C01 / lam)
    got = directional_cauchy_stress(HGO, parameters(angle=0.0, kappa=0.0), "uniaxial", lam, "across")
    np.testing.assert_allclose(got, matrix, rtol=1e-9)
    # strong dispersion: the fibres' isotropic share resists from stretch ~1.4 on, and the
    # lateral stretches differ; the reference is the independent W's uniaxial state
    p = parameters(angle=0.0, kappa=0.3)
    lam = np.array([1.1, 1.3, 1.5, 1.7])
    matrix = 2.0 * (lam**2 - 1.0 / lam) * (C10 + C01 / lam)
    got = directional_cauchy_stress(HGO, p, "uniaxial", lam, "across")
    reference = uniaxial_reference(p, lam, fibre_angles=(0.0, 0.0), load_axis=1)
    np.testing.assert_allclose(got, reference, rtol=2e-6)
    assert np.all(got[2:] > 1.01 * matrix[2:])


@pytest.mark.parametrize("angle", [0.0, 30.0, 45.0])
def test_equibiaxial_in_the_fibre_plane_closed_form(angle):
    p = parameters(angle=angle)
    lam = TENSION
    c2, s2 = np.cos(np.deg2rad(angle)) ** 2, np.sin(np.deg2rad(angle)) ** 2
    I1 = 2.0 * lam**2 + lam**-4
    E = KAPPA * (I1 - 3.0) + (1.0 - 3.0 * KAPPA) * (lam**2 - 1.0)
    matrix = 2.0 * (lam**2 - lam**-4) * (C10 + C01 * lam**2)
    s11 = matrix + 4.0 * psi_prime(E) * (KAPPA * (lam**2 - lam**-4) + (1.0 - 3.0 * KAPPA) * lam**2 * c2)
    s22 = matrix + 4.0 * psi_prime(E) * (KAPPA * (lam**2 - lam**-4) + (1.0 - 3.0 * KAPPA) * lam**2 * s2)
    np.testing.assert_allclose(homogeneous_cauchy_stress(HGO, p, "equibiaxial", lam), s11, rtol=1e-12)
    np.testing.assert_allclose(directional_cauchy_stress(HGO, p, "equibiaxial", lam), s11, rtol=1e-12)
    for stretch, a, b in zip(lam, s11, s22):
        sigma = cauchy_stress(HGO, p, np.diag([stretch, stretch, stretch**-2]))
        assert sigma[0, 0] - sigma[2, 2] == pytest.approx(a, rel=1e-12)
        assert sigma[1, 1] - sigma[2, 2] == pytest.approx(b, rel=1e-12)
        assert abs(sigma[0, 1]) < 1e-15


def test_uniaxial_along_the_bisector_and_along_an_oblique_family_match_the_independent_w():
    lam = np.array([0.85, 1.05, 1.15])
    p = parameters(angle=45.0)
    reference = uniaxial_reference(p, lam, fibre_angles=(np.pi / 4, -np.pi / 4))
    np.testing.assert_allclose(homogeneous_cauchy_stress(HGO, p, "uniaxial", lam), reference, rtol=2e-6)
    np.testing.assert_allclose(directional_cauchy_stress(HGO, p, "uniaxial", lam), reference, rtol=2e-6)
    p = parameters(angle=30.0)  # along the first family: the second one is 60 degrees off
    reference = uniaxial_reference(p, lam, fibre_angles=(0.0, -np.pi / 3))
    np.testing.assert_allclose(directional_cauchy_stress(HGO, p, "uniaxial", lam, "along"), reference, rtol=2e-6)


def test_stress_is_the_derivative_of_the_energy():
    """P = dW/dF by central differences of the library's W; P = J sigma F^-T."""
    rng = np.random.default_rng(3)
    p = parameters(angle=30.0)
    h = 1e-6
    for _ in range(6):
        F = random_F(rng) @ np.diag([1.15, 1.05, 0.85])
        P = np.empty((3, 3))
        for i in range(3):
            for j in range(3):
                dF = np.zeros((3, 3))
                dF[i, j] = h
                P[i, j] = (strain_energy(HGO, p, F + dF) - strain_energy(HGO, p, F - dF)) / (2.0 * h)
        expected = np.linalg.det(F) * cauchy_stress(HGO, p, F) @ np.linalg.inv(F).T
        np.testing.assert_allclose(P, expected, atol=1e-8 * np.abs(expected).max())
        assert strain_energy(HGO, p, F) == pytest.approx(energy(F, p), rel=1e-12)


def test_second_piola_kirchhoff_closed_form_gives_the_cauchy_stress():
    """S = S_iso + sum S_f + S_vol of the kernels' scalar functions; sigma = F S F^T / J."""
    rng = np.random.default_rng(5)
    p = parameters(angle=30.0)
    t = np.deg2rad(30.0)
    for _ in range(6):
        F = random_F(rng) @ np.diag([1.1, 1.1, 0.8])
        J = np.linalg.det(F)
        C = F.T @ F
        Ci = np.linalg.inv(C)
        six = lambda A: (A[0, 0], A[1, 1], A[2, 2], A[0, 1], A[1, 2], A[2, 0])  # noqa: E731
        S6 = np.array(isochoric_pk2(*six(C), *six(Ci), J ** (-2.0 / 3.0), C10, C01, 0.0, 0.0))
        for a in ((np.cos(t), np.sin(t), 0.0), (np.cos(t), -np.sin(t), 0.0)):
            S6 += np.array(fibre_pk2(*six(C), *six(Ci), J ** (-2.0 / 3.0), *a, K1, K2, KAPPA))
        S = np.array([[S6[0], S6[3], S6[5]], [S6[3], S6[1], S6[4]], [S6[5], S6[4], S6[2]]])
        S += volumetric_factor(J, 2.0 / D1) * Ci
        np.testing.assert_allclose(F @ S @ F.T / J, cauchy_stress(HGO, p, F), atol=1e-13)


def test_objectivity():
    rng = np.random.default_rng(7)
    p = parameters(angle=30.0)
    for _ in range(5):
        F, Q = random_F(rng) @ np.diag([1.15, 1.0, 0.9]), random_rotation(rng)
        np.testing.assert_allclose(cauchy_stress(HGO, p, Q @ F), Q @ cauchy_stress(HGO, p, F) @ Q.T, atol=1e-13)
        assert strain_energy(HGO, p, Q @ F) == pytest.approx(strain_energy(HGO, p, F), rel=1e-13)


def test_drucker_stable_along_paths_in_the_fibre_plane():
    """The library's check and a finite-difference Hessian of the independent W in (e1, e2)."""
    p = parameters(angle=45.0)
    assert check_stability(HGO, p).stable
    assert check_stability(HGO, load_material("stroma-hgo", warn=False).parameters()).stable
    stretch = np.linspace(0.7, 1.3, 13)
    for mode in ("uniaxial", "equibiaxial", "planar"):
        assert np.all(drucker_minimum_eigenvalue(HGO, p, mode, stretch) > 0.0)

    def w(e1, e2):
        return energy(np.diag(np.exp([e1, e2, -e1 - e2])), p)

    h = 1e-4
    for e1 in np.log(stretch):
        for e2 in (e1, 0.0, -0.5 * e1):  # equibiaxial, planar, near-uniaxial
            H = np.empty((2, 2))
            for i, di in enumerate(np.eye(2) * h):
                for j, dj in enumerate(np.eye(2) * h):
                    H[i, j] = (w(e1 + di[0] + dj[0], e2 + di[1] + dj[1]) - w(e1 + di[0] - dj[0], e2 + di[1] - dj[1])
                               - w(e1 - di[0] + dj[0], e2 - di[1] + dj[1])
                               + w(e1 - di[0] - dj[0], e2 - di[1] - dj[1])) / (4.0 * h * h)
            assert np.linalg.eigvalsh(H).min() > 0.0


def test_fibres_do_not_resist_compression():
    """Uniaxial compression along the fibres: E < 0, the matrix's stress exactly."""
    p = parameters(angle=0.0)
    lam = np.linspace(0.6, 0.99, 8)
    E = KAPPA * (lam**2 + 2.0 / lam - 3.0) + (1.0 - 3.0 * KAPPA) * (lam**2 - 1.0)
    assert np.all(E < 0.0)
    matrix = 2.0 * (lam**2 - 1.0 / lam) * (C10 + C01 / lam)
    np.testing.assert_allclose(homogeneous_cauchy_stress(HGO, p, "uniaxial", lam), matrix, rtol=1e-13)
    without_fibres = parameters(angle=0.0, k1=0.0)
    rng = np.random.default_rng(11)
    for stretch in lam:  # any state that shortens an aligned family (kappa = 0) is the matrix's
        F = np.diag([stretch, 1.0, 1.0 / stretch]) @ (np.eye(3) + 0.02 * rng.uniform(-1, 1, (3, 3)))
        aligned = parameters(angle=0.0, kappa=0.0)
        assert (F.T @ F)[0, 0] * np.linalg.det(F) ** (-2.0 / 3.0) < 1.0
        np.testing.assert_allclose(cauchy_stress(HGO, aligned, F), cauchy_stress(HGO, without_fibres, F),
                                   atol=1e-15)


def test_stress_is_continuous_across_the_switch():
    """E passes through 0 along a uniaxial path: the fibre share vanishes with E."""
    p, matrix = parameters(angle=0.0, kappa=0.0), parameters(angle=0.0, k1=0.0)
    for lam, bound in ((1.0 - 1e-9, 0.0), (1.0 + 1e-9, 1e-8), (1.0 + 1e-6, 1e-5)):
        F = np.diag([lam, lam**-0.5, lam**-0.5])
        share = cauchy_stress(HGO, p, F) - cauchy_stress(HGO, matrix, F)
        assert 0.0 <= share[0, 0] - share[1, 1] <= bound


def test_isotropic_dispersion_is_an_I1_exponential_law():
    """kappa = 1/3: E = (I1b - 3)/3 for both families, W1 = C10 + 2/3 Psi'(E), any fibre angle."""
    rng = np.random.default_rng(13)
    for angle in (0.0, 30.0, 90.0):
        p = parameters(angle=angle, kappa=1.0 / 3.0, c01=0.0)
        for _ in range(4):
            F = random_F(rng)
            J = np.linalg.det(F)
            b = J ** (-2.0 / 3.0) * F @ F.T
            E = (np.trace(b) - 3.0) / 3.0
            W1 = C10 + 2.0 / 3.0 * psi_prime(E)
            dev = 2.0 * W1 * (b - np.trace(b) / 3.0 * np.eye(3))
            expected = dev / J + 2.0 * (J - 1.0) / D1 * np.eye(3)
            np.testing.assert_allclose(cauchy_stress(HGO, p, F), expected, atol=1e-13)


def test_directions_of_the_command_line_are_those_of_the_library():
    from corneasim.cli.material import DIRECTIONS as CLI_DIRECTIONS

    assert CLI_DIRECTIONS == DIRECTIONS


BASE = {"c10": 0.025, "k1": 0.2, "k2": 70.0, "kappa": 0.1, "fibre_angle": 45.0, "d1": 0.0667}


@pytest.mark.parametrize("key, value, expected", [
    ("kappa", 0.4, "less than or equal to 0.333"),
    ("kappa", -0.1, "greater than or equal to 0"),
    ("k1", -1.0, "greater than or equal to 0"),
    ("k2", -1.0, "greater than or equal to 0"),
    ("fibre_angle", 100.0, "less than or equal to 90"),
])
def test_bad_constants_are_one_line_input_errors_naming_the_key(tmp_path, key, value, expected):
    table = "\n".join(f"{k} = {v!r}" for k, v in {**BASE, key: value}.items())
    path = tmp_path / "m.toml"
    path.write_text(f'name = "m"\ndensity = 1e-9\n[hyperelastic]\nmodel = "{HGO}"\n{table}\n')
    with pytest.raises(InputError) as error:
        load_material(path)
    message = str(error.value)
    assert "\n" not in message and f"{HGO}.{key}" in message and expected in message


def test_the_kernel_form_of_a_fibre_law_carries_its_fibre_constants():
    kernel = load_material("stroma-hgo", warn=False).kernel_form()
    # the preset's file: k1 = 0.2 MPa, k2 = 70, kappa = 0.1, 45 degrees; matrix C10 = 0.025 MPa
    assert (kernel.fibre_k1, kernel.fibre_k2, kernel.fibre_kappa) == (0.2, 70.0, 0.1)
    assert kernel.fibre_angle == pytest.approx(np.pi / 4, rel=1e-15)
    assert kernel.has_fibres and kernel.c10 == 0.025 and kernel.c20 == 0.0
