"""Mesh of a thick hemispherical cap (a spherical shell's upper half) for the cap-inflation example.

The cap is the quarter annulus a <= rho <= b, 0 <= theta <= pi/2 of the (r, z) half-plane
(r = rho cos theta, z = rho sin theta, mm): the upper half of a thick spherical shell, cut at
its equator z = 0 (held by symmetry, so the cap is the whole shell's half and Lame's solution
holds), meshed with ``radial`` x ``angular`` (default 4 x 48) axisymmetric 4-node quads (CAX4R).

Sets (names used by ``cap_inflation.toml``): node sets ``equator`` (z = 0), ``axis`` (r = 0),
``outer_equator``, ``outer_pole``, ``inner_pole`` (single nodes); surface set ``inner`` (the
faces on rho = a, where the pressure acts).

Run: ``python examples/cap_inflation/make_cap_mesh.py [OUT.inp]`` (default ``cap.inp`` next to
this file).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from corneasim.mesh import Mesh, write_mesh

HERE = Path(__file__).resolve().parent


def cap_mesh(inner_radius: float = 5.0, outer_radius: float = 6.0, radial: int = 4, angular: int = 48) -> Mesh:
    """Structured quad mesh of the hemispherical cap (module notes); radii in mm."""
    rho = np.linspace(inner_radius, outer_radius, radial + 1)
    theta = np.linspace(0.0, 0.5 * np.pi, angular + 1)
    tt, pp = np.meshgrid(theta, rho, indexing="ij")  # (angular + 1, radial + 1)
    points = np.column_stack([(pp * np.cos(tt)).ravel(), (pp * np.sin(tt)).ravel()])
    points[np.abs(points[:, 0]) < 1e-12, 0] = 0.0
    index = np.arange(points.shape[0]).reshape(angular + 1, radial + 1)
    cells = np.column_stack([index[:-1, :-1].ravel(), index[:-1, 1:].ravel(),
                             index[1:, 1:].ravel(), index[1:, :-1].ravel()]).astype(np.int64)
    inner = np.flatnonzero(np.tile(np.arange(radial), angular) == 0)  # elements on rho = a: face 3
    return Mesh(points, cells, "quad", np.zeros(len(cells), dtype=np.int64), ["shell"], axisymmetric=True,
                node_sets={"equator": index[0].copy(), "axis": index[-1].copy(),
                           "outer_equator": index[0, -1:].copy(), "outer_pole": index[-1, -1:].copy(),
                           "inner_pole": index[-1, :1].copy()},
                surface_sets={"inner": np.column_stack([inner, np.full(inner.size, 3)]).astype(np.int64)})


if __name__ == "__main__":
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else HERE / "cap.inp"
    mesh = cap_mesh()
    print(f"{write_mesh(mesh, out)}: {mesh.n_elements} elements, {mesh.n_nodes} nodes")
