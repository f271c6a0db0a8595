"""The node-update kernels against a plain NumPy central-difference step."""

import numpy as np
import pytest

from corneasim.solver._integrate import (
    ENERGY_DAMPING, ENERGY_EXTERNAL, ENERGY_INTERNAL, ENERGY_REACTION, N_ENERGIES,
    integrate_acceleration, integrate_velocity_displacement)
from corneasim.solver._loads import FIXED

N_NODES = 1001


def step(damping):
    """One step on fixed random data: (u, v, a, energies) after both kernels."""
    rng = np.random.default_rng(3)
    u, v, a, f_int, f_ext = (rng.uniform(-1, 1, (N_NODES, 3)) for _ in range(5))
    mass = rng.uniform(1.0, 2.0, 3 * N_NODES)
    fixed_dofs = np.array([0, 1, 2, 1500], np.int64)  # node 0 and one dof of node 500
    kind = np.full(fixed_dofs.size, FIXED, np.int64)
    energies = np.zeros(N_ENERGIES)
    integrate_velocity_displacement(u, v, a, f_int, f_ext, mass, 1e-3, 8e-4, 0.0, fixed_dofs, kind,
                                    np.zeros(fixed_dofs.size), np.zeros(fixed_dofs.size, np.int64),
                                    np.zeros((1, 8)), np.ones(N_NODES, np.uint8), energies)
    new_f_int, new_f_ext = (rng.uniform(-1, 1, (N_NODES, 3)) for _ in range(2))
    f_ext[:] = new_f_ext  # the kernel zeroed f_ext for the new loads
    integrate_acceleration(v, new_f_int, f_ext, 1.0 / mass, mass, 1e-3, damping, np.zeros(3), a,
                           energies, np.zeros(3))
    return u, v, a, energies


@pytest.mark.parametrize("damping", [0.0, 50.0])
def test_node_update_matches_the_central_difference_formulas(damping):
    """u, v, a and the half-step works to round-off, against the textbook step written out
    in NumPy (module docstring of ``_integrate``); the kernels fuse multiply-adds."""
    rng = np.random.default_rng(3)
    u, v, a, f_int, f_ext = (rng.uniform(-1, 1, (N_NODES, 3)).ravel() for _ in range(5))
    mass = rng.uniform(1.0, 2.0, 3 * N_NODES)
    new_f_int, new_f_ext = (rng.uniform(-1, 1, (N_NODES, 3)).ravel() for _ in range(2))
    dt, dt_old = 1e-3, 8e-4
    v_half = v + 0.5 * (dt + dt_old) * a
    v_old = v_half[[0, 1, 2, 1500]] - 0.5 * (dt + dt_old) * a[[0, 1, 2, 1500]]
    reaction = mass[[0, 1, 2, 1500]] * ((0.0 - v_old) / (0.5 * (dt + dt_old))
                                        - a[[0, 1, 2, 1500]])
    v_half[[0, 1, 2, 1500]] = 0.0
    du = dt * v_half
    a_new = (new_f_ext - new_f_int) / mass - damping * v_half
    expected_internal = 0.5 * du @ f_int + 0.5 * dt * v_half @ new_f_int
    expected_external = 0.5 * du @ f_ext + 0.5 * dt * v_half @ new_f_ext
    u_got, v_got, a_got, energies = step(damping)
    np.testing.assert_allclose(u_got.ravel(), u + du, rtol=0.0, atol=1e-15)
    np.testing.assert_allclose(v_got.ravel(), v_half, rtol=0.0, atol=1e-15)
    np.testing.assert_allclose(a_got.ravel(), a_new, rtol=1e-14, atol=1e-14)
    assert np.all(v_got.ravel()[[0, 1, 2, 1500]] == 0.0)
    assert energies[ENERGY_INTERNAL] == pytest.approx(expected_internal, rel=1e-12)
    assert energies[ENERGY_EXTERNAL] == pytest.approx(expected_external, rel=1e-12)
    assert energies[ENERGY_REACTION] == pytest.approx(
        0.5 * reaction @ (dt_old * v_old), rel=1e-12)
    assert energies[ENERGY_DAMPING] == pytest.approx(
        damping * dt * mass @ (v_half * v_half), rel=1e-12, abs=0.0)

