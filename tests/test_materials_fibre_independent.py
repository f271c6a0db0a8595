"""An independent evaluation of the Holzapfel-Gasser-Ogden stress on deformation histories.

FEBio's "Holzapfel-Gasser-Ogden" material (FEHolzapfelGasserOgden, public source) was read
for its conventions; nothing of it is implemented here or in the library. Where they agree
and where they differ:

* both are uncoupled: the fibre invariant uses the isochoric C_bar = J^-2/3 C, so
  I1_bar and I4_bar, and E = kappa (I1_bar - 3) + (1 - 3 kappa)(I4_bar - 1);
* the fibre energy is k1 / (2 k2) [exp(k2 E^2) - 1] per family in both;
* two families in the plane of the first two material axes at +-gamma (degrees) from the
  first axis: our ``fibre_angle`` from the bisector e1 in the (e1, e2) plane;
* the tension switch: FEBio adds a family when E >= 0, we when E > 0; the contribution is
  zero at E = 0, so the two give the same stress everywhere;
* ground matter: FEBio's c/2 (I1_bar - 3) is our C10 (I1_bar - 3) with c = 2 C10 (our C01
  term has no counterpart there; it is 0 for that comparison);
* the deviatoric Cauchy stress has the same form, (1/J) dev[2 C10 b_bar
  + sum 2 Psi'(E) h_bar], h_bar = kappa b_bar + (1 - 3 kappa) a_bar (x) a_bar;
* parameter ranges: FEBio accepts c, k1, k2 >= 0 and kappa in [0, 1/3]; k2 = 0 divides by
  zero in its energy, where ours takes the limit k1 E^2 / 2;
* the volumetric part differs: FEBio's uncoupled materials add their own U(J) with a bulk
  modulus, ours is (J - 1)^2 / D1; the pressures agree only at J = 1.

The second evaluation below is written differently from the library on purpose: the
energy from the left Cauchy-Green tensor b and the pushed-forward fibres |F_bar a_0|^2, and
the stress by complex-step differentiation of that energy, P_ij = Im W(F + i h e_ij) / h
(no subtractive cancellation, exact to round-off for h = 1e-30), then sigma = P F^T / J.
On six deformation histories (uniaxial along the bisector, equibiaxial in the fibre plane,
simple shear in the fibre plane and across it, through-thickness compression, a random
path) the two agree to within 1e-12 of the largest stress component plus 1e-13 MPa (measured:
at most 1.2e-14 relative, 2e-14 MPa absolute where the isochoric paths have J = 1 to
round-off and K (J - 1) carries the round-off of the determinant).
"""

import numpy as np
import pytest

from corneasim.materials import cauchy_stress

HGO = "holzapfel-gasser-ogden"
P = np.array([0.03, 0.01, 0.2, 20.0, 0.12, 35.0, 0.02])  # C10, C01, k1, k2, kappa, angle deg, D1
STEP = 1e-30


def complex_energy(F):
    c10, c01, k1, k2, kappa, angle, d1 = P
    J = F[0, 0] * (F[1, 1] * F[2, 2] - F[1, 2] * F[2, 1]) - F[0, 1] * (F[1, 0] * F[2, 2] - F[1, 2] * F[2, 0]) \
        + F[0, 2] * (F[1, 0] * F[2, 1] - F[1, 1] * F[2, 0])
    Fbar = F / J ** (1.0 / 3.0)
    b = np.einsum("ik,jk->ij", Fbar, Fbar)
    I1 = b[0, 0] + b[1, 1] + b[2, 2]
    I2 = 0.5 * (I1**2 - np.einsum("ij,ji->", b, b))
    W = c10 * (I1 - 3.0) + c01 * (I2 - 3.0) + (J - 1.0) ** 2 / d1
    t = np.deg2rad(angle)
    for a0 in (np.array([np.cos(t), np.sin(t), 0.0]), np.array([np.cos(t), -np.sin(t), 0.0])):
        a = Fbar @ a0
        E = kappa * (I1 - 3.0) + (1.0 - 3.0 * kappa) * (a @ a - 1.0)
        if E.real > 0.0:
            W = W + 0.5 * k1 / k2 * (np.exp(k2 * E**2) - 1.0)
    return W


def complex_step_cauchy(F):
    first_piola = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            dF = np.zeros((3, 3), dtype=complex)
            dF[i, j] = 1j * STEP
            first_piola[i, j] = complex_energy(F + dF).imag / STEP
    return first_piola @ F.T / np.linalg.det(F)


def _random_path():
    A = np.random.default_rng(17).uniform(-0.3, 0.3, (3, 3))
    return [np.eye(3) + t * A for t in np.linspace(0.05, 1.0, 8)]


HISTORIES = {
    "uniaxial along the bisector": [np.diag([s, s**-0.5, s**-0.5]) for s in np.linspace(1.0, 1.3, 8)[1:]],
    "equibiaxial in the fibre plane": [np.diag([s, s, 1.02 * s**-2]) for s in np.linspace(1.0, 1.25, 8)[1:]],
    "simple shear in the fibre plane": [np.eye(3) + g * np.outer([1, 0, 0], [0, 1, 0])
                                        for g in np.linspace(0, 0.6, 8)[1:]],
    "shear across the lamellae": [np.eye(3) + g * np.outer([1, 0, 0], [0, 0, 1]) for g in np.linspace(0, 0.6, 8)[1:]],
    "compression through the thickness": [np.diag([s**-0.5, s**-0.5, s]) for s in np.linspace(1.0, 0.7, 8)[1:]],
    "random path": _random_path(),
}


@pytest.mark.parametrize("history", HISTORIES)
def test_library_stress_equals_the_complex_step_derivative_of_an_independent_energy(history):
    for F in HISTORIES[history]:
        expected = complex_step_cauchy(F)
        got = cauchy_stress(HGO, P, F)
        assert np.abs(got - expected).max() <= 1e-12 * np.abs(expected).max() + 1e-13


def test_the_histories_load_the_fibres():
    """The comparison is not only the matrix's: each history stretches a family (E > 0)."""
    matrix = P.copy()
    matrix[2] = 0.0
    for history, path in HISTORIES.items():
        F = path[-1]
        share = np.abs(cauchy_stress(HGO, P, F) - cauchy_stress(HGO, matrix, F)).max()
        assert share > 1e-3, history
