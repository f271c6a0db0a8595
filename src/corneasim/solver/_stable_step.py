"""Stable time step and mass scaling.

The central-difference method is stable for Δt below the smallest element transit time of
the dilatational wave, Δt_e = L_e / c_d (reduced for bulk viscosity), computed by the
element kernels with the instantaneous (unrelaxed) moduli. The step used is

.. math::

    \\Delta t = s \\min_e \\Delta t_e \\sqrt{\\rho'_e / \\rho_e},

with the safety factor s (default 0.9) and ρ'_e / ρ_e the element's density scale.

**Mass scaling to a target step** Δt*: the density of each element with s Δt_e < Δt* is
multiplied by (Δt* / (s Δt_e))^2, so its scaled step s Δt_e sqrt(scale) equals Δt*
exactly, and elements already above the target keep their mass (Abaqus "fixed mass scaling
to a target time increment of elements below it"). The needle paper uses Δt* = 2e-5 s, the
trephination paper 1e-5 s. The added mass fraction is sum_e (scale_e - 1) m_e / sum_e m_e.
"""

from __future__ import annotations

import numpy as np

from corneasim.errors import InputError


def density_scale_for_target(element_dt, target_time_step, safety_factor):
    """Per-element density scale (n_elements,) >= 1 reaching ``target_time_step``.

    Parameters
    ----------
    element_dt : ndarray (n_elements,) float64
        Unscaled element stable steps, s (no safety factor).
    target_time_step : float or None
        Δt*, s; None means no mass scaling (all ones).
    safety_factor : float
        s, dimensionless.
    """
    element_dt = np.asarray(element_dt, dtype=np.float64)
    if target_time_step is None:
        return np.ones_like(element_dt)
    if not target_time_step > 0:
        raise InputError(f"target_time_step: expected a time step > 0 s, got {target_time_step}")
    limit = safety_factor * element_dt
    return np.where(limit < target_time_step, (target_time_step / limit) ** 2, 1.0)


def stable_time_step(element_dt, density_scale, alive, safety_factor) -> tuple[float, int]:
    """The stable step s min_e Δt_e sqrt(scale_e) over live elements, and the controlling element.

    Returns
    -------
    (float, int)
        Δt in s (infinity when no element is alive) and the index of the element that sets it
        (-1 when none).
    """
    scaled = np.where(alive != 0, element_dt * np.sqrt(density_scale), np.inf)
    if scaled.size == 0:
        return float("inf"), -1
    element = int(np.argmin(scaled))
    return float(safety_factor * scaled[element]), (element if np.isfinite(scaled[element]) else -1)


def check_fixed_time_step(time_step, stable_step, element, block, time) -> None:
    """InputError when a user-fixed time step exceeds the stable limit."""
    if time_step > stable_step:
        raise InputError(
            f"time_step {time_step:.4g} s exceeds the stable time step {stable_step:.4g} s "
            f"(element {element}, block '{block}', t = {time:.6g} s); lower it or use mass scaling")
