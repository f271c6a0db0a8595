"""The material point shared by the reference kernels: stress from F with the Prony update.

The law itself (isochoric and volumetric stress, Prony factors and step, failure measure) is
``materials.kernel``, and the instantaneous stress at a 3x3 F with the element's fibre frame
is its ``elastic_pk2``; this module adds the element's Prony history. The second
Piola-Kirchhoff stress of an element is (``materials/_kernel_form.py``)

.. math::

    S = S_{vol} + (1 - \\textstyle\\sum_i g_i)\\,\\bar S_0 + \\sum_i h_i, \\qquad
    h_i^{n+1} = a_i h_i^n + b_i (\\bar S_0^{n+1} - \\bar S_0^n), \\quad
    a_i = e^{-\\Delta t/\\tau_i}, \\; b_i = g_i \\frac{1 - a_i}{\\Delta t/\\tau_i}

(Simo & Hughes 1998, ch. 10; Taylor et al. 2009, doi:10.1002/cnm.1146), where the
instantaneous isochoric stress S0bar is that of the invariant family plus, for a fibre
material, the two fibre families of ``materials._fibre_law`` along
a_(1,2) = cos(angle) m +- sin(angle) n (m, n: the element's fibre frame). The history of an
element holds S0bar^n followed by h_i (one tensor per term, MAX_PRONY_TERMS terms), each of
6 components, or 4 for the axisymmetric quad, then J^n - 1 and the volumetric rate of
``_rate``, in the block-major array ``history[block, field, lane]``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.materials.kernel import (
    MAX_PRONY_TERMS, P_C01, P_C10, P_N_PRONY, P_PRONY_G, P_PRONY_TAU, elastic_pk2, prony_factors,
    prony_step)


@njit(cache=True)
def prony_coefficients(table, dt):
    """a_i = exp(-dt/tau_i) and b_i = g_i (1 - a_i)/(dt/tau_i) per material, (n_mat, 4) each.

    For dt <= 0 the limits a_i = 1, b_i = g_i apply (an evaluation without time passing).
    """
    n = table.shape[0]
    a = np.ones((n, MAX_PRONY_TERMS))
    b = np.zeros((n, MAX_PRONY_TERMS))
    for m in range(n):
        for i in range(int(table[m, P_N_PRONY])):
            a[m, i], b[m, i] = prony_factors(dt, table[m, P_PRONY_TAU + i], table[m, P_PRONY_G + i])
    return a, b


def step_prony_coefficients(table, dt, relaxed=False):
    """:func:`prony_coefficients` of a step, or with ``relaxed`` (and dt > 0) a_i = b_i = 0.

    ``relaxed`` is the limit dt / tau_i -> infinity of every term: the h_i vanish at the end
    of each step and the stress is the long-term one, S_vol + (1 - sum g_i) S0bar, while
    S0bar^n keeps following the deformation. A stage run so (the preload of a slow process)
    ends in the equilibrium a viscoelastic body reaches under a load held for long, and the
    next step's increments meet the full instantaneous response. (n_mat, 4) each.
    """
    if relaxed and dt > 0.0:
        n = table.shape[0]
        return np.zeros((n, MAX_PRONY_TERMS)), np.zeros((n, MAX_PRONY_TERMS))
    return prony_coefficients(table, dt)


@njit(cache=True)
def material_stress(F, table, m, prony_a, prony_b, history, block, lane, update, S, n_comp,
                    frame=None):
    """Second Piola-Kirchhoff stress S (6,) MPa at deformation gradient F (3, 3).

    ``frame`` (6,) is the element's fibre frame (m, n), two orthogonal unit vectors of the
    lamellar plane in the reference configuration (``ElementSet.fibre_frame[e]``); it is read
    only when the material has fibres (k1 > 0), which without it is a ValueError. With ``update`` the Prony history of (block, lane) advances (a time step); without it
    the stored h_i are used as they are (field output). Returns J and the viscoelastic
    dissipation density rate sum_i |h_i|^2 / (2 g_i mu_0 tau_i), MPa/s (the linear Maxwell
    value, an estimate at large strain). The history stores ``n_comp`` components per
    tensor: 6, or 4 (11, 22, 33, 12) for the axisymmetric quad.

    Kernels pass constant arguments typed, ``np.bool_(True)`` and ``np.int64(4)``: Numba compiles
    a literal argument (``True``, ``4``) as a specialisation of its own, so every caller and a
    call from Python share one compiled function (each specialisation costs seconds of compile).
    """
    J, vol, iso = elastic_pk2(F, table[m], frame)
    n_prony = int(table[m, P_N_PRONY])
    g_sum = 0.0
    for i in range(n_prony):
        g_sum += table[m, P_PRONY_G + i]
    mu0 = 2.0 * (table[m, P_C10] + table[m, P_C01])
    dissipation = 0.0
    for k in range(6):
        S[k] = vol[k] + (1.0 - g_sum) * iso[k]
    for i in range(n_prony):
        g = table[m, P_PRONY_G + i]
        hh = 0.0
        for k in range(n_comp):
            field = n_comp * (i + 1) + k
            if update:
                history[block, field, lane] = prony_step(prony_a[m, i], prony_b[m, i],
                                                         history[block, field, lane],
                                                         iso[k] - history[block, k, lane])
            h = history[block, field, lane]
            S[k] += h
            hh += h * h * (1.0 if k < 3 else 2.0)
        if g > 0.0:
            dissipation += hh / (2.0 * g * mu0 * table[m, P_PRONY_TAU + i])
    if update:
        for k in range(n_comp):
            history[block, k, lane] = iso[k]
    return J, dissipation
