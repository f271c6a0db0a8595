"""Smeared radial cracks along the needle's path: the hoop direction of a cut band may crack.

A sharp needle cuts a planar crack (a slit) that its shaft wedges open (Shergold and Fleck,
Proc. R. Soc. A 460 (2004) 3037; Azar and Hayward, MICCAI 2008; Montanari et al., Soft Matter
(2023): puncture is mode-I crack growth in a plane through the needle's axis). Seen in an
axisymmetric model a slit through the axis is ``n`` radial cracks (n = 2; 3 for a
tri-facet point). A round hole opened from a closed axis instead costs the hoop stretch
r / R, without bound at the axis (the cavity expansion of element deletion); radial cracks
leave the material's hoop stretch bounded.

Within the *cut band* (the elements of the cornea within ``band_radius`` of the axis) the
hoop direction, always principal in axisymmetry, may crack. The hoop stretch lambda =
F_thth of an element splits additively into the material's stretch and the opening of its n
cracks, which take up the circumference the material does not cover,

.. math::

    2\\pi R\\,\\lambda = 2\\pi R\\,\\lambda_e + n\\,\\delta, \\qquad
    F_e = F \\text{ with } (F_e)_{\\theta\\theta} = \\lambda_e = \\lambda - \\frac{n\\,\\delta}{2\\pi R},

with R the element's reference radius (V / (2 pi A), the centroid radius: Pappus). This is
the multiplicative split F = F_e F_c, F_c = diag(1, 1, lambda_c), written in the opening:
n delta = 2 pi r (1 - 1 / lambda_c) with r = lambda R. The crack faces carry the traction of
:mod:`corneasim.fracture._law` (extrinsic, delta_0 = 0: the crack starts when the nominal
hoop stress reaches sigma_c, then softens linearly to zero at delta_f = 2 G_c / sigma_c,
unloads on the secant, and a closed crack carries compression), balanced by the material's
nominal (first Piola-Kirchhoff) hoop stress, the force per unit reference area of a radial
plane:

.. math::

    P_{\\theta\\theta}(F_e) = T(\\delta), \\qquad \\delta \\ge 0 .

With W the strain energy of F_e and phi the work of the traction, the element's energy per
unit reference volume is Psi = W(F_e) + n phi(delta) / (2 pi R); the local equation is
dPsi/ddelta = 0 and the element's stress is P(F_e): the work of the nodal forces is the
change of W plus the crack work, and a crack that opens fully dissipates

.. math::

    \\frac{n}{2\\pi R}\\, G_c \\; \\text{per unit reference volume} \\;=\\; n\\, G_c\\, A_e
    \\; \\text{per element}

(A_e the element's area in (r, z)): G_c per unit area of each of the n crack faces, per unit
depth and radial extent, whatever the mesh. The scalar delta is found per element and step:
P_thth falls with delta and the secant traction rises, so on [0, delta_max] the root is
unique (bisection, Illinois); on the envelope the traction falls with delta too, and where
the element's ring is compliant enough for its crack to snap back (R > E n delta_f / (2 pi
sigma_c)) there are several roots: the search marches up from delta_max and takes the first
crossing from P > T to P < T, a stable equilibrium. The energy such a jump releases (Psi
falls at fixed F) would be the unstable crack's kinetic energy; a rate-independent local
law loses it, and the energy balance shows it.

A crack started by the needle's tip instead (:func:`tip_start`, the footprint of a conical
point: :mod:`corneasim.fracture._cut_band`, "The tip's split") keeps the material's hoop stretch
of its start, lambda_e = lambda_s, and its cracks take the rest, n delta = 2 pi R (lambda -
lambda_s), with free faces: the element's nominal hoop stress is 0 while they are open, the
material's at lambda <= lambda_s. Its energy, n G_c per unit crack area, is paid by the
point's drag, not by a traction.

The band's elements are evaluated by :func:`band_forces` with the pointwise law of the
reference material point (``solver.elements._material_point.material_stress``), apart from
the fast kernels (which skip them). The Prony history follows F_e; the bulk viscosity acts
on J_e. Band elements are not deleted (no failure ratio, no distortion erosion): they
separate by their cracks.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from corneasim.fracture._law import dissipated_density, envelope_traction
from corneasim.materials.kernel import MAX_PRONY_TERMS, P_DENSITY
from corneasim.materials.kernel import cauchy_from_pk2
from corneasim.solver.elements._material_point import material_stress
from corneasim.solver.elements._rate import stored_volumetric_rate
from corneasim.solver.elements._reference import _deformation_gradient
from corneasim.solver.elements._time_step import quad_length, wave_modulus

OPENING, OPENING_MAX, STARTED, HOOP_START, N_CRACK_FIELDS = 0, 1, 2, 3, 4
"""Columns of ``State.crack`` (one row per band element): delta and delta_max (mm), how the crack
started (0: not yet; :data:`STRESS_START` or :data:`TIP_START`) and, for a tip start, the
material's hoop stretch lambda_s at the start (dimensionless)."""

STRESS_START, TIP_START = 1.0, 2.0
"""Values of the STARTED column: the nominal hoop stress reached sigma_c, or the needle's tip
reached the element (a split at the apex: module notes)."""

DISSIPATED, STORED, N_OPEN, N_STARTED, N_OUTPUTS = 0, 1, 2, 3, 4
"""Entries of the kernel's output array: dissipated and recoverable crack energy (mJ, the
whole ring), fully open and started cracks (counts)."""

TOLERANCE = 1e-12
"""Relative tolerance of the local solve (of delta_f in the opening, of sigma_c in the traction)."""
MAX_ITERATIONS = 200
"""Iterations of the local solve (doubling and Illinois); reached only by a degenerate state."""
FIRST_STEP = 1e-3
"""The march up the envelope starts with steps of this fraction of delta_f (the first root
within this resolution; doubling afterwards)."""


@njit(cache=True)
def traction(opening, opening_max, started, strength, separation):
    """The crack's traction T (MPa) at the opening ``opening`` (mm) with the largest opening so far
    ``opening_max``: the extrinsic law of :mod:`corneasim.fracture._law` (delta_0 = 0), on the
    envelope beyond delta_max and on the secant below it; sigma_c at delta = 0 before any opening."""
    if opening > opening_max:
        return envelope_traction(opening, strength, 0.0, separation)
    if opening_max > 0.0:
        return envelope_traction(opening_max, strength, 0.0, separation) * opening / opening_max
    return strength if started else 0.0


@njit(cache=True)
def hoop_stress(F, opening, count, radius, table, m, prony_a, prony_b, history, block, lane, scratch,
                n_comp, S, update, frame):
    """Nominal hoop stress P_thth (MPa) of the material at F_e (module notes); S (6,) receives its
    second Piola-Kirchhoff stress; ``frame`` (6,) is the element's fibre frame (``material_stress``).
    Without ``update`` the Prony step is taken on ``scratch`` (a copy of the element's history), so
    the history is not changed. Returns P_thth, J_e and the
    viscoelastic dissipation density rate (MPa/s, ``material_stress``)."""
    total = F[2, 2]
    stretch = total - count * opening / (2.0 * math.pi * radius)
    if stretch <= 0.0:
        return -math.inf, 0.0, 0.0
    F[2, 2] = stretch  # F_e in place (restored below): no allocation in the local solve
    if update:
        J, dissipation = material_stress(F, table, m, prony_a, prony_b, history, block, lane, np.bool_(True), S,
                                         n_comp, frame)
    else:
        for k in range(history.shape[1]):
            scratch[0, k, 0] = history[block, k, lane]
        J, dissipation = material_stress(F, table, m, prony_a, prony_b, scratch, np.int64(0), np.int64(0),
                                         np.bool_(True), S, n_comp, frame)
    F[2, 2] = total
    return stretch * S[2], J, dissipation


@njit(cache=True)
def _residual(F, opening, opening_max, started, count, radius, strength, separation, table, m,
              prony_a, prony_b, history, block, lane, scratch, n_comp, S, frame):
    """g(delta) = P_thth(F_e(delta)) - T(delta), MPa (falls with delta on the secant)."""
    P, _, _ = hoop_stress(F, opening, count, radius, table, m, prony_a, prony_b, history, block, lane,
                          scratch, n_comp, S, np.bool_(False), frame)
    return P - traction(opening, opening_max, started, strength, separation)


@njit(cache=True)
def _illinois(F, lo, g_lo, hi, g_hi, opening_max, started, count, radius, strength, separation,
              table, m, prony_a, prony_b, history, block, lane, scratch, n_comp, S, frame):
    """The root of g in [lo, hi] with g(lo) > 0 > g(hi): regula falsi with the Illinois
    modification (Dowell and Jarratt, BIT 11 (1971) 168), bisecting when it stalls."""
    side = 0
    for _ in range(MAX_ITERATIONS):
        if hi - lo <= TOLERANCE * separation:
            break
        x = (lo * g_hi - hi * g_lo) / (g_hi - g_lo)
        if not (lo < x < hi):
            x = 0.5 * (lo + hi)
        g = _residual(F, x, opening_max, started, count, radius, strength, separation, table, m,
                      prony_a, prony_b, history, block, lane, scratch, n_comp, S, frame)
        if abs(g) <= TOLERANCE * strength:
            return x
        if g > 0.0:
            lo, g_lo = x, g
            if side == 1:
                g_hi *= 0.5
            side = 1
        else:
            hi, g_hi = x, g
            if side == -1:
                g_lo *= 0.5
            side = -1
    return 0.5 * (lo + hi)


@njit(cache=True)
def solve_opening(F, crack, count, radius, strength, separation, table, m, prony_a, prony_b, history,
                  block, lane, scratch, n_comp, S, frame):
    """The opening delta (mm) of the element's cracks at F (3, 3): the local equation
    P_thth(F_e) = T(delta) (module notes). ``crack`` (N_CRACK_FIELDS,) holds delta, delta_max
    and the started flag of the last step and receives the new ones."""
    opening_max = crack[OPENING_MAX]
    if crack[STARTED] == TIP_START:  # split by the tip: the cracks take the hoop stretch beyond lambda_s
        opening = max(0.0, (F[2, 2] - crack[HOOP_START]) * 2.0 * math.pi * radius / count)
        crack[OPENING] = opening
        crack[OPENING_MAX] = max(opening_max, opening)
        return
    started = crack[STARTED] != 0.0
    if not started:
        P, _, _ = hoop_stress(F, 0.0, count, radius, table, m, prony_a, prony_b, history, block, lane,
                              scratch, n_comp, S, np.bool_(False), frame)
        if P <= strength:
            crack[OPENING] = 0.0
            return
        started = True
        crack[STARTED] = STRESS_START
    g0 = _residual(F, 0.0, opening_max, started, count, radius, strength, separation, table, m,
                   prony_a, prony_b, history, block, lane, scratch, n_comp, S, frame)
    if g0 <= 0.0:  # closed: the faces carry compression (or sit at the peak before opening)
        crack[OPENING] = 0.0
        return
    if opening_max > 0.0:
        g_max = _residual(F, opening_max, opening_max, started, count, radius, strength, separation,
                          table, m, prony_a, prony_b, history, block, lane, scratch, n_comp, S, frame)
        if g_max <= 0.0:  # on the secant: one root in (0, delta_max]
            crack[OPENING] = _illinois(F, 0.0, g0, opening_max, g_max, opening_max, started, count, radius,
                                       strength, separation, table, m, prony_a, prony_b, history, block,
                                       lane, scratch, n_comp, S, frame)
            return
        lo, g_lo = opening_max, g_max
    else:
        lo, g_lo = 0.0, g0
    # loading: march up the envelope to the first crossing (the material's stretch stays > 0)
    limit = F[2, 2] * 2.0 * math.pi * radius / count
    step = FIRST_STEP * separation
    if crack[OPENING] > opening_max:
        step = min(step, crack[OPENING] - opening_max)
    hi, g_hi = lo, g_lo
    for _ in range(MAX_ITERATIONS):
        hi = min(lo + step, lo + 0.5 * (limit - lo))
        g_hi = _residual(F, hi, opening_max, started, count, radius, strength, separation, table, m, prony_a,
                         prony_b, history, block, lane, scratch, n_comp, S, frame)
        if g_hi <= 0.0:
            break
        lo, g_lo = hi, g_hi
        step *= 2.0
    opening = _illinois(F, lo, g_lo, hi, g_hi, opening_max, started, count, radius, strength, separation,
                        table, m, prony_a, prony_b, history, block, lane, scratch, n_comp, S, frame)
    crack[OPENING] = opening
    crack[OPENING_MAX] = max(opening_max, opening)


@njit(cache=True)
def tip_start(cells, b, hoop, points, u, band, radius, footprint, tip, crack):
    """Start the cracks of the band elements the needle's tip has reached (module notes): those
    not started yet whose reference radius R is below ``footprint`` (the shaft's radius, mm) and
    whose highest node lies above ``tip`` (the tip's height z, mm): the apex has entered the
    element's level, where it wedges the footprint's nodes apart. Each records its hoop
    stretch F_thth as lambda_s. Returns how many started."""
    F = np.empty((3, 3))
    started = 0
    for k in range(band.shape[0]):
        if crack[k, STARTED] != 0.0 or radius[k] >= footprint:
            continue
        e = band[k]
        z = -math.inf
        for a in range(4):
            z = max(z, points[cells[e, a], 1] + u[cells[e, a], 1])
        if z < tip:
            continue
        _deformation_gradient(cells, b, hoop, u, e, F)
        crack[k, STARTED] = TIP_START
        crack[k, HOOP_START] = F[2, 2]
        started += 1
    return started


@njit(cache=True)
def band_forces(cells, b, hoop, gamma, volume, hourglass_stiffness, bulk_linear, bulk_quadratic,
                element_material, table, fibre_frame, prony_a, prony_b, block_size, u, dt, alive, history,
                band, radius, strength, separation, count, crack, scratch, f_int, energy_rates, out):
    """Internal forces of the band's elements (added to ``f_int``), their crack state and Prony
    history advanced; the energies into ``energy_rates`` (added) and ``out`` (module notes).

    Parameters
    ----------
    cells, b, hoop, gamma, volume, hourglass_stiffness, bulk_linear, bulk_quadratic,
    element_material, table : ndarray
        The element set's reference data (``solver.elements.ElementSet``).
    fibre_frame : ndarray (n_elements, 6)
        The lamellar frame (m, n) of each element (``ElementSet.fibre_frame``; zero rows for a
        material without fibres). The band's hoop direction is n: the fibres see F_e.
    prony_a, prony_b : ndarray (n_materials, MAX_PRONY_TERMS)
        Prony factors of the step (``step_prony_coefficients``).
    block_size : int
    u : ndarray (n_nodes, 2)
        Displacement, mm.
    dt : float
        The step just taken, s (0: evaluate without advancing the rates).
    alive : ndarray (n_elements,) uint8
    history : ndarray
        The element history; the band elements' rows are advanced.
    band : ndarray (n_band,) int64
        Band elements.
    radius, strength, separation : ndarray (n_band,) float64
        R (mm), sigma_c (MPa) and delta_f (mm) per band element.
    count : float
        n, the number of radial cracks.
    crack : ndarray (n_band, N_CRACK_FIELDS) float64
        In/out: the crack state.
    scratch : ndarray (1, n_history, 1) float64
        Scratch history of the local solve.
    f_int : ndarray (n_nodes, 2)
        In/out: internal forces, N.
    energy_rates : ndarray (3,)
        In/out: the band's hourglass energy (mJ) and bulk-viscous and viscoelastic power (mJ/s) added.
    out : ndarray (N_OUTPUTS,)
        Out: crack energies (mJ) and counts.
    """
    n_comp = np.int64(4)
    F = np.empty((3, 3))
    S = np.empty(6)
    rates = history.shape[1] - 2
    out[:] = 0.0
    for k in range(band.shape[0]):
        e = band[k]
        if not alive[e]:
            continue
        m = element_material[e]
        blk, lane = e // block_size, e % block_size
        frame = fibre_frame[e]
        _deformation_gradient(cells, b, hoop, u, e, F)
        solve_opening(F, crack[k], count, radius[k], strength[k], separation[k], table, m, prony_a,
                      prony_b, history, blk, lane, scratch, n_comp, S, frame)
        opening = crack[k, OPENING]
        _, J, dissipation = hoop_stress(F, opening, count, radius[k], table, m, prony_a, prony_b, history,
                                        blk, lane, scratch, n_comp, S, np.bool_(True), frame)
        area = volume[e] / (2.0 * math.pi * radius[k])
        tip = crack[k, STARTED] == TIP_START
        if crack[k, STARTED] != 0.0:
            out[N_STARTED] += 1.0
        if crack[k, STARTED] == STRESS_START:
            opening_max = crack[k, OPENING_MAX]
            if opening_max >= separation[k]:
                out[N_OPEN] += 1.0
            out[DISSIPATED] += count * area * dissipated_density(opening_max, strength[k], 0.0, separation[k])
            out[STORED] += count * area * 0.5 * opening * traction(opening, opening_max, np.bool_(True), strength[k],
                                                                  separation[k])
        stretch = F[2, 2] - count * opening / (2.0 * math.pi * radius[k])
        edot = stored_volumetric_rate(J, history, blk, lane, rates, dt)
        q = edot * (bulk_linear[e] + bulk_quadratic[e] * max(-edot, 0.0))
        # P = F_e S + q J F_e^-T, F_e = [[F_rr, F_rz, 0], [F_zr, F_zz, 0], [0, 0, lambda_e]]
        qJ = q * J / (F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0])
        P_rr = F[0, 0] * S[0] + F[0, 1] * S[3] + qJ * F[1, 1]
        P_rz = F[0, 0] * S[3] + F[0, 1] * S[1] - qJ * F[1, 0]
        P_zr = F[1, 0] * S[0] + F[1, 1] * S[3] - qJ * F[0, 1]
        P_zz = F[1, 0] * S[3] + F[1, 1] * S[1] + qJ * F[0, 0]
        if tip and opening > 0.0:  # split by the tip: lambda_e held at lambda_s, free faces
            P_hoop = 0.0
        else:
            P_hoop = stretch * S[2] + q * J / stretch
        V = volume[e]
        for a in range(4):
            node = cells[e, a]
            f_int[node, 0] += V * (P_rr * b[e, a, 0] + P_rz * b[e, a, 1] + P_hoop * hoop[e, a])
            f_int[node, 1] += V * (P_zr * b[e, a, 0] + P_zz * b[e, a, 1])
        stiffness = hourglass_stiffness[e]
        for mode in range(gamma.shape[1]):
            for i in range(2):
                qx = 0.0
                for a in range(4):
                    qx += gamma[e, mode, a] * u[cells[e, a], i]
                for a in range(4):
                    f_int[cells[e, a], i] += stiffness * gamma[e, mode, a] * qx
                energy_rates[0] += 0.5 * stiffness * qx * qx
        energy_rates[1] += q * edot * J * V
        energy_rates[2] += dissipation * V


@njit(cache=True)
def band_stress(cells, b, hoop, element_material, table, fibre_frame, block_size, u, history, band, radius,
                count, crack, cauchy):
    """Cauchy stress (MPa) of the band's elements into their rows of ``cauchy`` (n_elements, 6):
    that of F_e with the stored openings and Prony history (field output; module notes)."""
    F = np.empty((3, 3))
    S = np.empty(6)
    sigma = np.empty(6)
    prony = np.zeros((table.shape[0], MAX_PRONY_TERMS))
    for k in range(band.shape[0]):
        e = band[k]
        _deformation_gradient(cells, b, hoop, u, e, F)
        F[2, 2] -= count * crack[k, OPENING] / (2.0 * math.pi * radius[k])
        J, _ = material_stress(F, table, element_material[e], prony, prony, history, e // block_size,
                               e % block_size, np.bool_(False), S, np.int64(4), fibre_frame[e])
        cauchy_from_pk2(F, S, J, sigma)
        for i in range(6):  # element by element: a slice copy compiles a shape check's message
            cauchy[e, i] = sigma[i]


@njit(cache=True)
def band_time_steps(points, cells, b, hoop, element_material, table, fibre_frame, u, b1, band, radius, count,
                    crack, out):
    """Stable time steps (s) of the band's elements into their rows of ``out`` (n_elements,): those
    of ``solver.elements._time_step`` with the material's F_e, whose J_e leaves out the cracks'
    volume (the total J of an open crack would inflate the bulk wave speed K max(J, 1)), and for a
    fibre material the fibres' bound M_f at F_e (``_time_step.wave_modulus``)."""
    F = np.empty((3, 3))
    factor = np.sqrt(1.0 + b1 * b1) - b1
    for k in range(band.shape[0]):
        e = band[k]
        _deformation_gradient(cells, b, hoop, u, e, F)
        F[2, 2] -= count * crack[k, OPENING] / (2.0 * math.pi * radius[k])
        J = F[2, 2] * (F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0])
        m = element_material[e]
        modulus = wave_modulus(F[0, 0], F[0, 1], F[0, 2], F[1, 0], F[1, 1], F[1, 2], F[2, 0], F[2, 1], F[2, 2],
                               J, table[m], fibre_frame[e])
        out[e] = quad_length(points, u, cells, e) / np.sqrt(modulus / table[m, P_DENSITY]) * factor
