"""Prony-series viscoelasticity on the isochoric second Piola-Kirchhoff stress.

The hyperelastic constants give the *instantaneous* response. Each Prony term i
with normalised weight g_i and time tau_i (s) relaxes a share of the isochoric
stress, so that a step strain held for long times keeps the fraction
``1 - sum g_i`` of the instantaneous deviatoric stress. The update is the one
documented in ``_kernel_form.py``, with the factors and the step of ``_law`` that the
element kernels evaluate too:

.. math::

    S = S_{vol} + (1 - \\textstyle\\sum_i g_i)\\,\\bar S_0 + \\sum_i h_i,\\qquad
    h_i^{n+1} = e^{-\\Delta t/\\tau_i} h_i^n
        + g_i \\frac{1 - e^{-\\Delta t/\\tau_i}}{\\Delta t/\\tau_i}(\\bar S_0^{n+1} - \\bar S_0^n),

exact for any step size when :math:`\\bar S_0` varies linearly within the step
(Simo & Hughes 1998, *Computational Inelasticity*, sec. 10.3; Taylor et al. 2009,
doi:10.1002/cnm.1146).

The needle paper (eq. 2) gives the relaxation function as moduli,
:math:`G(t) = \\sum_i E_i e^{-t/\\tau_i} + E_\\infty`; the normalised weights are
:math:`g_i = E_i / (\\sum_j E_j + E_\\infty)` (:func:`normalised_prony_weights`).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.errors import InputError
from corneasim.materials._kernel_form import MAX_PRONY_TERMS, P_N_PRONY, P_PRONY_G, P_PRONY_TAU
from corneasim.materials._law import prony_factors, prony_step
from corneasim.materials._point import (
    POINT_FRAME, VOIGT_PAIRS, cauchy_from_pk2, elastic_pk2, symmetric_matrix)

HISTORY_SHAPE = (1 + MAX_PRONY_TERMS, 3, 3)
"""Material-point history: previous instantaneous isochoric S (row 0), then one h_i per term (MPa)."""


def normalised_prony_weights(moduli, long_term_modulus: float) -> np.ndarray:
    """Normalised Prony weights g_i = E_i / (sum_j E_j + E_inf).

    Parameters
    ----------
    moduli : sequence of float
        Relaxation moduli E_i, MPa (each >= 0).
    long_term_modulus : float
        Equilibrium modulus E_inf, MPa (> 0).

    Returns
    -------
    numpy.ndarray
        Weights g_i (dimensionless), sum < 1.

    Examples
    --------
    >>> normalised_prony_weights([0.69, 0.43, 0.31, 0.40], 0.43).round(4)
    array([0.3053, 0.1903, 0.1372, 0.177 ])
    """
    moduli = np.asarray(moduli, dtype=np.float64)
    if np.any(moduli < 0.0) or long_term_modulus <= 0.0:
        raise InputError("Prony moduli must be >= 0 MPa and the long-term modulus > 0 MPa")
    return moduli / (moduli.sum() + long_term_modulus)


def new_history() -> np.ndarray:
    """A zero material-point history (reference state), shape ``HISTORY_SHAPE``, MPa."""
    return np.zeros(HISTORY_SHAPE)


@njit(cache=True)
def viscoelastic_stress(F, history, dt, record):
    """Visco-hyperelastic Cauchy stress at one material point (pure function).

    The instantaneous stress is the kernels' (``_point.elastic_pk2``; fibre families in the
    (e1, e2) plane), its isochoric part S0bar relaxed by the Prony terms.

    Parameters
    ----------
    F : numpy.ndarray
        Deformation gradient at the end of the step, (3, 3), dimensionless.
    history : numpy.ndarray
        History at the start of the step, ``HISTORY_SHAPE``, MPa (not modified).
    dt : float
        Step length, s (>= 0).
    record : numpy.ndarray
        Flat :class:`~corneasim.materials.KernelMaterial` record (``as_array()``).

    Returns
    -------
    sigma : numpy.ndarray
        Cauchy stress (3, 3), MPa.
    history_new : numpy.ndarray
        History at the end of the step, ``HISTORY_SHAPE``, MPa.
    """
    J, vol, iso = elastic_pk2(F, record, POINT_FRAME)
    history_new = np.zeros_like(history)
    S = np.empty(6)
    for k in range(6):
        S[k] = vol[k] + iso[k]
    for i in range(int(record[P_N_PRONY])):
        g = record[P_PRONY_G + i]
        a, b = prony_factors(dt, record[P_PRONY_TAU + i], g)
        for k in range(6):
            r, c = VOIGT_PAIRS[k, 0], VOIGT_PAIRS[k, 1]
            h = prony_step(a, b, history[1 + i, r, c], iso[k] - history[0, r, c])
            history_new[1 + i, r, c] = history_new[1 + i, c, r] = h
            S[k] += h - g * iso[k]
    for k in range(6):
        r, c = VOIGT_PAIRS[k, 0], VOIGT_PAIRS[k, 1]
        history_new[0, r, c] = history_new[0, c, r] = iso[k]
    sigma = np.empty(6)
    cauchy_from_pk2(F, S, J, sigma)
    return symmetric_matrix(sigma), history_new
