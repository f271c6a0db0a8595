"""Placing an instrument on the tissue: lower it along its axis until the nearest node is at a gap.

The tip of a needle sits above the corneal apex, but a trephine's cutting edge meets the
cornea at its cutting radius, about 1 mm below the apex. Both cases are one rule: with the
instrument axis on the optical axis pointing down, find the tip height H at which the
smallest signed distance from the instrument to the tissue's surface nodes equals the
requested gap,

.. math::

    \\min_i d\\big(x_i - H e_z\\big) = g ,

solved by bisection (the clearance grows monotonically as the instrument rises clear of the
tissue).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.tools.shapes import signed_distance, signed_distance_rz


@njit(cache=True)
def clearance(shape, points, height, axisymmetric):
    """Smallest signed distance (mm) from the instrument with its tip at ``height`` on the axis to ``points``.

    ``points`` (n, 2) as (r, z) when ``axisymmetric`` else (n, 3) as (x, y, z), mm.
    """
    smallest = np.inf
    for i in range(points.shape[0]):
        if axisymmetric:
            d = signed_distance_rz(shape, points[i, 0], points[i, 1] - height)[0]
        else:
            d = signed_distance(shape, points[i, 0], points[i, 1], points[i, 2] - height)[0]
        if d < smallest:
            smallest = d
    return smallest


def tip_height_for_gap(shape: np.ndarray, points: np.ndarray, gap: float, axisymmetric: bool) -> float:
    """Tip height (mm) on the axis at which the instrument clears ``points`` by ``gap`` (mm).

    Parameters
    ----------
    shape : ndarray
        Packed instrument shape (``Needle.pack()``, ``Trephine.pack()``).
    points : ndarray (n, 2 or 3)
        Current positions of the tissue's surface nodes, mm.
    gap : float
        Required clearance, mm (>= 0).
    axisymmetric : bool
        Points are (r, z).
    """
    points = np.ascontiguousarray(points, dtype=np.float64)
    top = float(points[:, -1].max())
    span = float(np.ptp(points[:, -1])) + 1.0
    low, high = top - span, top + span + gap
    while clearance(shape, points, high, axisymmetric) < gap:
        high += span
    for _ in range(60):
        middle = 0.5 * (low + high)
        if clearance(shape, points, middle, axisymmetric) < gap:
            low = middle
        else:
            high = middle
    return high
