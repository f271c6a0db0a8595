"""Plan-view quadrilateral mesh of a half disc (y >= 0) without degenerate cells at the centre.

An O-grid: a half square of 2m x m cells around the centre, surrounded by rings whose
4m sectors end on the circle at equal angles, so no cell collapses onto the centre. The
rim nodes are at exactly sigma = radius and alpha = j pi / n_sectors (more sectors
further out come from the strip's sector transitions, see ``hexahedral``).
"""

from __future__ import annotations

import math

import numpy as np


def _ring_count(inner: float, outer: float, sectors: int) -> int:
    return max(1, int(round((outer - inner) / (math.pi * 0.5 * (inner + outer) / sectors))))


def half_disc(radius: float, n_sectors: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """O-grid mesh of the half disc of ``radius`` with ``n_sectors`` equal sectors on the rim.

    Parameters
    ----------
    radius : float
        Rim radius in plan parameter units (mm of arc length s).
    n_sectors : int
        Sectors on the rim, a multiple of 4 (the half square has n_sectors / 4 rows).

    Returns
    -------
    sigma, alpha : ndarray, shape (n_nodes,)
        Polar plan coordinates of the nodes (radius, azimuth in [0, pi]).
    quads : ndarray, shape (n_cells, 4)
        Counter-clockwise in the (sigma cos alpha, sigma sin alpha) plane.
    """
    if n_sectors % 4 or n_sectors <= 0:
        raise ValueError(f"{n_sectors} sectors cannot be built (a positive multiple of 4 is needed)")
    m = n_sectors // 4
    b = 0.5 * radius
    gx, gy = np.meshgrid(np.linspace(-b, b, 2 * m + 1), np.linspace(0.0, b, m + 1))
    grid = np.arange(gx.size).reshape(m + 1, 2 * m + 1)  # half square: (m + 1) rows of (2m + 1) nodes
    square = np.stack([gx.ravel(), gy.ravel()], 1)
    walk = np.concatenate([grid[:, -1], grid[-1, -2::-1], grid[-2::-1, 0]])  # (4m + 1,) from alpha 0 to pi
    alpha = np.linspace(0.0, math.pi, n_sectors + 1)
    rim = radius * np.stack([np.cos(alpha), np.sin(alpha)], 1)
    rim[[0, -1], 1] = 0.0
    rings = _ring_count(1.2 * b, radius, n_sectors)
    xi = np.arange(1, rings + 1)[:, None, None] / rings
    ring_points = (1 - xi) * square[walk] + xi * rim  # (rings, 4m + 1, 2)
    rows = np.vstack([walk, gx.size + np.arange(rings * (n_sectors + 1)).reshape(rings, -1)])
    quads = np.concatenate([
        np.stack([grid[:-1, :-1], grid[:-1, 1:], grid[1:, 1:], grid[1:, :-1]], -1).reshape(-1, 4),
        np.stack([rows[:-1, :-1], rows[1:, :-1], rows[1:, 1:], rows[:-1, 1:]], -1).reshape(-1, 4),
    ])
    points = np.concatenate([square, ring_points.reshape(-1, 2)])
    sigma = np.hypot(points[:, 0], points[:, 1])
    azimuth = np.arctan2(points[:, 1], points[:, 0])
    azimuth[sigma < 1e-12] = 0.0
    rim_nodes = rows[-1]
    sigma[rim_nodes], azimuth[rim_nodes] = radius, alpha
    return sigma, azimuth, quads
