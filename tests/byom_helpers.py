"""Small meshes and scenarios shared by the bring-your-own-model tests."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from corneasim.mesh import Mesh, write_mesh

SUBSTRATE = Path(__file__).resolve().parents[1] / "examples" / "flat_punch" / "materials" / "substrate.toml"
"""Linear elastic, E = 1 MPa, nu = 0.3, rho = 1e-9 tonne/mm^3."""


def cylinder_mesh(radius: float = 1.0, height: float = 1.0, n_r: int = 3, n_z: int = 3) -> Mesh:
    """Axisymmetric (r, z) rectangle [0, radius] x [0, height] of n_r x n_z quads, mm.

    Node sets ``bottom`` (z = 0), ``top`` (z = height), ``axis`` (r = 0); one block ``solid``;
    surface set ``top_surface`` (the faces on z = height).
    """
    r, z = np.meshgrid(np.linspace(0.0, radius, n_r + 1), np.linspace(0.0, height, n_z + 1))
    points = np.column_stack([r.ravel(), z.ravel()])
    node = np.arange(points.shape[0]).reshape(n_z + 1, n_r + 1)
    cells = np.array([[node[j, i], node[j, i + 1], node[j + 1, i + 1], node[j + 1, i]]
                      for j in range(n_z) for i in range(n_r)], dtype=np.int64)
    top_elements = np.arange((n_z - 1) * n_r, n_z * n_r)
    return Mesh(points, cells, "quad", np.zeros(len(cells), dtype=np.int64), ["solid"], axisymmetric=True,
                node_sets={"bottom": node[0], "top": node[-1], "axis": node[:, 0]},
                surface_sets={"top_surface": np.column_stack([top_elements, np.full(n_r, 2)])})


def compression_scenario(folder: Path, end_time: float = 2.0e-3, extra: str = "") -> Path:
    """A cylinder on a frictionless base, its top pushed down 0.01 mm by a smooth step, bottom reaction logged."""
    mesh_path = write_mesh(cylinder_mesh(), folder / "cylinder.inp")
    text = f"""
name = "compression"
[mesh]
file = "{mesh_path.name}"
[materials]
solid = {{ material = "{SUBSTRATE.as_posix()}" }}
[[constraints]]
node_set = "bottom"
fixed = "z"
[[constraints]]
node_set = "axis"
symmetry = "r"
[[constraints]]
node_set = "top"
prescribed = "displacement"
component = "z"
value = -0.01
amplitude = {{ type = "smooth-step", t0 = 0.0, t1 = {0.6 * end_time} }}
[[reactions]]
name = "base"
node_set = "bottom"
component = "z"
[solver]
end_time = {end_time}
damping = 2000.0
history_every = 20
field_count = 0
{extra}
"""
    path = folder / "compression.toml"
    path.write_text(text)
    return path
