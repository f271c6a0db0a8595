"""The material point of ``materials.kernel`` against NumPy and finite differences of its energy.

The energy (``elastic_energy``) and the stress (``elastic_pk2``) are written separately, so
P = dW/dF by central differences checks the stress, the fibre families' directions in an
element's frame and the frame's use in both.
"""

import numpy as np
import pytest

from corneasim.materials import KernelMaterial
from corneasim.materials.kernel import (
    POINT_FRAME, cauchy_from_pk2, elastic_energy, elastic_pk2, isochoric_strain_energy,
    kinematics, symmetric_matrix, volumetric_energy)

FIBRE = KernelMaterial(density=1e-9, c10=0.03, c01=0.01, c20=0.2, d1=0.05, fibre_k1=0.4,
                       fibre_k2=8.0, fibre_kappa=0.1, fibre_angle=np.deg2rad(25.0)).as_array()
ISOTROPIC = KernelMaterial(density=1e-9, c10=0.3, c01=0.05, c30=0.4, d1=0.02).as_array()


def deformation(seed):
    return np.eye(3) + 0.12 * np.random.default_rng(seed).normal(size=(3, 3))


def frame(seed):
    """An orthonormal pair (m, n) of a random rotation."""
    q, _ = np.linalg.qr(np.random.default_rng(100 + seed).normal(size=(3, 3)))
    return np.concatenate([q[:, 0], q[:, 1]])


@pytest.mark.parametrize("seed", range(4))
def test_kinematics_and_push_forward_are_numpys(seed):
    F = deformation(seed)
    C = F.T @ F
    *c, J = kinematics(F)
    np.testing.assert_allclose(c, [C[0, 0], C[1, 1], C[2, 2], C[0, 1], C[1, 2], C[2, 0]], rtol=1e-14)
    assert J == pytest.approx(np.linalg.det(F), rel=1e-14)
    S = np.random.default_rng(seed).normal(size=6)
    sigma = np.empty(6)
    cauchy_from_pk2(F, S, J, sigma)
    np.testing.assert_allclose(symmetric_matrix(sigma), F @ symmetric_matrix(S) @ F.T / J,
                               rtol=1e-13, atol=1e-15)


@pytest.mark.parametrize("record", [ISOTROPIC, FIBRE], ids=["isotropic", "fibre"])
@pytest.mark.parametrize("seed", range(3))
def test_first_piola_kirchhoff_stress_is_the_energy_gradient(record, seed):
    F, m_n = deformation(seed), frame(seed)
    J, vol, iso = elastic_pk2(F, record, m_n)
    P = F @ symmetric_matrix(np.add(vol, iso))
    h = 1e-6
    numeric = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            dF = np.zeros((3, 3))
            dF[i, j] = h
            numeric[i, j] = (elastic_energy(F + dF, record, m_n) - elastic_energy(F - dF, record, m_n)) / (2 * h)
    np.testing.assert_allclose(P, numeric, rtol=0, atol=1e-7 * np.abs(P).max())
    assert J == pytest.approx(np.linalg.det(F), rel=1e-14)


def test_the_energy_parts_add_up_and_a_fibre_material_needs_its_frame():
    F = deformation(7)
    W = elastic_energy(F, FIBRE, POINT_FRAME)
    iso = isochoric_strain_energy(F, FIBRE, POINT_FRAME)
    assert W == pytest.approx(iso + volumetric_energy(np.linalg.det(F), 2.0 / 0.05), rel=1e-13)
    with pytest.raises(ValueError, match="fibre frame"):
        elastic_pk2(F, FIBRE, None)
    with pytest.raises(ValueError, match="fibre frame"):
        elastic_energy(F, FIBRE, None)
