"""Prony relaxation against the closed-form 1D solutions (step and ramp-and-hold)."""

import numpy as np
import pytest

from corneasim.materials import (
    KernelMaterial,
    cauchy_stress,
    new_history,
    normalised_prony_weights,
    viscoelastic_stress,
)

MODULI = np.array([0.69, 0.43, 0.31, 0.40])
LONG_TERM = 0.43
TAU = np.array([8.83, 65.33, 876.93, 2840.0])
G = normalised_prony_weights(MODULI, LONG_TERM)
C10 = 0.3
MATERIAL = KernelMaterial(density=1e-9, c10=C10, d1=0.01, prony_g=tuple(G), prony_tau=tuple(TAU))
RECORD = MATERIAL.as_array()
MU0 = 2 * C10


def shear(gamma):
    F = np.eye(3)
    F[0, 1] = gamma
    return F


def test_weights_of_the_paper():
    total = MODULI.sum() + LONG_TERM
    np.testing.assert_allclose(G, MODULI / total, rtol=1e-15)
    assert 1 - G.sum() == pytest.approx(LONG_TERM / total)


def run(gammas, times):
    history, out = new_history(), []
    for k in range(1, len(times)):
        before = history.copy()
        sigma, history = viscoelastic_stress(shear(gammas[k]), history, times[k] - times[k - 1], RECORD)
        if k == 1:
            np.testing.assert_array_equal(before, new_history())  # pure: input not modified
        out.append(sigma[0, 1])
    return np.array(out)


def relaxation(t):
    return (1 - G.sum()) + np.sum(G * np.exp(-np.asarray(t)[:, None] / TAU), axis=1)


def test_step_relaxation_any_step_size():
    gamma = 1e-5
    times = np.concatenate([[0.0, 0.0], np.cumsum(np.random.default_rng(0).uniform(0.1, 400.0, 40))])
    gammas = np.full(times.size, gamma)
    gammas[0] = 0.0
    expected = MU0 * gamma * relaxation(times[1:])
    np.testing.assert_allclose(run(gammas, times), expected, rtol=1e-8)


def test_ramp_and_hold():
    gamma0, t_ramp = 1e-5, 30.0
    rate = gamma0 / t_ramp
    times = np.concatenate([np.linspace(0.0, t_ramp, 8), t_ramp + np.cumsum(np.geomspace(0.5, 900.0, 25))])
    gammas = np.minimum(times / t_ramp, 1.0) * gamma0
    t = times[1:]
    ramp = np.minimum(t, t_ramp)
    # sigma(t) = mu0 rate [g_inf min(t, t_r) + sum g_i tau_i (e^{-(t - min(t, t_r))/tau_i} - e^{-t/tau_i})]
    expected = MU0 * rate * ((1 - G.sum()) * ramp + np.sum(
        G * TAU * (np.exp(-(t - ramp)[:, None] / TAU) - np.exp(-t[:, None] / TAU)), axis=1))
    np.testing.assert_allclose(run(gammas, times), expected, rtol=1e-8)


def test_long_term_response_is_scaled_isochoric_stress():
    """After complete relaxation the isochoric stress is (1 - sum g) times the instantaneous one."""
    F = np.array([[1.3, 0.2, 0.0], [0.05, 0.9, 0.1], [0.0, -0.1, 1.05]])
    _, history = viscoelastic_stress(F, new_history(), 0.0, RECORD)
    sigma, _ = viscoelastic_stress(F, history, 1e9, RECORD)
    expected = cauchy_stress("neo-hooke", [(1 - G.sum()) * C10, 0.01], F)
    np.testing.assert_allclose(sigma, expected, rtol=1e-10, atol=1e-12)
    instantaneous, _ = viscoelastic_stress(F, new_history(), 0.0, RECORD)
    np.testing.assert_allclose(instantaneous, cauchy_stress("neo-hooke", [C10, 0.01], F), rtol=1e-12)


def test_instantaneous_modulus_for_time_step():
    assert MATERIAL.initial_shear_modulus == pytest.approx(MU0)
    assert MATERIAL.wave_speed == pytest.approx(np.sqrt((2 / 0.01 + 4 / 3 * MU0) / 1e-9))


def test_the_fibres_of_a_fibre_material_relax_with_its_matrix():
    """Instantaneously the stress is the elastic one, fibres included; held at F for many
    times the longest tau, it keeps (1 - sum g) of the isochoric part and all of the pressure."""
    p = [0.03, 0.01, 0.2, 20.0, 0.12, 35.0, 0.02]  # C10, C01, k1, k2, kappa, angle deg, D1
    fibre = KernelMaterial(density=1e-9, c10=0.03, c01=0.01, d1=0.02, fibre_k1=0.2, fibre_k2=20.0,
                           fibre_kappa=0.12, fibre_angle=np.deg2rad(35.0), prony_g=tuple(G),
                           prony_tau=tuple(TAU)).as_array()
    F = np.array([[1.08, 0.03, 0.0], [0.02, 0.97, 0.01], [0.0, -0.02, 0.99]])
    elastic = cauchy_stress("holzapfel-gasser-ogden", p, F)
    sigma0, history = viscoelastic_stress(F, new_history(), 0.0, fibre)
    np.testing.assert_allclose(sigma0, elastic, rtol=0, atol=1e-12 * np.abs(elastic).max())
    relaxed, _ = viscoelastic_stress(F, history, 1e3 * TAU.max(), fibre)
    pressure = np.trace(elastic) / 3
    expected = (1 - G.sum()) * (elastic - pressure * np.eye(3)) + pressure * np.eye(3)
    np.testing.assert_allclose(relaxed, expected, rtol=0, atol=1e-12 * np.abs(elastic).max())
