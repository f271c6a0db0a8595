"""Plan-view quadrilateral mesh of a half disc (y >= 0) without degenerate cells at the centre.

An O-grid: a half square of 2m x m cells around the centre, surrounded by rings whose
4m sectors end on the circle at equal angles. Optionally a ring of 3:1 transitions
triples the number of sectors towards the rim, so the rim matches a revolved mesh of
many sectors while the centre stays coarse. The rim nodes are at exactly
sigma = radius and alpha = j pi / n_sectors.
"""

from __future__ import annotations

import math

import numpy as np


def _ring_count(inner: float, outer: float, sectors: int) -> int:
    return max(1, int(round((outer - inner) / (math.pi * 0.5 * (inner + outer) / sectors))))


def half_disc(radius: float, n_sectors: int, coarsen: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """O-grid mesh of the half disc of ``radius`` with ``n_sectors`` equal sectors on the rim.

    Parameters
    ----------
    radius : float
        Rim radius in plan parameter units (mm of arc length s).
    n_sectors : int
        Sectors on the rim (multiple of 4; of 12 with ``coarsen``).
    coarsen : bool
        Put one 3:1 sector transition ring inside, so the square has n_sectors / 3 sides.

    Returns
    -------
    sigma, alpha : ndarray, shape (n_nodes,)
        Polar plan coordinates of the nodes (radius, azimuth in [0, pi]).
    quads : ndarray, shape (n_cells, 4)
        Counter-clockwise in the (sigma cos alpha, sigma sin alpha) plane.
    """
    inner_sectors = n_sectors // 3 if coarsen else n_sectors
    m = inner_sectors // 4
    if inner_sectors % 4 or (coarsen and n_sectors % 3):
        raise ValueError(f"{n_sectors} sectors cannot be built (multiple of {12 if coarsen else 4} needed)")
    sigma_inner = 0.55 * radius if coarsen else radius
    b = 0.5 * sigma_inner
    xy: list[np.ndarray] = []
    quads: list[np.ndarray] = []

    # half square: (m + 1) rows of (2m + 1) nodes
    gx, gy = np.meshgrid(np.linspace(-b, b, 2 * m + 1), np.linspace(0.0, b, m + 1))
    grid = np.arange(gx.size).reshape(m + 1, 2 * m + 1)
    xy.append(np.stack([gx.ravel(), gy.ravel()], 1))
    quads.append(np.stack([grid[:-1, :-1], grid[:-1, 1:], grid[1:, 1:], grid[1:, :-1]], -1).reshape(-1, 4))
    walk = np.concatenate([grid[:, -1], grid[-1, -2::-1], grid[-2::-1, 0]])  # (4m + 1,) from alpha 0 to pi
    square_points = xy[0][walk]
    count = gx.size

    def ring(previous, start_points, sigma_end, sectors, rings):
        nonlocal count
        alpha = np.linspace(0.0, math.pi, sectors + 1)
        rim = sigma_end * np.stack([np.cos(alpha), np.sin(alpha)], 1)
        rim[[0, -1], 1] = 0.0
        rows = [previous]
        for i in range(1, rings + 1):
            xi = i / rings
            xy.append((1 - xi) * start_points + xi * rim)
            rows.append(np.arange(count, count + sectors + 1))
            count += sectors + 1
        for inner_row, outer_row in zip(rows[:-1], rows[1:]):
            quads.append(np.stack([inner_row[:-1], outer_row[:-1], outer_row[1:], inner_row[1:]], 1))
        return rows[-1], rim

    rings = _ring_count(b * 1.2, sigma_inner, inner_sectors)
    row, rim = ring(walk, square_points, sigma_inner, inner_sectors, rings)
    if coarsen:
        sigma_mid = min(sigma_inner + math.pi * sigma_inner / inner_sectors, 0.5 * (sigma_inner + radius))
        row, rim = _sector_transition(row, sigma_inner, sigma_mid, inner_sectors, xy, quads, count)
        count = sum(len(p) for p in xy)
        ring(row, rim, radius, n_sectors, _ring_count(sigma_mid, radius, n_sectors))
    points = np.concatenate(xy)
    sigma = np.hypot(points[:, 0], points[:, 1])
    alpha = np.arctan2(points[:, 1], points[:, 0])
    alpha[sigma < 1e-12] = 0.0
    rim_nodes = np.isclose(sigma, radius, rtol=1e-9)
    sigma[rim_nodes] = radius
    alpha[rim_nodes] = np.round(alpha[rim_nodes] / (math.pi / n_sectors)) * (math.pi / n_sectors)
    cells = np.concatenate(quads)
    x = points[cells]
    area = np.sum(x[..., 0] * np.roll(x[..., 1], -1, 1) - np.roll(x[..., 0], -1, 1) * x[..., 1], 1)
    cells[area < 0] = cells[area < 0][:, ::-1]
    return sigma, alpha, cells


def _sector_transition(coarse_row, sigma_coarse, sigma_fine, coarse_sectors, xy, quads, count):
    """One ring of 3:1 sector transitions from ``coarse_sectors`` to three times as many."""
    fine_sectors = 3 * coarse_sectors
    alpha_fine = np.linspace(0.0, math.pi, fine_sectors + 1)
    fine_points = sigma_fine * np.stack([np.cos(alpha_fine), np.sin(alpha_fine)], 1)
    fine_points[[0, -1], 1] = 0.0
    fine_row = np.arange(count, count + fine_sectors + 1)
    xy.append(fine_points)
    count += fine_sectors + 1
    sigma_mid = 0.5 * (sigma_coarse + sigma_fine)
    alpha_mid = np.stack([alpha_fine[1:-1:3], alpha_fine[2::3]], 1).ravel()  # two per coarse sector
    xy.append(sigma_mid * np.stack([np.cos(alpha_mid), np.sin(alpha_mid)], 1))
    mid = np.arange(count, count + alpha_mid.size).reshape(-1, 2)
    c0, c1 = coarse_row[:-1], coarse_row[1:]
    f0, f1, f2, f3 = fine_row[0:-1:3], fine_row[1::3], fine_row[2::3], fine_row[3::3]
    m1, m2 = mid[:, 0], mid[:, 1]
    quads.append(np.concatenate([
        np.stack([f0, f1, m1, c0], 1),
        np.stack([f1, f2, m2, m1], 1),
        np.stack([f2, f3, c1, m2], 1),
        np.stack([c0, m1, m2, c1], 1),
    ]))
    return fine_row, fine_points
