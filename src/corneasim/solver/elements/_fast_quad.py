"""Fast axisymmetric quad kernel: SIMD across the elements of a block.

Same mathematics as ``_reference.internal_forces_reference`` (``docs/elements.md``), with
the material law of ``materials.kernel`` inlined, arranged for the compiler (the rules that
keep such loops vectorised: ``docs/performance.md``): for each block of
B = QUAD_BLOCK_SIZE elements the nodal displacements and the material constants with this
step's Prony factors are gathered into a flat per-thread scratch array ``s``; short
straight-line loops over the B lanes (the passes of ``_lanes``) then read ``s`` and the
block's rows of the flat block-major geometry and history arrays, all at compile-time
offsets ``row * B`` (so LLVM proves the rows independent and emits vector code), with
J^{-1/3} by Newton's iteration instead of libm; finally forces are scattered into the
force rows of the block's part (``_reduce``). Dead and padding lanes are masked by
multiplication (their F is replaced by the identity so that nothing overflows).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from corneasim.materials.kernel import (
    M_BULK, M_C01, M_C10, M_C20, M_C30, M_DISSIPATION, M_FIBRE_COS, M_FIBRE_K1, M_FIBRE_K2,
    M_FIBRE_KAPPA, M_FIBRE_SIN, M_INVERSE_LIMIT, M_LONG_TERM, M_PRONY_A, M_PRONY_B, N_PACKED,
    fibre_pk2, isochoric_pk2, prony_step, volumetric_factor, von_mises)
from corneasim.solver.elements._constitutive import inverse_cube_root
from corneasim.solver.elements._layout import QUAD_BLOCK_SIZE as B
from corneasim.solver.elements._rate import volumetric_rate
from corneasim.solver.elements._schedule import active_threads, claim_part, use_threads

N_GEOMETRY = 20  # b_r(4) b_z(4) hoop(4) gamma(4) V k bv1 bv2
N_FRAME = 2  # fibre frame rows: the bisector (m_r, m_z) in the section; n is the hoop direction
N_HISTORY = 22  # S0bar (4), h_1..h_4 (4 each): (rr, zz, thth, rz); J^n - 1; edot
HJ, HEDOT = 20, 21  # history rows of the volumetric rate (``_api.volumetric_rate``)
# scratch rows (each B long); XR, XZ hold displacements (F = I + sum u_a b_a)
XR, XZ, MASK = 0, 4, 8
MAT = 9  # M_FIBRE_K1 rows: the material row (``_kernel_form.M_*``) with this step's Prony factors
RATIO = MAT + M_FIBRE_K1
KF11, KF12, KF21, KF22, KF33, KJ, KJM23, KIJ = range(RATIO + 1, RATIO + 9)  # pass results
KS11, KS22, KS33, KS12 = range(KIJ + 1, KIJ + 5)  # second Piola-Kirchhoff stress
# the fibre constants (M_FIBRE_K1 .. N_PACKED - 1) after the rows above, which keep the offsets
# of a kernel without fibres (``_gather``)
FIB = KS12 + 1
FK1, FK2, FKAPPA, FCOS, FSIN = (FIB + M_FIBRE_K1 - M_FIBRE_K1, FIB + M_FIBRE_K2 - M_FIBRE_K1,
                                FIB + M_FIBRE_KAPPA - M_FIBRE_K1, FIB + M_FIBRE_COS - M_FIBRE_K1,
                                FIB + M_FIBRE_SIN - M_FIBRE_K1)
N_SCRATCH = FIB + N_PACKED - M_FIBRE_K1
FR, FZ = XR, XZ  # forces overwrite u (same lane, after its last read)
# geometry rows, read in place from the flat block-major geometry array
BR, BZ, HOOP, GAM, VOL, KHG, BV1, BV2 = 0, 4, 8, 12, 16, 17, 18, 19


@njit(cache=True, inline="always")
def _row4(a, row, l):
    """The four entries (one per node) of rows ``row .. row + 3`` of lane l (inlined, so
    the offsets stay compile-time constants)."""
    return a[row * B + l], a[(row + 1) * B + l], a[(row + 2) * B + l], a[(row + 3) * B + l]


@njit(cache=True, fastmath=True, error_model="numpy")
def _kinematics(s, g):
    """Pass 1: F (dead lanes: identity) and J into ``s``.

    F = I + sum_a u_a (x) b_a in the (r, z) plane, F_33 = 1 + sum_a u_ra h_a (hoop).
    """
    for l in range(B):
        m = s[MASK * B + l]
        xr0, xr1, xr2, xr3 = _row4(s, XR, l)
        xz0, xz1, xz2, xz3 = _row4(s, XZ, l)
        br0, br1, br2, br3 = _row4(g, BR, l)
        bz0, bz1, bz2, bz3 = _row4(g, BZ, l)
        hp0, hp1, hp2, hp3 = _row4(g, HOOP, l)
        F11 = 1.0 + m * (xr0 * br0 + xr1 * br1 + xr2 * br2 + xr3 * br3)
        F12 = m * (xr0 * bz0 + xr1 * bz1 + xr2 * bz2 + xr3 * bz3)
        F21 = m * (xz0 * br0 + xz1 * br1 + xz2 * br2 + xz3 * br3)
        F22 = 1.0 + m * (xz0 * bz0 + xz1 * bz1 + xz2 * bz2 + xz3 * bz3)
        F33 = 1.0 + m * (xr0 * hp0 + xr1 * hp1 + xr2 * hp2 + xr3 * hp3)
        J = F33 * (F11 * F22 - F12 * F21)
        s[KF11 * B + l] = F11
        s[KF12 * B + l] = F12
        s[KF21 * B + l] = F21
        s[KF22 * B + l] = F22
        s[KF33 * B + l] = F33
        s[KJ * B + l] = J


@njit(cache=True, fastmath=True, error_model="numpy")
def _cube_root(s):
    """Pass 2: J^{-2/3} = y^2 and 1/J = y^3 into ``s`` with y = J^{-1/3}
    (``_constitutive.inverse_cube_root``). The iteration is one long chain of dependent
    operations, so it has a short loop of its own in which the processor overlaps lanes."""
    for l in range(B):
        y = inverse_cube_root(s[KJ * B + l])
        s[KJM23 * B + l] = y * y
        s[KIJ * B + l] = y * y * y


@njit(cache=True, fastmath=True, error_model="numpy")
def _stress(s, g, h, fr, viscous):
    """Pass 3: the second Piola-Kirchhoff stress with the Prony update, into ``s``.

    S = J K (J - 1) C^-1 + g_inf S0 + sum_i h_i, S0 the instantaneous isochoric stress of
    the kernel family (``docs/elements.md``) and h_i the Prony history (exact recursive
    update with d = S0^{n+1} - S0^n). ``viscous`` False skips the Prony terms of a block
    whose materials have none (their history stays zero: the same result, without reading
    or writing 16 of the 22 history rows). ``fr``, the block's fibre frame rows (None for a
    mesh without fibre materials), adds to S0 the fibre families a_(1,2) = (c m_r, c m_z, +-s):
    both have the same I4 (C has no r-theta or z-theta entries), so their (rr, zz, thth, rz)
    stresses are equal and their r-theta and z-theta stresses cancel (no twist); lanes
    without fibres have k1 = 0. Returns the viscoelastic dissipation power, mJ/s.
    """
    e_ve = 0.0
    for l in range(B):
        m = s[MASK * B + l]
        F11, F12, F21, F22, F33 = (s[KF11 * B + l], s[KF12 * B + l], s[KF21 * B + l],
                                   s[KF22 * B + l], s[KF33 * B + l])
        J = s[KJ * B + l]
        Jm23 = s[KJM23 * B + l]
        iJ = s[KIJ * B + l]
        D = F11 * F22 - F12 * F21
        C11 = F11 * F11 + F21 * F21
        C22 = F12 * F12 + F22 * F22
        C12 = F11 * F12 + F21 * F22
        C33 = F33 * F33
        c10 = s[(MAT + M_C10) * B + l]
        c01 = s[(MAT + M_C01) * B + l]
        c20 = s[(MAT + M_C20) * B + l]
        c30 = s[(MAT + M_C30) * B + l]
        K = s[(MAT + M_BULK) * B + l]
        ginf = s[(MAT + M_LONG_TERM) * B + l]
        idet = iJ * iJ * C33  # 1 / (C11 C22 - C12^2) = F33^2 / J^2
        i11 = C22 * idet
        i22 = C11 * idet
        i12 = -C12 * idet
        i33 = (D * iJ) * (D * iJ)  # 1 / F33^2
        S0_11, S0_22, S0_33, S0_12, _, _ = isochoric_pk2(
            C11, C22, C33, C12, 0.0, 0.0, i11, i22, i33, i12, 0.0, 0.0, Jm23, c10, c01, c20, c30)
        if fr is not None:  # pruned by Numba when fr is None: the isotropic code
            c = s[FCOS * B + l]
            f11, f22, f33, f12, _, _ = fibre_pk2(
                C11, C22, C33, C12, 0.0, 0.0, i11, i22, i33, i12, 0.0, 0.0, Jm23,
                c * fr[l], c * fr[B + l], s[FSIN * B + l],
                s[FK1 * B + l], s[FK2 * B + l], s[FKAPPA * B + l])
            S0_11 += 2.0 * f11
            S0_22 += 2.0 * f22
            S0_33 += 2.0 * f33
            S0_12 += 2.0 * f12
        pv = volumetric_factor(J, K)
        S11 = pv * i11 + ginf * S0_11
        S22 = pv * i22 + ginf * S0_22
        S33 = pv * i33 + ginf * S0_33
        S12 = pv * i12 + ginf * S0_12
        d11 = S0_11 - h[l]
        d22 = S0_22 - h[B + l]
        d33 = S0_33 - h[2 * B + l]
        d12 = S0_12 - h[3 * B + l]
        h[l] += m * d11
        h[B + l] += m * d22
        h[2 * B + l] += m * d33
        h[3 * B + l] += m * d12
        hh = 0.0
        if viscous:  # loop-invariant: LLVM unswitches the loop
            for i in range(4):
                a_i = 1.0 + m * (s[(MAT + M_PRONY_A + i) * B + l] - 1.0)  # a dead lane keeps h_i
                b_i = m * s[(MAT + M_PRONY_B + i) * B + l]
                r = 4 * (i + 1) * B + l
                p11, p22, p33, p12 = h[r], h[r + B], h[r + 2 * B], h[r + 3 * B]
                n11 = prony_step(a_i, b_i, p11, d11)
                n22 = prony_step(a_i, b_i, p22, d22)
                n33 = prony_step(a_i, b_i, p33, d33)
                n12 = prony_step(a_i, b_i, p12, d12)
                h[r], h[r + B], h[r + 2 * B], h[r + 3 * B] = n11, n22, n33, n12
                S11 += n11
                S22 += n22
                S33 += n33
                S12 += n12
                hh += s[(MAT + M_DISSIPATION + i) * B + l] * (
                    n11 * n11 + n22 * n22 + n33 * n33 + 2.0 * n12 * n12)
        s[KS11 * B + l] = S11
        s[KS22 * B + l] = S22
        s[KS33 * B + l] = S33
        s[KS12 * B + l] = S12
        e_ve += m * g[VOL * B + l] * hh
    return e_ve


@njit(cache=True, fastmath=True, error_model="numpy")
def _forces(s, g, h, rate_factor):
    """Pass 4: nodal forces (stress, bulk viscosity, hourglass) and the failure measure
    (the von Mises stress, divided by the limit in ``_scatter``).

    f_a = V (P b_a + P_33 h_a e_r) + k gamma_a (gamma . x) with P = F S + q cof F and the
    bulk-viscous pressure q = edot (b1 rho c L + rho (b2 L)^2 max(-edot, 0)), edot from
    ``_rate.volumetric_rate`` (rate_factor = 2 / dt, 1/s); forces overwrite the displacement
    rows of ``s``. Returns the hourglass energy k |gamma . x|^2 / 2 (mJ; stiffness-type
    hourglass control stores it) and the bulk-viscous power (mJ/s).
    """
    e_hg = 0.0
    e_bv = 0.0
    for l in range(B):
        m = s[MASK * B + l]
        xr0, xr1, xr2, xr3 = _row4(s, XR, l)
        xz0, xz1, xz2, xz3 = _row4(s, XZ, l)
        br0, br1, br2, br3 = _row4(g, BR, l)
        bz0, bz1, bz2, bz3 = _row4(g, BZ, l)
        hp0, hp1, hp2, hp3 = _row4(g, HOOP, l)
        gm0, gm1, gm2, gm3 = _row4(g, GAM, l)
        F11, F12, F21, F22, F33 = (s[KF11 * B + l], s[KF12 * B + l], s[KF21 * B + l],
                                   s[KF22 * B + l], s[KF33 * B + l])
        S11, S22, S33, S12 = s[KS11 * B + l], s[KS22 * B + l], s[KS33 * B + l], s[KS12 * B + l]
        J = s[KJ * B + l]
        iJ = s[KIJ * B + l]
        edot = volumetric_rate(J, h, HJ * B + l, HEDOT * B + l, m, rate_factor)
        D = F11 * F22 - F12 * F21
        cof11 = F22 * F33
        cof12 = -F21 * F33
        cof21 = -F12 * F33
        cof22 = F11 * F33
        q = edot * (g[BV1 * B + l] + g[BV2 * B + l] * max(-edot, 0.0))
        Pm11 = F11 * S11 + F12 * S12
        Pm12 = F11 * S12 + F12 * S22
        Pm21 = F21 * S11 + F22 * S12
        Pm22 = F21 * S12 + F22 * S22
        Pm33 = F33 * S33
        P11 = Pm11 + q * cof11
        P12 = Pm12 + q * cof12
        P21 = Pm21 + q * cof21
        P22 = Pm22 + q * cof22
        P33 = Pm33 + q * D
        qr = gm0 * xr0 + gm1 * xr1 + gm2 * xr2 + gm3 * xr3
        qz = gm0 * xz0 + gm1 * xz1 + gm2 * xz2 + gm3 * xz3
        mV = m * g[VOL * B + l]
        mk = m * g[KHG * B + l]
        s[FR * B + l] = mV * (P11 * br0 + P12 * bz0 + P33 * hp0) + mk * gm0 * qr
        s[(FR + 1) * B + l] = mV * (P11 * br1 + P12 * bz1 + P33 * hp1) + mk * gm1 * qr
        s[(FR + 2) * B + l] = mV * (P11 * br2 + P12 * bz2 + P33 * hp2) + mk * gm2 * qr
        s[(FR + 3) * B + l] = mV * (P11 * br3 + P12 * bz3 + P33 * hp3) + mk * gm3 * qr
        s[FZ * B + l] = mV * (P21 * br0 + P22 * bz0) + mk * gm0 * qz
        s[(FZ + 1) * B + l] = mV * (P21 * br1 + P22 * bz1) + mk * gm1 * qz
        s[(FZ + 2) * B + l] = mV * (P21 * br2 + P22 * bz2) + mk * gm2 * qz
        s[(FZ + 3) * B + l] = mV * (P21 * br3 + P22 * bz3) + mk * gm3 * qz
        e_hg += 0.5 * mk * (qr * qr + qz * qz)
        e_bv += mV * q * edot * J
        s11 = (Pm11 * F11 + Pm12 * F12) * iJ
        s22 = (Pm21 * F21 + Pm22 * F22) * iJ
        s12 = (Pm11 * F21 + Pm12 * F22) * iJ
        s33 = Pm33 * F33 * iJ
        s[RATIO * B + l] = von_mises(s11, s22, s33, s12, 0.0, 0.0)
    return e_hg, e_bv


@njit(cache=True, fastmath=True, error_model="numpy")
def _lanes(s, g, h, fr, rate_factor, viscous):
    """One block's element computations, in four vector passes over its B lanes.

    s: scratch; g, h, fr: this block's rows of the flat geometry, history and fibre frame
    arrays (fr None for a mesh without fibre materials: Numba then compiles the passes
    without the fibre term); viscous: whether a lane's material has Prony terms. Every
    index is a compile-time multiple of B plus the lane, so LLVM can prove the rows
    independent and vectorise (a runtime offset would keep Numba's negative-index check).
    Four short passes instead of one long loop: each lane's work is a long chain of
    dependent operations, and only short loop bodies let the processor overlap lanes.
    rate_factor = 2 / dt (1/s; 0 for an evaluation with dt = 0). Returns the hourglass
    energy (mJ), the bulk-viscous and the viscoelastic power (mJ/s).
    """
    _kinematics(s, g)
    _cube_root(s)
    e_ve = _stress(s, g, h, fr, viscous)
    e_hg, e_bv = _forces(s, g, h, rate_factor)
    return e_hg, e_bv, e_ve


@njit(cache=True, fastmath=True, error_model="numpy")
def _gather(blk, n_e, u, alive, cells, material, block_material, mat, s, loaded):
    """Nodal displacements (``u`` flat, node-major, 2 per node), alive mask and material
    rows into ``s``. The node indices are unsigned: a signed index costs the scalar gather
    Numba's negative-index wraparound (quad kernel 4-10% slower in an A/B timing).

    ``loaded`` is the material whose rows ``s`` already holds (-1: none); returns the
    material now held (-1 after a mixed block)."""
    for a in range(4):
        for l in range(B):
            k = np.uint64(2) * np.uint64(cells[blk, a, l])
            s[(XR + a) * B + l] = u[k]
            s[(XZ + a) * B + l] = u[k + np.uint64(1)]
    base = blk * B
    for l in range(B):
        e = base + l
        s[MASK * B + l] = float(alive[min(e, n_e - 1)]) * (1.0 if e < n_e else 0.0)
    uniform = block_material[blk]
    if uniform >= 0:
        if uniform != loaded:
            for row in range(N_PACKED):
                value = material[uniform, row]
                start = (MAT + row if row < M_FIBRE_K1 else FIB + row - M_FIBRE_K1) * B
                for l in range(B):
                    s[start + l] = value
    else:
        for row in range(N_PACKED):
            start = (MAT + row if row < M_FIBRE_K1 else FIB + row - M_FIBRE_K1) * B
            for l in range(B):
                s[start + l] = material[mat[blk, l], row]
    return uniform


@njit(cache=True, fastmath=True, error_model="numpy")
def _scatter(blk, n_e, cells_target, s, row_forces, failure_ratio):
    """Failure ratios (von Mises stress / limit; 0 for dead lanes) out and forces into the
    force rows."""
    base = blk * B
    for l in range(min(B, n_e - base)):
        failure_ratio[base + l] = (s[RATIO * B + l] * s[MASK * B + l]
                                   * s[(MAT + M_INVERSE_LIMIT) * B + l])
    for l in range(B):
        for a in range(4):
            k = np.uint64(2) * np.uint64(cells_target[blk, a, l])
            row_forces[k] += s[(FR + a) * B + l]
            row_forces[k + np.uint64(1)] += s[(FZ + a) * B + l]


@njit(cache=True, parallel=True, fastmath=True, error_model="numpy")
def quad_internal_forces(u, rate_factor, alive, cells, cells_target, geom, material,
                         block_material, mat, history, part_block, viscous_blocks, fibre_frame,
                         row_forces, scratch, part_energy, failure_ratio):
    """Forces into the rows of ``row_forces`` (``_reduce``), parts claimed by the threads.

    The threads claim parts at run time (``_schedule.claim_part``: in pairs, from both
    ends of a range) and run each whole, its blocks in order, so every row gets the same
    sum whichever thread ran it, on any number of threads; each part's hourglass energy
    and powers go to ``part_energy[p]``. rate_factor = 2 / dt, 1/s. ``cells``
    gathers the displacements, ``cells_target`` places the forces (zero rows on entry).

    geom and history are flat (block-major raveled); material (n_mat, N_PACKED) holds the
    constants and this step's Prony factors (``_kernel_form.packed_constants``);
    block_material (n_blocks,) is the material of a block whose elements share one, else -1.
    viscous_blocks (n_blocks,) uint8: blocks with Prony terms. fibre_frame: flat
    (n_blocks, N_FRAME, B), or None for a mesh without fibre materials, for which Numba
    compiles the kernel without the fibre term (the code of an isotropic kernel; in a mesh
    with fibres, lanes without them have k1 = 0). scratch (nt, N_SCRATCH * B): one row per
    thread; the region runs on nt threads (at most Numba's current count), so a kernel given
    one row wakes no other thread (``_schedule.use_threads``).
    """
    n_e = alive.shape[0]
    nt = scratch.shape[0]
    n_parts = part_energy.shape[0]
    u_flat = u.reshape(u.size)
    saved = active_threads()
    use_threads(min(nt, saved))
    claimed = np.empty((nt + 1) // 2, np.int64)
    for r in range(claimed.size):  # not np.zeros: a parallel kernel makes that a parallel region
        claimed[r] = 0
    for t in prange(nt):
        s = scratch[t]
        loaded = np.int64(-1)
        for taken in range(n_parts):
            p = claim_part(claimed, t, nt, n_parts, taken)
            if p < 0:
                break
            e0 = 0.0
            e1 = 0.0
            e2 = 0.0
            for blk in range(part_block[p], part_block[p + 1]):
                loaded = _gather(blk, n_e, u_flat, alive, cells, material, block_material, mat, s,
                                 loaded)
                g = geom[blk * N_GEOMETRY * B:(blk + 1) * N_GEOMETRY * B]
                h = history[blk * N_HISTORY * B:(blk + 1) * N_HISTORY * B]
                if fibre_frame is None:  # pruned by Numba: a mesh without fibre materials
                    r0, r1, r2 = _lanes(s, g, h, None, rate_factor, viscous_blocks[blk] != 0)
                else:
                    r0, r1, r2 = _lanes(s, g, h, fibre_frame[blk * N_FRAME * B:(blk + 1) * N_FRAME * B],
                                        rate_factor, viscous_blocks[blk] != 0)
                _scatter(blk, n_e, cells_target, s, row_forces, failure_ratio)
                e0 += r0
                e1 += r1
                e2 += r2
            part_energy[p, 0] = e0
            part_energy[p, 1] = e1
            part_energy[p, 2] = e2
    use_threads(saved)
