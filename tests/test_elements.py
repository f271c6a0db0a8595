"""Element kernels against closed forms, finite differences and exact integrals."""

from __future__ import annotations

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.materials import KernelMaterial, kernel_table
from corneasim.solver import elements as el
from corneasim.solver.elements._constitutive import cube_root, inverse_cube_root

from elements_helpers import RHO, cauchy_closed_form, grid_hex, grid_quad, materials, voigt

KERNELS = ["reference", "fast"]


def evaluate(es, u, dt=0.0, alive=None, history=None):
    n, dim = es.points.shape
    f = np.zeros((n, dim))
    ratio = np.zeros(es.n_elements)
    rates = np.zeros(3)
    history = el.new_history(es) if history is None else history
    alive = np.ones(es.n_elements, np.uint8) if alive is None else alive
    el.eval_internal_forces(es, u, dt, alive, history, f, ratio, rates)
    return f, ratio, rates, history


def interior(points):
    lo, hi = points.min(axis=0), points.max(axis=0)
    return np.all((points > lo + 1e-9) & (points < hi - 1e-9), axis=1)


@pytest.mark.parametrize("kernel", KERNELS)
def test_quad_patch_test_homogeneous_axisymmetric_field(kernel):
    points, cells = grid_quad(3, 3, jitter=0.25)
    table = materials()
    es = el.prepare(points, cells, "quad", np.zeros(len(cells), int), table, kernel=kernel)
    a, b, c = 0.15, -0.1, 0.2  # u_r = a r, u_z = b z + c r
    u = np.stack([a * points[:, 0], b * points[:, 1] + c * points[:, 0]], axis=1)
    F = np.array([[1 + a, 0, 0], [c, 1 + b, 0], [0, 0, 1 + a]])
    f, *_ , history = evaluate(es, u)
    sigma = el.element_stress(es, u, history)
    expected = voigt(cauchy_closed_form(F, table[0]))
    assert np.allclose(sigma, expected[None, :], rtol=0, atol=1e-13 * np.abs(expected).max())
    # homogeneous stress is an axisymmetric equilibrium state only if sigma_rr = sigma_thth
    # and sigma_rz = 0 (d sigma_rz/dr + sigma_rz/r = 0): the force check takes c = 0
    u[:, 1] = b * points[:, 1]
    f, *_ = evaluate(es, u)
    assert np.abs(f[interior(points)]).max() < 1e-12 * np.abs(f).max()


@pytest.mark.parametrize("kernel", KERNELS)
def test_hex_patch_test_homogeneous_field(kernel):
    points, cells = grid_hex(2, jitter=0.3)
    table = materials()
    es = el.prepare(points, cells, "hexahedron", np.zeros(len(cells), int), table, kernel=kernel)
    F = np.array([[1.2, 0.1, -0.05], [0.08, 0.9, 0.12], [-0.1, 0.05, 1.1]])
    u = points @ (F - np.eye(3)).T
    f, *_, history = evaluate(es, u)
    sigma = el.element_stress(es, u, history)
    expected = voigt(cauchy_closed_form(F, table[0]))
    assert np.allclose(sigma, expected[None, :], rtol=0, atol=1e-13 * np.abs(expected).max())
    assert np.abs(f[interior(points)]).max() < 1e-12 * np.abs(f).max()


@pytest.mark.parametrize("kernel", KERNELS)
def test_rigid_motions_give_zero_force(kernel):
    table = materials()
    points, cells = grid_quad(3, 2, jitter=0.3)
    es = el.prepare(points, cells, "quad", np.zeros(len(cells), int), table, kernel=kernel)
    u = np.zeros_like(points)
    u[:, 1] = 0.7
    f, *_ = evaluate(es, u, dt=0.01)  # a rigid step: no volume change, no bulk viscosity
    f_ref, *_ = evaluate(es, points * 0.01)
    assert np.abs(f).max() < 1e-12 * np.abs(f_ref).max()
    points, cells = grid_hex(2, jitter=0.3)
    es = el.prepare(points, cells, "hexahedron", np.zeros(len(cells), int), table, kernel=kernel)
    axis = np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5])
    K = np.cross(np.eye(3), axis)
    R = np.eye(3) + np.sin(1.1) * K + (1 - np.cos(1.1)) * K @ K  # 63 degree rotation
    u = points @ (R - np.eye(3)).T + np.array([0.3, -0.2, 0.5])
    f, *_ = evaluate(es, u)
    u_strained = points @ np.diag([0.01, 0, 0])
    f_ref, *_ = evaluate(es, u_strained)
    assert np.abs(f).max() < 1e-10 * np.abs(f_ref).max()


def finite_difference_forces(es, u, h=1e-6):
    grad = np.zeros_like(u)
    for n in range(u.shape[0]):
        for i in range(u.shape[1]):
            up, um = u.copy(), u.copy()
            up[n, i] += h
            um[n, i] -= h
            grad[n, i] = (el.stored_energy(es, up) - el.stored_energy(es, um)) / (2 * h)
    return grad


@pytest.mark.parametrize("cell_type", ["quad", "hexahedron"])
def test_forces_are_the_energy_gradient(cell_type):
    if cell_type == "quad":
        points, cells = grid_quad(2, 2, jitter=0.3)
    else:
        points, cells = grid_hex(1)
        points = points + 0.15 * np.random.default_rng(3).uniform(-1, 1, points.shape)
    table = materials()
    es = el.prepare(points, cells, cell_type, np.zeros(len(cells), int), table,
                    hourglass_coefficient=0.3, kernel="reference")
    rng = np.random.default_rng(1)
    u = 0.08 * rng.uniform(-1, 1, points.shape)
    if cell_type == "quad":
        u[points[:, 0] == 0.0, 0] = 0.0
    f, *_ = evaluate(es, u)
    fd = finite_difference_forces(es, u)
    assert np.abs(f - fd).max() < 1e-7 * np.abs(f).max()
    es0 = el.prepare(points, cells, cell_type, np.zeros(len(cells), int), table,
                     hourglass_coefficient=0.0, kernel="reference")
    f0, *_ = evaluate(es0, u)
    assert np.abs(f - f0).max() > 1e-4 * np.abs(f).max()  # the hourglass part was exercised


@pytest.mark.parametrize("kernel", KERNELS)
def test_uniaxial_large_stretch_of_one_hexahedron(kernel):
    points, cells = grid_hex(1, size=1.0)
    table = materials()
    es = el.prepare(points, cells, "hexahedron", [0], table, kernel=kernel)
    stretch, lateral = 1.8, 0.76
    F = np.diag([lateral, lateral, stretch])
    u = points @ (F - np.eye(3)).T
    f, *_, history = evaluate(es, u)
    expected = cauchy_closed_form(F, table[0])
    sigma = el.element_stress(es, u, history)[0]
    assert np.allclose(sigma, voigt(expected), rtol=1e-13, atol=1e-13 * np.abs(expected).max())
    top = points[:, 2] == 1.0  # reaction = P_zz * reference area = sigma_zz * lateral^2
    assert np.isclose(f[top, 2].sum(), expected[2, 2] * lateral**2, rtol=1e-13)


@pytest.mark.parametrize("kernel", KERNELS)
def test_uniaxial_large_stretch_of_one_axisymmetric_quad(kernel):
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    table = materials()
    es = el.prepare(points, [[0, 1, 2, 3]], "quad", [0], table, kernel=kernel)
    stretch, lateral = 1.8, 0.76
    u = np.stack([(lateral - 1) * points[:, 0], (stretch - 1) * points[:, 1]], axis=1)
    f, *_, history = evaluate(es, u)
    expected = cauchy_closed_form(np.diag([lateral, stretch, lateral]), table[0])
    sigma = el.element_stress(es, u, history)[0]
    assert np.allclose(sigma, voigt(expected), rtol=1e-13, atol=1e-13 * np.abs(expected).max())
    top = points[:, 1] == 1.0  # full-ring reaction = sigma_zz * pi (lateral R)^2
    assert np.isclose(f[top, 1].sum(), expected[1, 1] * np.pi * lateral**2, rtol=1e-13)


@pytest.mark.parametrize("kernel", KERNELS)
def test_prony_relaxation_under_held_stretch(kernel):
    g, tau = (0.3, 0.2, 0.1, 0.15), (0.01, 0.1, 1.0, 10.0)
    table = materials(prony_g=g, prony_tau=tau)
    points, cells = grid_hex(1, size=1.0)
    es = el.prepare(points, cells, "hexahedron", [0], table, kernel=kernel)
    F = np.diag([0.85, 0.85, 1.4])
    u = points @ (F - np.eye(3)).T
    f, ratio, rates, history = evaluate(es, u, dt=0.0)  # the stretch appears at t = 0
    dt, t = 0.0037, 0.0
    for _ in range(300):
        evaluate(es, u, dt=dt, history=history)
        t += dt
    relax = 1 - sum(g) + sum(gi * np.exp(-t / ti) for gi, ti in zip(g, tau))
    volumetric = cauchy_closed_form(F, table[0], relax=0.0)
    expected = volumetric + relax * (cauchy_closed_form(F, table[0]) - volumetric)
    assert np.allclose(el.element_stress(es, u, history)[0], voigt(expected), rtol=1e-12,
                       atol=1e-12 * np.abs(expected).max())


@pytest.mark.parametrize("kernel", KERNELS)
def test_relaxed_steps_give_the_long_term_stress_then_the_instantaneous_increment(kernel):
    """A relaxed stage (every Prony term relaxed within each step) ends in the long-term stress
    sigma_vol + g_inf sigma_iso; held there, ordinary steps change nothing (no creep); an
    increment F1 -> F2 at once adds sum g_i (S0(F2) - S0(F1)) pushed forward by F2."""
    g, tau = (0.3, 0.2, 0.1, 0.15), (0.01, 0.1, 1.0, 10.0)
    table = materials(prony_g=g, prony_tau=tau)
    points, cells = grid_hex(1, size=1.0)
    es = el.prepare(points, cells, "hexahedron", [0], table, kernel=kernel)
    F1 = np.array([[0.9, 0.1, 0.0], [0.0, 0.95, 0.05], [0.02, 0.0, 1.25]])
    history = el.new_history(es)
    n, dim = points.shape
    for fraction in (0.3, 0.7, 1.0):  # ramp with relaxed steps of any length
        u = points @ (fraction * (F1 - np.eye(3))).T
        el.eval_internal_forces(es, u, 0.004 * fraction, np.ones(1, np.uint8), history,
                                np.zeros((n, dim)), np.zeros(1), np.zeros(3), relaxed=True)
    u1 = points @ (F1 - np.eye(3)).T
    long_term = cauchy_closed_form(F1, table[0], relax=1 - sum(g))
    scale = np.abs(long_term).max()
    assert np.allclose(el.element_stress(es, u1, history)[0], voigt(long_term), rtol=1e-12,
                       atol=1e-12 * scale)
    for _ in range(20):
        evaluate(es, u1, dt=0.37, history=history)
    assert np.allclose(el.element_stress(es, u1, history)[0], voigt(long_term), rtol=1e-12,
                       atol=1e-12 * scale)
    F2 = F1 @ np.array([[1.03, 0.0, 0.02], [0.0, 0.99, 0.0], [0.0, 0.01, 0.98]])
    u2 = points @ (F2 - np.eye(3)).T
    evaluate(es, u2, dt=0.0, history=history)
    J1, J2 = np.linalg.det(F1), np.linalg.det(F2)
    iso1 = cauchy_closed_form(F1, table[0]) - cauchy_closed_form(F1, table[0], relax=0.0)
    S0_1 = J1 * np.linalg.inv(F1) @ iso1 @ np.linalg.inv(F1).T
    expected = cauchy_closed_form(F2, table[0]) - sum(g) * F2 @ S0_1 @ F2.T / J2
    assert np.allclose(el.element_stress(es, u2, history)[0], voigt(expected), rtol=1e-12,
                       atol=1e-12 * scale)


@pytest.mark.parametrize("cell_type", ["quad", "hexahedron"])
def test_stable_time_step_of_a_cube(cell_type):
    h = 0.25
    table = materials()
    points, cells = grid_quad(1, 1, width=h, height=h, r0=2.0) if cell_type == "quad" else grid_hex(1, size=h)
    for b1 in (0.0, 0.06):
        es = el.prepare(points, cells, cell_type, [0], table, bulk_viscosity_linear=b1)
        material = KernelMaterial(density=RHO, c10=0.05, c01=0.02, c20=0.3, c30=0.1, d1=0.2)
        # hexahedron: Flanagan-Belytschko bound h / sqrt(3); quad: area / longest diagonal
        length = h / np.sqrt(3) if cell_type == "hexahedron" else h / np.sqrt(2)
        expected = length / material.wave_speed * (np.sqrt(1 + b1**2) - b1)
        assert np.isclose(el.stable_time_steps(es, np.zeros_like(points))[0], expected, rtol=1e-12)
    if cell_type == "hexahedron":  # uniform dilatation by 1.1: L = 1.1 h / sqrt(3), K J with J = 1.1^3
        stretched = el.stable_time_steps(es, 0.1 * points)[0]
        modulus = material.bulk_modulus * 1.1**3 + 4 / 3 * material.initial_shear_modulus
        expected = 1.1 * h / np.sqrt(3) / np.sqrt(modulus / RHO) * (np.sqrt(1 + 0.06**2) - 0.06)
        assert np.isclose(stretched, expected, rtol=1e-12)


def test_lumped_mass_is_density_times_volume():
    points, cells = grid_quad(3, 3, jitter=0.3)
    es = el.prepare(points, cells, "quad", np.zeros(len(cells), int), materials())
    ring_volume = 2 * np.pi * 2.0**2 / 2 * 2.0  # 2 pi * integral of r dA over [0,2]^2
    assert np.isclose(el.lumped_masses(es).sum(), RHO * ring_volume, rtol=1e-13)
    assert np.isclose(el.lumped_masses(es, np.full(len(cells), 4.0)).sum(), 4 * RHO * ring_volume,
                      rtol=1e-13)
    points, cells = grid_hex(2, jitter=0.3)
    es = el.prepare(points, cells, "hexahedron", np.zeros(len(cells), int), materials())
    assert np.isclose(el.lumped_masses(es).sum(), RHO * 8.0, rtol=1e-13)
    assert np.all(el.lumped_masses(es) > 0)


@pytest.mark.parametrize("kernel", KERNELS)
def test_dead_elements_carry_no_force_and_keep_history(kernel):
    table = materials(prony_g=(0.4,), prony_tau=(0.1,))
    points, cells = grid_hex(2, jitter=0.2)
    es = el.prepare(points, cells, "hexahedron", np.zeros(len(cells), int), table, kernel=kernel)
    u = 0.05 * np.random.default_rng(0).uniform(-1, 1, points.shape)
    alive = np.ones(len(cells), np.uint8)
    alive[[2, 5]] = 0
    f, ratio, _, history = evaluate(es, u, dt=1e-3, alive=alive)
    assert np.all(history[0, :, [2, 5]] == 0.0) and np.any(history[0, :, 0] != 0.0)
    assert np.all(ratio[[2, 5]] == 0.0)
    keep = alive.astype(bool)
    es_kept = el.prepare(points, cells[keep], "hexahedron", np.zeros(keep.sum(), int), table,
                         kernel=kernel)
    f_kept, *_ = evaluate(es_kept, u, dt=1e-3)
    assert np.allclose(f, f_kept, rtol=0, atol=1e-13 * np.abs(f).max())


@pytest.mark.parametrize("kernel", KERNELS)
def test_failure_ratios_of_the_criterion_and_of_none(kernel):
    points, cells = grid_hex(1, size=1.0)
    F = np.array([[1.3, 0.2, 0.0], [0.1, 0.9, 0.05], [0.0, -0.1, 1.05]])
    u = points @ (F - np.eye(3)).T
    rows = [KernelMaterial(density=RHO, c10=0.05, c01=0.02, c20=0.3, c30=0.1, d1=0.2,
                           failure_criterion=code, failure_limit=0.5) for code in (1, 0)]
    table = kernel_table(rows)
    sigma = cauchy_closed_form(F, table[0])
    s = sigma - np.trace(sigma) / 3 * np.eye(3)
    expected = [np.sqrt(1.5 * np.sum(s * s)) / 0.5, 0.0]
    for m in range(2):
        es = el.prepare(points, cells, "hexahedron", [m], table, kernel=kernel)
        _, ratio, *_ = evaluate(es, u)
        assert np.isclose(ratio[0], expected[m], rtol=1e-12)


@pytest.mark.parametrize("kernel", KERNELS)
def test_bulk_viscosity_of_a_uniform_compression_step(kernel):
    """x = lambda(t) X with J = exp(rate t): the volumetric rate from J over one step is
    rate to O((rate dt)^2); the bulk-viscous pressure q = rate (b1 rho c_d L + rho (b2 L)^2
    |rate|) does power q rate J V, which the viscous forces deliver as f . v."""
    points, cells = grid_hex(1, size=1.0)
    table = materials()
    rate, dt = -50.0, 1e-5  # 1/s, s
    stretch = np.exp(rate * dt / 3.0)
    u = (stretch - 1.0) * points
    v = rate / 3.0 * (points + u)  # the velocity of this motion, at the new time
    results = {}
    for b1, b2 in ((0.06, 1.2), (0.0, 0.0)):
        es = el.prepare(points, cells, "hexahedron", [0], table, bulk_viscosity_linear=b1,
                        bulk_viscosity_quadratic=b2, kernel=kernel)
        results[b1] = evaluate(es, u, dt=dt)
    c_d = KernelMaterial(density=RHO, c10=0.05, c01=0.02, c20=0.3, c30=0.1, d1=0.2).wave_speed
    q = rate * (0.06 * RHO * c_d * 1.0 + RHO * 1.2**2 * abs(rate))
    J = stretch**3
    assert np.isclose(results[0.06][2][1], q * rate * J, rtol=1e-6)
    viscous = results[0.06][0] - results[0.0][0]
    assert np.isclose(np.sum(viscous * v), q * rate * J, rtol=1e-6)  # viscous power = f . v
    es = el.prepare(points, cells, "hexahedron", [0], table, kernel=kernel)
    _, _, again, _ = evaluate(es, u, history=results[0.06][3].copy())  # dt = 0: stored rate
    assert np.isclose(again[1], q * rate * J, rtol=1e-6)


@pytest.mark.parametrize("kernel", KERNELS)
@pytest.mark.parametrize("cell_type", ["quad", "hexahedron"])
def test_hourglass_energy_is_the_stored_hourglass_energy(kernel, cell_type):
    """The kernel's hourglass energy equals stored_energy with minus without hourglass
    stiffness, an independent computation of k_e |gamma . u|^2 / 2."""
    table = materials()
    if cell_type == "quad":
        points, cells = grid_quad(3, 3, jitter=0.2)
    else:
        points, cells = grid_hex(2, jitter=0.2)
    rng = np.random.default_rng(3)
    u = 0.02 * rng.uniform(-1, 1, points.shape)
    if cell_type == "quad":
        u[points[:, 0] == 0.0, 0] = 0.0
    material = np.zeros(len(cells), int)
    with_hg = el.prepare(points, cells, cell_type, material, table, kernel=kernel,
                         hourglass_coefficient=0.3)
    without = el.prepare(points, cells, cell_type, material, table, hourglass_coefficient=0.0)
    _, _, rates, _ = evaluate(with_hg, u)
    expected = el.stored_energy(with_hg, u) - el.stored_energy(without, u)
    assert expected > 0.0
    assert np.isclose(rates[0], expected, rtol=1e-10)


def test_helpers_cube_root():
    # the truth in long double (libm's cbrtl): numpy's float64 cbrt may take a vector library
    # with an error of a few ulp on some processors, as large as the one tested here
    x = np.geomspace(0.05, 20.0, 4000)
    exact = np.cbrt(x.astype(np.longdouble))
    assert np.allclose([cube_root(xi) for xi in x], exact, rtol=2e-15, atol=0.0)
    # the fast kernels' Newton iteration: round-off over the range its docstring states
    J = np.geomspace(0.105, 7.5, 4000)
    exact = 1.0 / np.cbrt(J.astype(np.longdouble))
    assert np.allclose([inverse_cube_root(j) for j in J], exact, rtol=1e-15, atol=0.0)


def test_bad_input_raises_one_line_input_errors():
    points, cells = grid_hex(1)
    table = materials()
    with pytest.raises(InputError, match="cell_type"):
        el.prepare(points, cells, "tetra", [0], table)
    with pytest.raises(InputError, match="element 0"):
        el.prepare(points, cells[:, [1, 0, 3, 2, 5, 4, 7, 6]], "hexahedron", [0], table)
    with pytest.raises(InputError, match="element_material"):
        el.prepare(points, cells, "hexahedron", [3], table)
    with pytest.raises(InputError, match="r < 0"):
        el.prepare(np.array([[-1.0, 0], [1, 0], [1, 1], [-1, 1]]), [[0, 1, 2, 3]], "quad", [0], table)


def test_free_hexahedron_is_stable_just_below_its_stable_step():
    """Random velocities on a free, distorted hexahedron at 0.95 of the stable step: bounded energy."""
    from corneasim.materials import KernelMaterial
    from corneasim.mesh import Mesh
    from corneasim.solver import build_model, new_state, run

    points, cells = grid_hex(1, size=0.25, jitter=0.2)
    mesh = Mesh(points, cells, "hexahedron", np.zeros(len(cells), np.int64), ["m"])
    material = KernelMaterial(density=RHO, c10=0.05, d1=0.2)
    probe = build_model(mesh, {"m": material}, safety_factor=1.0, bulk_viscosity_linear=0.0,
                        bulk_viscosity_quadratic=0.0)
    dt = 0.95 * probe.stable_time_step()[0]
    model = build_model(mesh, {"m": material}, safety_factor=0.95, time_step=dt,
                        bulk_viscosity_linear=0.0, bulk_viscosity_quadratic=0.0)
    velocity = np.random.default_rng(3).normal(size=points.shape)
    state = new_state(model, velocity=velocity)
    energies = [row.history["kinetic_energy_mJ"] + row.history["internal_energy_mJ"]
                for row in run(model, state, end_time=3000 * dt, history_every=100) if row.history]
    assert max(energies) < 1.5 * energies[0]
