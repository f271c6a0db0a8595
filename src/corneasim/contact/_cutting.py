"""The cutting rule of a sharp circular edge: the ring's line load against the cutting toughness.

A sharp blade cuts when its force per unit length of edge reaches the tissue's toughness
(A. G. Atkins, *The Science and Engineering of Cutting*, 2009: F / L = G_c for a blade that
neither rubs nor deforms the work far ahead). For a turning trephine the cut advances around
the whole edge, so the line load is the ring's: the instrument's axial push |F_z| (edge,
bevel and wall together) over the length of edge above the tissue,

.. math::

    q = \\frac{|F_z|}{L}, \\qquad \\bar q \\leftarrow \\bar q\\,(1 - 1/N) + q / N, \\qquad
    r_e = \\bar q_e / G_c,

the same q for every element the edge presses, averaged per element over about N =
:data:`CUT_AVERAGING_STEPS` steps (an exponential moving average, so that the ringing of the
penalty springs over a few steps does not count). r_e is a failure ratio like the material
criterion's: an element with r_e >= 1 is deleted by the solver's failure check (or starts its
softening). Verification: ``tests/test_contact_edge.py``; calibration: ``docs/contact.md``.
"""

from __future__ import annotations

import numpy as np

CUT_AVERAGING_STEPS = 50
"""N of the moving average. A load that lasts longer than the ringing, as at the trephine's
first touch (0.06 s there, docs/contact.md), still counts."""


class RingCut:
    """The averaged line loads of the cutting rule (module notes).

    Parameters
    ----------
    toughness : float
        G_c, the line load at which the edge cuts, N/mm (> 0).
    n_elements : int
        Elements of the model.
    """

    def __init__(self, toughness: float, n_elements: int):
        self.toughness = float(toughness)
        self.load = np.zeros(n_elements)  # q_avg per element, N/mm

    def failure_ratios(self, elements: np.ndarray, push: float, edge_length: float) -> np.ndarray:
        """Advance the average one step and return r_e of ``elements`` (those the edge presses
        now), given the instrument's axial push |F_z| (N) and the length of edge above the
        tissue (mm)."""
        line_load = abs(push) / edge_length
        self.load *= 1.0 - 1.0 / CUT_AVERAGING_STEPS
        self.load[elements] += line_load / CUT_AVERAGING_STEPS
        return self.load[elements] / self.toughness
