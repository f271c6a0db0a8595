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
        solve_opening(F, crack, count, radius, STRENGTH, separation, table, 0, a, b, history, 0, 0, scratch, 4, S)
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
