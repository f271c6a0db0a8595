"""The fibre law in the element kernels against the material-point law and closed forms.

The truth of every stress here is the closed form of the two families in the e1-e2 plane in
its spatial form (``elements_helpers.fibre_cauchy_closed_form``; the library's law is
verified against closed forms and an independent evaluation in ``test_materials_fibre*``)
plus the matrix's closed form, rotated into the element's fibre frame.
"""

from __future__ import annotations

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.materials import KernelMaterial, kernel_table
from corneasim.materials._fibre_law import exp_nonnegative
from corneasim.materials.kernel import P_D1, P_FIBRE_K1
from corneasim.mesh import EyeGeometry, Mesh, lamellar_frames
from corneasim.mesh._lamellae import meridional_tangents
from corneasim.solver import elements as el

from elements_helpers import (
    RHO, cauchy_closed_form, fibre_cauchy_closed_form, grid_hex, grid_quad, voigt)

KERNELS = ["reference", "fast"]
K1, K2, KAPPA, ANGLE = 2.0, 5.0, 0.1, np.deg2rad(30.0)


def fibre_table(**kwargs):
    base = dict(density=RHO, c10=0.025, d1=0.02, fibre_k1=K1, fibre_k2=K2, fibre_kappa=KAPPA,
                fibre_angle=ANGLE)
    base.update(kwargs)
    return kernel_table([KernelMaterial(**base)])


def expected_cauchy(F, frame, table, relax=1.0, angle=ANGLE):
    """Matrix + volumetric closed form plus the material-point fibre stress in the frame (m, n);
    ``relax`` multiplies the isochoric part (matrix and fibres)."""
    m, n = frame[:3], frame[3:]
    R = np.stack([m, n, np.cross(m, n)], axis=1)  # columns: the frame
    row = table[0]
    fibre = R @ fibre_cauchy_closed_form(R.T @ F @ R, K1, K2, KAPPA, angle) @ R.T
    return cauchy_closed_form(F, row, relax) + relax * fibre


def evaluate(es, u, dt=0.0, history=None):
    f = np.zeros_like(es.points)
    history = el.new_history(es) if history is None else history
    el.eval_internal_forces(es, u, dt, np.ones(es.n_elements, np.uint8), history, f,
                            np.zeros(es.n_elements), np.zeros(3))
    return f, history


def element_forces(es, F, sigma):
    """f_a = V P b_a (+ P_thth h_a on u_r for the quad), P = J sigma F^-T (homogeneous F)."""
    P = np.linalg.det(F) * sigma @ np.linalg.inv(F).T
    dim = es.points.shape[1]
    local = np.einsum("ij,aj->ai", P[:dim, :dim], es.b[0]) * es.volume[0]
    if dim == 2:
        local[:, 0] += es.volume[0] * P[2, 2] * es.hoop[0]
    f = np.zeros_like(es.points)
    f[es.cells[0]] = local
    return f


def isochoric_uniaxial(direction, stretch):
    """F = stretch a (x) a + stretch^-1/2 (I - a (x) a) along the unit vector a."""
    A = np.outer(direction, direction)
    return stretch * A + stretch ** -0.5 * (np.eye(3) - A)


def rotation(seed):
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


FAMILY = np.array([np.cos(ANGLE), np.sin(ANGLE), 0.0])  # family 1 in the frame (m, n)
ACROSS = np.array([-np.sin(ANGLE), np.cos(ANGLE), 0.0])  # in-plane, across family 1
HEX_DEFORMATIONS = {
    "uniaxial along a family": isochoric_uniaxial(FAMILY, 1.12),
    "uniaxial across a family": isochoric_uniaxial(ACROSS, 1.12),
    "uniaxial along the bisector": isochoric_uniaxial(np.array([1.0, 0.0, 0.0]), 1.1),
    "equibiaxial in plane": np.diag([1.08, 1.08, 1.08 ** -2]),
    "through the thickness": np.diag([1.15 ** -0.5, 1.15 ** -0.5, 1.15]),
    "compression along the bisector": isochoric_uniaxial(np.array([1.0, 0.0, 0.0]), 0.9),
    "general": np.array([[1.1, 0.06, -0.04], [0.03, 0.95, 0.08], [-0.05, 0.02, 1.04]]),
}


@pytest.mark.parametrize("kernel", KERNELS)
@pytest.mark.parametrize("name", HEX_DEFORMATIONS)
def test_one_hexahedron_in_homogeneous_deformation_has_the_material_point_stress(kernel, name):
    R = rotation(7)  # the frame and the deformation rotated together: any frame orientation
    frame = np.concatenate([R[:, 0], R[:, 1]])
    F = R @ HEX_DEFORMATIONS[name] @ R.T
    points, cells = grid_hex(1, size=0.5)
    table = fibre_table()
    es = el.prepare(points, cells, "hexahedron", [0], table, kernel=kernel, fibre_frame=frame[None])
    u = points @ (F - np.eye(3)).T
    f, history = evaluate(es, u)
    expected = expected_cauchy(F, frame, table)
    scale = np.abs(expected).max()
    # the closed form's own round-off: K (J - 1) with J = det F in floating point, a few ulp of 1
    # times the bulk modulus K = 2 / D1 (here 10^4 times the stress scale)
    volumetric = 2.0 / table[0, P_D1] * 4.0 * np.finfo(float).eps
    assert np.allclose(el.element_stress(es, u, history)[0], voigt(expected), rtol=0,
                       atol=1e-12 * scale + volumetric)
    assert np.allclose(f, element_forces(es, F, expected), rtol=0,
                       atol=1e-12 * np.abs(f).max() + np.abs(element_forces(es, F, volumetric * np.eye(3))).max())
    isotropic = cauchy_closed_form(F, table[0])
    if name in ("through the thickness", "compression along the bisector"):
        assert np.all(expected == isotropic)  # E <= 0 in both families: they do not resist
    else:
        assert np.abs(expected - isotropic).max() > 0.01 * scale  # the fibres carry a share


QUAD_DEFORMATIONS = {  # (m in the section, F (r, z, theta)); F_rr = F_thth for u_r = a r
    "uniaxial along the bisector": ((0.0, 1.0), np.diag([1.1 ** -0.5, 1.1, 1.1 ** -0.5])),
    "equibiaxial in plane": ((1.0, 0.0), np.diag([1.08, 1.08 ** -2, 1.08])),
    "through the thickness": ((1.0, 0.0), np.diag([1.15 ** -0.5, 1.15, 1.15 ** -0.5])),
    "oblique bisector": ((0.6, 0.8), np.array([[1.05, 0.0, 0.0], [0.07, 0.93, 0.0], [0, 0, 1.05]])),
}


@pytest.mark.parametrize("kernel", KERNELS)
@pytest.mark.parametrize("name", QUAD_DEFORMATIONS)
def test_one_axisymmetric_quad_in_homogeneous_deformation_has_the_material_point_stress(kernel, name):
    (m_r, m_z), F = QUAD_DEFORMATIONS[name]
    frame = np.array([m_r, m_z, 0.0, 0.0, 0.0, 1.0])
    points = np.array([[1.0, 0.0], [1.4, 0.0], [1.4, 0.4], [1.0, 0.4]])
    table = fibre_table()
    es = el.prepare(points, [[0, 1, 2, 3]], "quad", [0], table, kernel=kernel, fibre_frame=frame[None])
    u = points @ (F[:2, :2] - np.eye(2)).T
    f, history = evaluate(es, u)
    expected = expected_cauchy(F, frame, table)
    assert abs(expected[0, 2]) + abs(expected[1, 2]) < 1e-14  # the balanced families do not twist
    assert np.allclose(el.element_stress(es, u, history)[0], voigt(expected), rtol=0,
                       atol=1e-12 * np.abs(expected).max())
    assert np.allclose(f, element_forces(es, F, expected), rtol=0, atol=1e-12 * np.abs(f).max())


@pytest.mark.parametrize("kernel", KERNELS)
def test_hex_patch_test_with_the_fibre_law(kernel):
    points, cells = grid_hex(2, jitter=0.3)
    frame = np.tile(np.concatenate([rotation(3)[:, 0], rotation(3)[:, 1]]), (len(cells), 1))
    table = fibre_table()
    es = el.prepare(points, cells, "hexahedron", np.zeros(len(cells), int), table, kernel=kernel,
                    fibre_frame=frame)
    F = HEX_DEFORMATIONS["general"]
    u = points @ (F - np.eye(3)).T
    f, history = evaluate(es, u)
    inner = np.all((points > 1e-9) & (points < 2.0 - 1e-9), axis=1)
    assert np.abs(f[inner]).max() < 1e-12 * np.abs(f).max()
    expected = voigt(expected_cauchy(F, frame[0], table))
    assert np.allclose(el.element_stress(es, u, history), expected[None], rtol=0,
                       atol=1e-12 * np.abs(expected).max())


@pytest.mark.parametrize("kernel", KERNELS)
def test_quad_patch_test_with_the_fibre_law(kernel):
    points, cells = grid_quad(3, 3, r0=0.5, jitter=0.25)
    # lamellae in the r-theta plane, families at 45 degrees from r: sigma_rr = sigma_thth
    frame = np.tile([1.0, 0.0, 0.0, 0.0, 0.0, 1.0], (len(cells), 1))
    table = fibre_table(fibre_angle=np.pi / 4)
    es = el.prepare(points, cells, "quad", np.zeros(len(cells), int), table, kernel=kernel,
                    fibre_frame=frame)
    a, b = 0.06, -0.1  # u_r = a r, u_z = b z: sigma_rr = sigma_thth, sigma_rz = 0 (equilibrium)
    u = np.stack([a * points[:, 0], b * points[:, 1]], axis=1)
    f, history = evaluate(es, u)
    lo, hi = points.min(axis=0), points.max(axis=0)
    inner = np.all((points > lo + 1e-9) & (points < hi - 1e-9), axis=1)
    assert np.abs(f[inner]).max() < 1e-12 * np.abs(f).max()
    expected = voigt(expected_cauchy(np.diag([1 + a, 1 + b, 1 + a]), frame[0], table, angle=np.pi / 4))
    assert np.allclose(el.element_stress(es, u, history), expected[None], rtol=0,
                       atol=1e-12 * np.abs(expected).max())


@pytest.mark.parametrize("kernel", KERNELS)
@pytest.mark.parametrize("cell_type", ["quad", "hexahedron"])
def test_prony_relaxes_the_fibre_stress_of_a_held_stretch(kernel, cell_type):
    g, tau = (0.3, 0.2), (0.01, 0.1)
    table = fibre_table(prony_g=g, prony_tau=tau)
    if cell_type == "quad":  # stretch along z with the bisector along z
        points, cells = np.array([[1.0, 0.0], [1.4, 0.0], [1.4, 0.4], [1.0, 0.4]]), [[0, 1, 2, 3]]
        frame = np.array([0.0, 1.0, 0.0, 0.0, 0.0, 1.0])
        F = np.diag([1.12 ** -0.5, 1.12, 1.12 ** -0.5])
        u = points @ (F[:2, :2] - np.eye(2)).T
    else:
        points, cells = grid_hex(1, size=0.5)
        frame = np.array([1.0, 0.0, 0.0, 0.0, 1.0, 0.0])
        F = isochoric_uniaxial(FAMILY, 1.12)
        u = points @ (F - np.eye(3)).T
    es = el.prepare(points, cells, cell_type, [0], table, kernel=kernel, fibre_frame=frame[None])
    _, history = evaluate(es, u, dt=0.0)  # the stretch appears at t = 0
    dt, t = 0.0021, 0.0
    for _ in range(60):
        evaluate(es, u, dt=dt, history=history)
        t += dt
    relax = 1 - sum(g) + sum(gi * np.exp(-t / ti) for gi, ti in zip(g, tau))
    expected = expected_cauchy(F, frame, table, relax)
    fibre_share = np.abs(expected - cauchy_closed_form(F, table[0], relax)).max()
    assert fibre_share > 0.5 * np.abs(expected - cauchy_closed_form(F, table[0], 0.0)).max()
    assert np.allclose(el.element_stress(es, u, history)[0], voigt(expected), rtol=0,
                       atol=1e-12 * np.abs(expected).max())


@pytest.mark.parametrize("cell_type", ["quad", "hexahedron"])
def test_fibre_forces_are_the_gradient_of_the_stored_energy(cell_type):
    if cell_type == "quad":
        points, cells = grid_quad(2, 2, r0=0.5, jitter=0.3)
        frame = np.tile([0.6, 0.8, 0.0, 0.0, 0.0, 1.0], (len(cells), 1))
    else:
        points, cells = grid_hex(1, size=0.5)
        points = points + 0.05 * np.random.default_rng(3).uniform(-1, 1, points.shape)
        frame = np.tile(np.concatenate([rotation(2)[:, 0], rotation(2)[:, 1]]), (len(cells), 1))
    es = el.prepare(points, cells, cell_type, np.zeros(len(cells), int), fibre_table(),
                    kernel="reference", fibre_frame=frame)
    u = 0.04 * np.random.default_rng(1).uniform(-1, 1, points.shape)
    f, _ = evaluate(es, u)
    fd = np.zeros_like(u)
    h = 1e-6
    for index in np.ndindex(u.shape):
        step = np.zeros_like(u)
        step[index] = h
        fd[index] = (el.stored_energy(es, u + step) - el.stored_energy(es, u - step)) / (2 * h)
    assert np.abs(f - fd).max() < 1e-7 * np.abs(f).max()


def _highest_frequency(es, u):
    """omega_max (1/s) of the lumped-mass central-difference step at u: the tangent stiffness by
    central differences of the internal forces, M^-1/2 K M^-1/2 its largest eigenvalue."""
    n = u.size
    K = np.zeros((n, n))
    h = 1e-7
    for k in range(n):
        step = np.zeros(n)
        step[k] = h
        plus, _ = evaluate(es, u + step.reshape(u.shape))
        minus, _ = evaluate(es, u - step.reshape(u.shape))
        K[:, k] = (plus - minus).ravel() / (2 * h)
    mass = np.repeat(el.lumped_masses(es), u.shape[1])
    scaled = (K + K.T) / 2 / np.sqrt(np.outer(mass, mass))
    return np.sqrt(np.linalg.eigvalsh(scaled).max())


@pytest.mark.parametrize("cell_type", ["quad", "hexahedron"])
def test_stable_step_bounds_the_highest_frequency_of_stretched_fibres(cell_type):
    """Central differences are stable for omega_max dt <= 2: with the fibres' tangent the element
    step satisfies it; the same step without the fibre term (k1 = 0 in the step) does not."""
    table = fibre_table(fibre_k1=2.0, fibre_k2=20.0, fibre_kappa=0.0, fibre_angle=0.0, d1=0.2)
    if cell_type == "quad":
        points, cells = np.array([[1.0, 0.0], [1.3, 0.0], [1.3, 0.3], [1.0, 0.3]]), [[0, 1, 2, 3]]
        frame = np.array([0.0, 1.0, 0.0, 0.0, 0.0, 1.0])  # both families along z
        u = points @ (np.diag([1.15 ** -0.5, 1.15]) - np.eye(2)).T
    else:
        points, cells = grid_hex(1, size=0.3)
        frame = np.array([1.0, 0.0, 0.0, 0.0, 1.0, 0.0])  # both families along x
        u = points @ (isochoric_uniaxial(np.array([1.0, 0.0, 0.0]), 1.15) - np.eye(3)).T
    es = el.prepare(points, cells, cell_type, [0], table, kernel="reference", fibre_frame=frame[None],
                    bulk_viscosity_linear=0.0)
    omega = _highest_frequency(es, u)
    assert omega * el.stable_time_steps(es, u)[0] <= 2.0
    isotropic = table.copy()
    isotropic[0, P_FIBRE_K1] = 0.0
    es_iso = el.prepare(points, cells, cell_type, [0], isotropic, kernel="reference",
                        bulk_viscosity_linear=0.0)
    assert omega * el.stable_time_steps(es_iso, u)[0] > 2.0  # the isotropic bound is too long


def test_vectorising_exp_matches_numpy():
    x = np.concatenate([np.linspace(0.0, 50.0, 2001), np.geomspace(1e-12, 700.0, 500)])
    ours = np.array([exp_nonnegative(v) for v in x])
    assert np.abs(ours / np.exp(x) - 1.0).max() < 2e-15
    assert exp_nonnegative(709.5) == np.inf  # the overflow of e^x, as np.exp's


def test_a_fibre_material_without_a_frame_or_with_a_bad_frame_is_an_input_error():
    points, cells = grid_hex(1)
    table = fibre_table()
    with pytest.raises(InputError, match="fibre_frame: a fibre material"):
        el.prepare(points, cells, "hexahedron", [0], table)
    with pytest.raises(InputError, match="fibre_frame: expected two orthogonal unit vectors"):
        el.prepare(points, cells, "hexahedron", [0], table, fibre_frame=[[1.0, 0, 0, 1.0, 0, 0]])
    quad = np.array([[1.0, 0.0], [1.3, 0.0], [1.3, 0.3], [1.0, 0.3]])
    with pytest.raises(InputError, match="for quads m must lie in the"):
        el.prepare(quad, [[0, 1, 2, 3]], "quad", [0], table, fibre_frame=[[1.0, 0, 0, 0, 1.0, 0]])


CONCENTRIC = EyeGeometry(anterior_radius=7.8, posterior_radius=7.25, central_thickness=0.55,
                         peripheral_thickness=0.55)  # posterior sphere concentric with the anterior


def test_lamellae_of_a_cornea_with_concentric_surfaces_are_the_concentric_spheres():
    rng = np.random.default_rng(5)
    theta = rng.uniform(0.0, 0.6, 50)
    depth = rng.uniform(0.0, 0.55, 50)
    radius = 7.8 - depth
    r, z = radius * np.sin(theta), -7.8 + radius * np.cos(theta)
    tangent = meridional_tangents(CONCENTRIC, r, z)
    assert np.allclose(tangent, np.stack([np.cos(theta), -np.sin(theta)], axis=1), atol=1e-8)


def test_lamellar_frames_of_3d_elements_are_meridional_and_circumferential():
    points, cells = grid_hex(2, size=0.2)
    points = points + np.array([1.5, 1.0, -0.5])  # inside the cornea, off the axes
    mesh = Mesh(points, cells, "hexahedron", np.zeros(len(cells), np.int64), ["stroma"])
    frame = lamellar_frames(mesh, CONCENTRIC)
    centres = points[cells].mean(axis=1)
    phi = np.arctan2(centres[:, 1], centres[:, 0])
    theta = np.arctan2(np.hypot(centres[:, 0], centres[:, 1]), centres[:, 2] + 7.8)
    m = np.stack([np.cos(theta) * np.cos(phi), np.cos(theta) * np.sin(phi), -np.sin(theta)], axis=1)
    n = np.stack([-np.sin(phi), np.cos(phi), np.zeros_like(phi)], axis=1)
    assert np.allclose(frame[:, :3], m, atol=1e-8) and np.allclose(frame[:, 3:], n, atol=1e-15)
    chosen = np.arange(len(cells)) % 2 == 0
    partial = lamellar_frames(mesh, CONCENTRIC, chosen)
    assert np.all(partial[~chosen] == 0.0) and np.allclose(partial[chosen], frame[chosen])


def test_the_needle_scenario_gives_fibre_frames_to_its_fibre_stroma_only():
    from corneasim.scenarios import build, load_scenario

    scenario, _, base = load_scenario("needle", ["mesh.preset=coarse",
                                                 "materials.stroma.material=stroma-hgo"])
    setup = build(scenario, base)
    mesh, frame = setup.mesh, setup.model.elements.fibre_frame
    stroma = mesh.element_block == mesh.block_names.index("stroma")
    assert np.all(frame[~stroma] == 0.0)
    centres = mesh.points[mesh.cells[stroma]].mean(axis=1)
    expected = meridional_tangents(scenario.mesh.geometry, centres[:, 0], centres[:, 1])
    assert np.allclose(frame[stroma, :2], expected) and np.all(frame[stroma, 5] == 1.0)
    apex = centres[:, 0] < 0.05  # near the axis the lamellae are horizontal (m = e_r)
    assert np.all(frame[stroma][apex, 0] > 0.999)
