"""The traction-separation law of the tissue's separation: a strength and a toughness.

One bilinear law (Camacho and Ortiz, Int. J. Solids Struct. 33 (1996) 2899-2938; Turon et
al., Eng. Fract. Mech. 74 (2007) 1665-1682) serves every separation model of the package:
the traction T rises to the strength sigma_c at the opening delta_0 (an elastic branch that
stands for the uncut tissue), then falls linearly to zero at delta_f,

.. math::

    T(\\bar\\delta) = \\begin{cases} \\sigma_c\\, \\bar\\delta/\\delta_0, & \\bar\\delta \\le \\delta_0\\\\
    \\sigma_c\\, \\frac{\\delta_f - \\bar\\delta}{\\delta_f - \\delta_0}, & \\delta_0 < \\bar\\delta < \\delta_f\\\\
    0, & \\bar\\delta \\ge \\delta_f \\end{cases}, \\qquad
    \\delta_f = \\frac{2 G_c}{\\sigma_c},

where \\bar\\delta is the largest opening reached (damage is irreversible; unloading follows
the secant T(\\bar\\delta)/\\bar\\delta back to the origin). The area under the envelope is
G_c: an interface that opens fully dissipates G_c per unit area whatever the mesh.
Units: MPa (tractions, strengths), mm (openings), N/mm = mJ/mm^2 (toughness, energies per
unit area).
"""

from __future__ import annotations

from numba import njit


@njit(cache=True, inline="always")
def envelope_traction(opening_max, strength, opening_peak, separation):
    """Traction on the envelope at the largest opening ``opening_max`` (MPa; module notes).

    Parameters
    ----------
    opening_max : float
        \\bar\\delta, the largest opening reached, mm (>= 0).
    strength : float
        sigma_c, MPa.
    opening_peak : float
        delta_0, the opening at the peak, mm.
    separation : float
        delta_f = 2 G_c / sigma_c, mm. An interface with delta_0 >= delta_f has no
        softening branch: it breaks at its peak.
    """
    if opening_max <= opening_peak:
        return strength * opening_max / opening_peak
    if opening_max < separation and opening_peak < separation:
        return strength * (separation - opening_max) / (separation - opening_peak)
    return 0.0


@njit(cache=True, inline="always")
def dissipated_density(opening_max, strength, opening_peak, separation):
    """Energy per unit area dissipated by an interface opened up to ``opening_max``
    (mJ/mm^2 = N/mm): the area under the envelope up to it less the elastic energy that the
    secant gives back, G_c once fully open (or sigma_c delta_0 / 2 for a brittle one)."""
    if opening_max <= opening_peak:
        return 0.0
    if opening_max >= separation or opening_peak >= separation:
        return 0.5 * strength * max(separation, opening_peak)
    envelope = strength * (separation - opening_max) / (separation - opening_peak)
    absorbed = 0.5 * strength * opening_peak + 0.5 * (strength + envelope) * (opening_max - opening_peak)
    return absorbed - 0.5 * envelope * opening_max
