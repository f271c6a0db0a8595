"""Smeared radial cracks of the cut band: the local law against its closed-form traction-separation
curve, the dissipated energy of an expanded ring against n G_c x area, and the energy balance."""

import math

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.fracture import CutAxis, RadialCracks, attach_radial_cracks, band_elements
from corneasim.fracture._radial_cracks import N_CRACK_FIELDS, OPENING, OPENING_MAX, STARTED, solve_opening
from corneasim.materials import KernelMaterial, kernel_table
from corneasim.solver import Prescribed, build_model, new_state, run
from corneasim.solver._amplitudes import Constant
from corneasim.solver._integrate import ENERGY_DAMPING, ENERGY_INTERNAL, ENERGY_REACTION
from corneasim.solver.elements._material_point import prony_coefficients
from corneasim.solver.elements._reference import _deformation_gradient
from test_solver_meshes import box_quad

C10, BULK = 0.5, 50.0  # MPa: neo-Hooke, K = 2 / D1
MATERIAL = KernelMaterial(density=1e-9, c10=C10, d1=2.0 / BULK)
HEAVY = KernelMaterial(density=1e-2, c10=C10, d1=2.0 / BULK)  # quasi-static rings in few steps
STRENGTH, TOUGHNESS = 0.4, 0.1  # MPa, N/mm: delta_f = 0.5 mm
NO_FRAME = np.zeros(6)  # the fibre frame of a material without fibres
# a fibre stroma: families at +-45 degrees from the meridian m = e_z in the (z, theta) plane
K1, K2, KAPPA, ANGLE = 2.0, 20.0, 0.1, math.radians(45.0)  # MPa, 1, 1, rad
FIBRE = KernelMaterial(density=1e-9, c10=C10, d1=2.0 / BULK, fibre_k1=K1, fibre_k2=K2, fibre_kappa=KAPPA,
                       fibre_angle=ANGLE)
FRAME = np.array([0.0, 1.0, 0.0, 0.0, 0.0, 1.0])  # (m, n): m = e_z, n = e_theta


def nominal_hoop_stress(stretch_r, stretch_z, stretch):
    """P_thth of the compressible neo-Hooke law W = C10 (I1bar - 3) + K (J - 1)^2 / 2 at the
    principal stretches (closed form, MPa)."""
    J = stretch_r * stretch_z * stretch
    I1 = stretch_r ** 2 + stretch_z ** 2 + stretch ** 2
    return (C10 * J ** (-2.0 / 3.0) * (2.0 * stretch - 2.0 / 3.0 * I1 / stretch)
            + BULK * (J - 1.0) * J / stretch)


def bilinear(opening, opening_max):
    """The extrinsic bilinear law written out: envelope sigma_c (1 - delta / delta_f), secant below
    delta_max (MPa)."""
    separation = 2.0 * TOUGHNESS / STRENGTH
    envelope = lambda d: STRENGTH * max(0.0, 1.0 - d / separation)
    if opening >= opening_max:
        return envelope(opening)
    return envelope(opening_max) * opening / opening_max


def test_the_local_solve_follows_the_closed_form_traction_separation_curve():
    """Drive the hoop stretch of one material point up, down, up past full opening: at every
    state P_thth(F_e) equals the bilinear law's T(delta) (envelope on loading, secant on unloading,
    zero once open; a closed crack carries compression) and the crack starts at sigma_c."""
    table = kernel_table([MATERIAL])
    a, b = prony_coefficients(table, 0.0)
    history = np.zeros((1, 22, 1))
    scratch = np.zeros((1, 22, 1))
    S = np.empty(6)
    crack = np.zeros(N_CRACK_FIELDS)
    radius, count = 0.02, 2.0
    separation = 2.0 * TOUGHNESS / STRENGTH
    path = np.concatenate([np.linspace(1.0, 1.6, 61), np.linspace(1.6, 1.1, 26), np.linspace(1.1, 0.95, 7),
                           np.linspace(0.95, 15.0, 300)])
    started_at = None
    loaded = unloaded = opened = closed = 0
    for stretch in path:
        F = np.diag([0.98, 0.99, stretch])
        before = crack[OPENING_MAX]
        solve_opening(F, crack, count, radius, STRENGTH, separation, table, 0, a, b, history, 0, 0, scratch, 4, S,
                      NO_FRAME)
        opening = crack[OPENING]
        material = stretch - count * opening / (2 * math.pi * radius)
        P = nominal_hoop_stress(0.98, 0.99, material)
        if crack[STARTED] and started_at is None:
            started_at = stretch
            assert nominal_hoop_stress(0.98, 0.99, stretch) >= STRENGTH
            assert nominal_hoop_stress(0.98, 0.99, stretch - 0.01) < STRENGTH
        if not crack[STARTED]:
            assert opening == 0.0 and P <= STRENGTH
            continue
        if opening == 0.0:
            assert P <= bilinear(0.0, crack[OPENING_MAX]) + 1e-12
            closed += 1
            continue
        assert P == pytest.approx(bilinear(opening, crack[OPENING_MAX]), abs=1e-9)
        if opening >= separation:
            opened += 1
        elif opening >= before:
            loaded += 1
        else:
            unloaded += 1
    assert started_at is not None and loaded > 5 and unloaded > 5 and opened > 5 and closed > 0


def fibre_hoop_stress(stretch_r, stretch_z, stretch):
    """P_thth = dW/dlambda_thth of the compressible HGO law W = C10 (I1bar - 3) + K (J - 1)^2 / 2
    + sum_i k1 / (2 k2) (exp(k2 E_i^2) - 1), E_i = kappa (I1bar - 3) + (1 - 3 kappa)(I4bar_i - 1)
    (E_i > 0), with both families a_i = cos t e_z +- sin t e_theta at the principal stretches
    (closed form, MPa)."""
    J = stretch_r * stretch_z * stretch
    I1 = stretch_r ** 2 + stretch_z ** 2 + stretch ** 2
    I4 = math.cos(ANGLE) ** 2 * stretch_z ** 2 + math.sin(ANGLE) ** 2 * stretch ** 2
    Jm23 = J ** (-2.0 / 3.0)
    dI1b = Jm23 * (2.0 * stretch - 2.0 / 3.0 * I1 / stretch)
    dI4b = Jm23 * (2.0 * math.sin(ANGLE) ** 2 * stretch - 2.0 / 3.0 * I4 / stretch)
    E = KAPPA * (Jm23 * I1 - 3.0) + (1.0 - 3.0 * KAPPA) * (Jm23 * I4 - 1.0)
    fibres = 2.0 * K1 * E * math.exp(K2 * E * E) * (KAPPA * dI1b + (1.0 - 3.0 * KAPPA) * dI4b) if E > 0 else 0.0
    return nominal_hoop_stress(stretch_r, stretch_z, stretch) + fibres


def test_a_fibre_stroma_cracks_where_its_fibres_carry_the_closed_form_hoop_stress():
    """A band point of a fibre material, its hoop stretch driven up, down and up past full
    opening: the crack starts when the closed-form HGO nominal hoop stress (fibres of the
    element's frame included) reaches sigma_c, and at every cracked state P_thth(F_e) of that
    closed form equals the bilinear T(delta)."""
    table = kernel_table([FIBRE])
    a, b = prony_coefficients(table, 0.0)
    history, scratch = np.zeros((1, 22, 1)), np.zeros((1, 22, 1))
    S = np.empty(6)
    crack = np.zeros(N_CRACK_FIELDS)
    radius, count, strength = 0.2, 2.0, 0.6  # mm, 1, MPa
    side = 1.0 / math.sqrt(1.2)  # F_rr = F_zz: J = 1 at the hoop stretch 1.2
    separation = 2.0 * TOUGHNESS / strength
    path = np.concatenate([np.linspace(1.0, 1.4, 81), np.linspace(1.4, 1.25, 16), np.linspace(1.25, 3.0, 200)])
    started_at = None
    checked = 0
    for stretch in path:
        F = np.diag([side, side, stretch])
        solve_opening(F, crack, count, radius, strength, separation, table, 0, a, b, history, 0, 0, scratch, 4, S,
                      FRAME)
        opening = crack[OPENING]
        if crack[STARTED] and started_at is None:
            started_at = stretch
            assert fibre_hoop_stress(side, side, stretch) >= strength
            assert fibre_hoop_stress(side, side, stretch - 0.005) < strength
            # the matrix alone would not have reached the strength: the fibres start the crack
            assert nominal_hoop_stress(side, side, stretch) < strength
        if not crack[STARTED] or opening == 0.0:
            continue
        material = stretch - count * opening / (2 * math.pi * radius)
        envelope = lambda d: strength * max(0.0, 1.0 - d / separation)
        expected = envelope(opening) if opening >= crack[OPENING_MAX] else (
            envelope(crack[OPENING_MAX]) * opening / crack[OPENING_MAX])
        assert fibre_hoop_stress(side, side, material) == pytest.approx(expected, abs=1e-8)
        checked += 1
    assert started_at is not None and checked > 100 and crack[OPENING_MAX] >= separation


def test_the_band_step_of_a_fibre_stroma_has_the_fibres_wave_modulus():
    """At rest the stable step of a band element of side h is (h / sqrt 2) / c (sqrt(1 + b1^2) - b1)
    with rho c^2 = K + 4/3 (2 C10) + 8 k1, the two fibre families' bound at rest (4 k1 each); the
    band's step and the fast kernels' agree on it."""
    mesh = box_quad(2, 2, 0.0, 0.02, 0.0, 0.02)
    model = build_model(mesh, {"solid": FIBRE}, [], fibre_frame=np.tile(FRAME, (mesh.n_elements, 1)))
    cracks = RadialCracks(model.elements, np.arange(mesh.n_elements), np.full(mesh.n_elements, STRENGTH),
                          np.full(mesh.n_elements, TOUGHNESS), 2)
    attach_radial_cracks(model, cracks)
    state = new_state(model)
    out = np.zeros(mesh.n_elements)
    cracks.stable_time_steps(state, out)
    b1 = model.elements.bulk_viscosity_linear
    modulus = BULK + 4.0 / 3.0 * 2.0 * C10 + 8.0 * K1
    expected = 0.01 / math.sqrt(2.0) / math.sqrt(modulus / FIBRE.density) * (math.sqrt(1 + b1 ** 2) - b1)
    assert out == pytest.approx(np.full(mesh.n_elements, expected), rel=1e-12)


def ring(n_r=6, inner=0.2, outer=0.5, height=0.1, n_z=2):
    """An annulus r in [inner, outer], z in [0, height] of quads, all in the cut band."""
    return box_quad(n_r, n_z, inner, outer, 0.0, height)


def expanded_ring(mesh, count, stretch_rate, end_time):
    """Model of ``mesh`` with every element in the band, its radial edges pulled at u_r = rate r t."""
    conditions = [Prescribed("r0", "r", "velocity", stretch_rate * mesh.points[mesh.node_sets["r0"], 0].max(), Constant(1.0)),
                  Prescribed("r1", "r", "velocity", stretch_rate * mesh.points[mesh.node_sets["r1"], 0].max(), Constant(1.0))]
    model = build_model(mesh, {"solid": HEAVY}, conditions)
    band = np.arange(mesh.n_elements)
    cracks = RadialCracks(model.elements, band, np.full(band.size, STRENGTH), np.full(band.size, TOUGHNESS), count)
    attach_radial_cracks(model, cracks)
    return model, cracks


@pytest.mark.parametrize("count", [2, 3])
def test_an_expanded_ring_dissipates_n_toughness_per_crack_area(count):
    """Open every crack of a thick ring fully (its hole and outer edge pulled outwards): the
    dissipated energy is n G_c times the ring's area in (r, z), and the work of the pulling
    reactions is that plus what stays in the ring (internal energy less the cracks' dissipation,
    kinetic and damping energies): the energy balance."""
    mesh = ring()
    model, cracks = expanded_ring(mesh, count, 2.0, 1.0)
    state = new_state(model)
    hook = CutAxis(model, np.zeros(0, np.int64))
    for frame in run(model, state, 1.0, history_every=200, hooks=[hook], damping=300.0):
        pass
    row = frame.history
    area = 0.3 * 0.1
    assert row["cut_open_elements"] == mesh.n_elements
    assert row["cut_dissipated_energy_mJ"] == pytest.approx(count * TOUGHNESS * area, rel=0.02)
    energies = state.energies
    left = energies[ENERGY_INTERNAL] + row["kinetic_energy_mJ"] + energies[ENERGY_DAMPING]
    assert energies[ENERGY_REACTION] == pytest.approx(left, rel=2e-3)
    # the internal work is the cracks' energy plus the elastic energy of the material's own stretch
    elastic = elastic_energy(model, state, count)
    cracks_energy = row["cut_dissipated_energy_mJ"] + row["cut_stored_energy_mJ"]
    assert energies[ENERGY_INTERNAL] == pytest.approx(elastic + cracks_energy + row["hourglass_energy_mJ"]
                                                      + row["viscous_energy_mJ"], rel=5e-3)


def elastic_energy(model, state, count):
    """sum_e V_e W(F_e) of the closed-form neo-Hooke law, F_e from the elements' mean gradients
    and their cracks' openings, mJ."""
    elements = model.elements
    cracks = model.radial_cracks
    F = np.empty((3, 3))
    total = 0.0
    for k, e in enumerate(cracks.band):
        _deformation_gradient(elements.cells, elements.b, elements.hoop, state.u, e, F)
        F[2, 2] -= count * state.crack[k, OPENING] / (2 * math.pi * cracks.radius[k])
        J = np.linalg.det(F)
        I1 = np.sum(F * F)
        total += elements.volume[e] * (C10 * (J ** (-2.0 / 3.0) * I1 - 3.0) + 0.5 * BULK * (J - 1.0) ** 2)
    return total


def test_the_band_must_reach_the_axis_and_the_law_needs_positive_constants():
    mesh = box_quad(4, 2, 0.0, 0.4, 0.0, 0.1)
    with pytest.raises(InputError, match="band_radius"):
        band_elements(mesh, ["solid"], 0.01)
    assert band_elements(mesh, ["solid"], 0.15).size == 4


@pytest.mark.parametrize("zeta", [0.0, 0.1])
def test_a_held_axis_node_rings_down_at_the_contacts_damping_ratio(zeta):
    """A held axis node displaced 1 um off the axis, integrated by central differences under
    the axis penalty alone: its velocity amplitude decays as exp(-zeta omega t) (the damped
    oscillator's closed form, omega = sqrt(k / m), k = beta m / dt^2); undamped it keeps ringing."""
    from corneasim.fracture._cut_band import AXIS_PENALTY_FRACTION, axis_forces
    mass, dt = np.array([2e-9]), 1e-6
    u, v = np.array([[1e-3, 0.0]]), np.zeros((1, 2))
    nodes, held = np.zeros(1, np.int64), np.ones(1, np.uint8)
    omega = math.sqrt(AXIS_PENALTY_FRACTION) / dt
    steps = int(round(10 * 2 * math.pi / omega / dt))  # ten periods
    speeds = []
    for n in range(steps):
        f = np.zeros((1, 2))
        v_mid = v.copy()
        axis_forces(u, v_mid, mass, nodes, held, AXIS_PENALTY_FRACTION / dt ** 2, zeta, f)
        v += f / mass[0] * dt
        u += v * dt
        speeds.append(abs(v[0, 0]))
    period = int(round(2 * math.pi / omega / dt))
    first, last = max(speeds[:period]), max(speeds[-period:])
    assert first > 1e-3 * omega * 0.9  # the node rings at first (peak speed ~ omega x 1 um)
    expected = math.exp(-zeta * omega * (steps - period) * dt)
    assert last / first == pytest.approx(expected, rel=0.1, abs=0.01)
