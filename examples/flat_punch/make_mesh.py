"""Mesh of a two-layer axisymmetric disc for the flat-punch example, written to an Abaqus ``.inp``.

The disc is the (r, z) rectangle 0 <= r <= ``radius``, -``thickness`` <= z <= 0 (mm), the top
surface at z = 0 where the punch presses, meshed with structured 4-node quads (CAX4R). The
node spacing is uniform (h = a / (``elements_under_punch`` + 1/2)) over the square
0 <= r, -z <= ``fine_extent`` x ``punch_radius`` under the punch, where the stress gradients
are, and grows geometrically (ratio at most ``growth``) from there to the far boundaries,
which are put far away so that the disc behaves like a half-space (see ``flat_punch.py``).

What the file holds (names used by ``flat_punch.toml``):

* blocks (``*ELEMENT ... ELSET=``) ``top_layer`` (0 >= z >= -``layer_thickness``) and
  ``substrate`` (the rest): one material each;
* node sets ``bottom`` (z = -thickness, held fixed), ``axis`` (r = 0), ``top`` (z = 0),
  ``outer`` (r = radius, left free) and ``punch`` (the top nodes with r <= a, for the punch
  as a prescribed displacement: ``flat_punch_prescribed.toml``);
* surface set ``top_surface`` (the faces on z = 0; free here, a pressure could act on it).

Run it: ``python examples/flat_punch/make_mesh.py [OUT.inp]`` (default ``disc.inp`` next
to this file), or call :func:`disc_mesh` and :func:`corneasim.mesh.write_mesh`.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from corneasim.mesh import Mesh, write_mesh

HERE = Path(__file__).resolve().parent


def graded_coordinates(fine_size: float, fine_extent: float, total: float, growth: float) -> np.ndarray:
    """Node coordinates from 0 to ``total`` (mm): uniform steps ``fine_size`` up to ``fine_extent``, then growing.

    Beyond the fine zone the steps are ``fine_size * q**k`` (k = 1, 2, ...) with the ratio
    q <= ``growth`` chosen so that the last node lands exactly on ``total``.
    """
    n_fine = max(1, int(round(fine_extent / fine_size)))
    fine = fine_size * np.arange(n_fine + 1)
    remaining = total - fine[-1]
    if remaining <= 1e-12 * total:
        return fine
    n_grow = int(np.ceil(np.log1p(remaining * (growth - 1.0) / fine_size) / np.log(growth)))
    low, high = 1.0, growth
    for _ in range(200):
        q = 0.5 * (low + high)
        span = fine_size * sum(q ** k for k in range(1, n_grow + 1))
        low, high = (q, high) if span < remaining else (low, q)
    steps = fine_size * q ** np.arange(1, n_grow + 1)
    steps *= remaining / steps.sum()
    return np.concatenate([fine, fine[-1] + np.cumsum(steps)])


def disc_mesh(punch_radius: float = 0.5, radius: float = 25.0, thickness: float = 25.0,
              layer_thickness: float = 0.25, elements_under_punch: int = 10, fine_extent: float = 1.5,
              growth: float = 1.2) -> Mesh:
    """Structured axisymmetric mesh of a disc with a top layer.

    Parameters
    ----------
    punch_radius : float
        Radius a of the flat punch, mm; the punch edge lies half-way between two node lines.
    radius, thickness : float
        Disc radius and total thickness, mm.
    layer_thickness : float
        Thickness of the top layer, mm; the nearest node line is moved onto the interface.
    elements_under_punch : int
        n: nodes at r = 0, h, ..., n h under the punch, fine spacing h = a / (n + 1/2).
    fine_extent : float
        Size of the uniformly meshed square under the punch, in punch radii.
    growth : float
        Largest ratio of neighbouring element sizes outside the fine square (> 1).

    Returns
    -------
    Mesh
        Axisymmetric quad mesh with blocks ``top_layer``, ``substrate`` and the sets listed
        in the module notes.
    """
    h = punch_radius / (elements_under_punch + 0.5)
    extent = max(fine_extent * punch_radius, layer_thickness + h)
    r = graded_coordinates(h, extent, radius, growth)
    depth = graded_coordinates(h, extent, thickness, growth)
    depth[np.argmin(np.abs(depth - layer_thickness))] = layer_thickness
    z = -depth[::-1]
    nr, nz = r.size, z.size
    rr, zz = np.meshgrid(r, z, indexing="xy")
    points = np.column_stack([rr.ravel(), zz.ravel()])
    index = np.arange(nr * nz).reshape(nz, nr)
    cells = np.column_stack([index[:-1, :-1].ravel(), index[:-1, 1:].ravel(),
                             index[1:, 1:].ravel(), index[1:, :-1].ravel()]).astype(np.int64)
    centre_z = 0.5 * (z[:-1] + z[1:])
    layer_rows = np.repeat(centre_z > -layer_thickness, nr - 1)
    element_block = np.where(layer_rows, 0, 1).astype(np.int64)
    top_row = np.arange((nz - 2) * (nr - 1), (nz - 1) * (nr - 1))
    return Mesh(
        points=points, cells=cells, cell_type="quad", element_block=element_block,
        block_names=["top_layer", "substrate"], axisymmetric=True,
        node_sets={"bottom": index[0].copy(), "top": index[-1].copy(),
                   "axis": index[:, 0].copy(), "outer": index[:, -1].copy(),
                   "punch": index[-1, r <= punch_radius * (1 + 1e-9)].copy()},
        surface_sets={"top_surface": np.column_stack([top_row, np.full(top_row.size, 2)]).astype(np.int64)},
    )


def main(out: str | Path = HERE / "disc.inp", **parameters) -> Path:
    """Write the default disc (or one with ``parameters`` of :func:`disc_mesh`) and say what it holds."""
    mesh = disc_mesh(**parameters)
    path = write_mesh(mesh, out)
    counts = {name: int(np.sum(mesh.element_block == k)) for k, name in enumerate(mesh.block_names)}
    print(f"{path}: {mesh.n_elements} elements ({counts}), {mesh.n_nodes} nodes")
    return path


if __name__ == "__main__":
    main(*sys.argv[1:])
