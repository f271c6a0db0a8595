"""The volumetric strain rate that drives bulk viscosity, from J over the last step.

.. math::

    \\dot\\varepsilon_{vol}^{n+1/2} = \\frac{J^{n+1} - J^{n}}{\\Delta t\\, (J^{n+1} + J^{n}) / 2}

is the midpoint value of tr D = J-dot / J over the step just taken: with
u^{n+1} = u^n + Δt v^{n+1/2} it is the rate of the velocity v^{n+1/2}, to second order in
Δt, without that velocity. The element keeps J^n - 1 and the last rate in two history
fields; an evaluation with Δt = 0 (the initial state, the re-evaluation after a deletion)
reuses the stored rate and advances nothing. Bulk viscosity as in Abaqus/Explicit and
LS-DYNA (Belytschko, Liu & Moran, *Nonlinear Finite Elements*, 2000, sec. 6.2.4).
"""

from __future__ import annotations

from numba import njit


@njit(cache=True, inline="always")
def volumetric_rate(J, h, j_row, rate_row, m, rate_factor):
    """The volumetric strain rate, 1/s, and the update of its two history fields.

    Parameters
    ----------
    J : float
        det F now (J^{n+1}).
    h : ndarray float64
        History: ``h[j_row]`` holds J^n - 1 and ``h[rate_row]`` the last rate (1/s).
    m : float
        1.0 for a live element (its history advances), 0.0 for a dead one.
    rate_factor : float
        2 / Δt, 1/s; 0.0 evaluates without advancing (Δt = 0).
    """
    advance = 1.0 if rate_factor > 0.0 else 0.0
    Jn = 1.0 + h[j_row]
    rate = advance * (J - Jn) * rate_factor / (J + Jn) + (1.0 - advance) * h[rate_row]
    h[j_row] += m * advance * (J - Jn)
    h[rate_row] += m * advance * (rate - h[rate_row])
    return rate


@njit(cache=True, inline="always")
def stored_volumetric_rate(J, history, blk, lane, rates, dt):
    """The volumetric strain rate, 1/s, of an element of the block-major history
    ``history[block, field, lane]`` (the reference kernels' layout), and its update.

    ``history[blk, rates, lane]`` holds J^n - 1 and ``history[blk, rates + 1, lane]`` the last
    rate; dt = 0 returns the stored rate and advances nothing (module notes).
    """
    if dt > 0.0:
        J_old = 1.0 + history[blk, rates, lane]
        edot = 2.0 * (J - J_old) / (dt * (J + J_old))
        history[blk, rates, lane] = J - 1.0
        history[blk, rates + 1, lane] = edot
        return edot
    return history[blk, rates + 1, lane]
