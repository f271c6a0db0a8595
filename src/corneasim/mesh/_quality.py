"""Element quality: scaled Jacobians, aspect ratios, characteristic lengths, stable time step.

* **Scaled Jacobian** at a corner: the determinant of the unit edge vectors leaving the
  corner (quad: the 2D cross product of its two edges; hexahedron: the triple product of
  its three edges, taken in the element's right-handed order). 1 for a square or cube
  corner, 0 for a degenerate one, negative for an inverted one. The element's value is
  the minimum over its corners (Knupp, "Achieving finite element mesh quality via
  optimization of the Jacobian matrix norm", 2000).
* **Aspect ratio**: longest over shortest edge.
* **Characteristic length** L_e: area over longest edge (quad), volume over largest face
  area (hexahedron): the element's smallest dimension, the edge for a square or cube.
* **Stable time step** of the central-difference scheme: dt = min L_e / c for the
  dilatational wave speed c = sqrt((lambda + 2 mu) / rho) (Belytschko, Liu & Moran,
  Nonlinear Finite Elements, 2000, section 6.3).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from corneasim.errors import InputError
from corneasim.mesh._mesh import HEXAHEDRON_FACES, Mesh

HEXAHEDRON_CORNERS = np.array(
    [[0, 1, 3, 4], [1, 2, 0, 5], [2, 3, 1, 6], [3, 0, 2, 7],
     [4, 7, 5, 0], [5, 4, 6, 1], [6, 5, 7, 2], [7, 6, 4, 3]], dtype=np.int64,
)
"""Each hexahedron corner and its three neighbours in right-handed order."""

HEXAHEDRON_EDGES = np.array(
    [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4], [0, 4], [1, 5], [2, 6], [3, 7]],
    dtype=np.int64,
)


def corner_jacobians(mesh: Mesh) -> np.ndarray:
    """Scaled Jacobian at every corner, shape (n_elements, nodes_per_cell)."""
    x = mesh.points[mesh.cells]  # (n, k, dim)
    if mesh.cell_type == "quad":
        e1 = np.roll(x, -1, axis=1) - x  # (n, 4, 2) to the next corner
        e2 = np.roll(x, 1, axis=1) - x  # (n, 4, 2) to the previous corner
        cross = e1[..., 0] * e2[..., 1] - e1[..., 1] * e2[..., 0]
        norm = np.linalg.norm(e1, axis=-1) * np.linalg.norm(e2, axis=-1)
    else:
        corner = x[:, HEXAHEDRON_CORNERS[:, 0]]  # (n, 8, 3)
        e = [x[:, HEXAHEDRON_CORNERS[:, k]] - corner for k in (1, 2, 3)]  # 3 x (n, 8, 3)
        cross = np.einsum("nki,nki->nk", np.cross(e[0], e[1]), e[2])
        norm = np.prod([np.linalg.norm(v, axis=-1) for v in e], axis=0)
    return np.divide(cross, norm, out=np.zeros_like(cross), where=norm > 0)


def _edges(mesh: Mesh) -> np.ndarray:
    """Edge lengths, shape (n_elements, n_edges)."""
    pairs = np.array([[0, 1], [1, 2], [2, 3], [3, 0]]) if mesh.cell_type == "quad" else HEXAHEDRON_EDGES
    x = mesh.points[mesh.cells]
    return np.linalg.norm(x[:, pairs[:, 1]] - x[:, pairs[:, 0]], axis=-1)


def element_measures(mesh: Mesh) -> np.ndarray:
    """Area (quad, in the (r, z) plane, mm^2) or volume (hexahedron, mm^3) of each element."""
    x = mesh.points[mesh.cells]
    if mesh.cell_type == "quad":
        return 0.5 * np.sum(x[..., 0] * np.roll(x[..., 1], -1, 1) - np.roll(x[..., 0], -1, 1) * x[..., 1], 1)
    # six tetrahedra around the 0-6 diagonal: exact when the faces are planar
    tets = np.array([[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]])
    a, b, c, d = (x[:, tets[:, k]] for k in range(4))  # (n, 6, 3)
    return np.einsum("nti,nti->nt", np.cross(b - a, c - a), d - a).sum(axis=1) / 6.0


def element_sizes(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Element size h_e (n_elements,), mm: sqrt(area) of a quad in (r, z), cbrt(volume) of a
    hexahedron, the volume from its three mean edge vectors (exact for parallelepipeds).

    The size of the crack band (``solver/_deletion.py``, ``solver/_softening.py``) and of the
    contact's tributary areas (``tools/interaction.py``).
    """
    x = points[cells]
    if cells.shape[1] == 4:
        d1, d2 = x[:, 2] - x[:, 0], x[:, 3] - x[:, 1]
        size = np.sqrt(0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]))
    else:
        g1 = 0.25 * (x[:, [1, 2, 5, 6]].sum(axis=1) - x[:, [0, 3, 4, 7]].sum(axis=1))
        g2 = 0.25 * (x[:, [2, 3, 6, 7]].sum(axis=1) - x[:, [0, 1, 4, 5]].sum(axis=1))
        g3 = 0.25 * (x[:, 4:].sum(axis=1) - x[:, :4].sum(axis=1))
        size = np.cbrt(np.abs(np.einsum("ij,ij->i", g1, np.cross(g2, g3))))
    return size


def characteristic_lengths(mesh: Mesh) -> np.ndarray:
    """Characteristic length of each element (mm): its smallest dimension."""
    if mesh.cell_type == "quad":
        return element_measures(mesh) / _edges(mesh).max(axis=1)
    x = mesh.points[mesh.cells][:, HEXAHEDRON_FACES]  # (n, 6, 4, 3)
    face_area = 0.5 * np.linalg.norm(np.cross(x[:, :, 2] - x[:, :, 0], x[:, :, 3] - x[:, :, 1]), axis=-1)
    return element_measures(mesh) / face_area.max(axis=1)


def check_elements(mesh: Mesh) -> None:
    """Raise :class:`InputError` naming the first element with a corner Jacobian <= 0."""
    jacobians = corner_jacobians(mesh)
    bad = np.flatnonzero((jacobians <= 1e-12).any(axis=1))
    if bad.size:
        element = int(bad[0])
        block = mesh.block_names[int(mesh.element_block[element])]
        worst = float(jacobians[element].min())
        kind = "inverted" if worst < 0 else "degenerate"
        raise InputError(
            f"element {element} (block '{block}') is {kind}: scaled Jacobian {worst:.3g} at a corner "
            f"({bad.size} bad element{'s' if bad.size > 1 else ''} in total)"
        )


@dataclass
class QualityReport:
    """Summary of a mesh's quality (lengths in mm, time in s)."""

    n_nodes: int
    n_elements: int
    cell_type: str
    min_scaled_jacobian: float
    max_scaled_jacobian: float
    max_aspect_ratio: float
    min_length: float
    smallest_element: int
    stable_time_step: float | None
    wave_speed: float | None
    block_counts: dict[str, int] = field(default_factory=dict)
    refined_count: int | None = None

    def lines(self) -> list[str]:
        """Human-readable report, one fact per line."""
        text = [
            f"nodes {self.n_nodes}, elements {self.n_elements} ({self.cell_type})",
            "elements per block: " + ", ".join(f"{k} {v}" for k, v in self.block_counts.items()),
        ]
        if self.refined_count is not None:
            share = self.refined_count / max(self.n_elements, 1)
            text.append(f"refined area: {self.refined_count} elements ({100 * share:.1f}%)")
        text += [
            f"scaled Jacobian: min {self.min_scaled_jacobian:.3f}, max {self.max_scaled_jacobian:.3f}",
            f"aspect ratio: max {self.max_aspect_ratio:.2f}",
            f"smallest element: {self.smallest_element}, characteristic length {self.min_length:.4g} mm",
        ]
        if self.stable_time_step is not None:
            text.append(
                f"stable time step: {self.stable_time_step:.3e} s at wave speed {self.wave_speed:.4g} mm/s"
            )
        return text


def quality_report(mesh: Mesh, wave_speed: float | None = None) -> QualityReport:
    """Quality of ``mesh``; with ``wave_speed`` (mm/s) also the stable time step L_min / c."""
    jacobians = corner_jacobians(mesh).min(axis=1)
    edges = _edges(mesh)
    lengths = characteristic_lengths(mesh)
    smallest = int(np.argmin(lengths))
    if wave_speed is not None and wave_speed <= 0:
        raise InputError(f"wave speed must be positive (mm/s), got {wave_speed}")
    refined = mesh.element_sets.get("refined")
    return QualityReport(
        n_nodes=mesh.n_nodes,
        n_elements=mesh.n_elements,
        cell_type=mesh.cell_type,
        min_scaled_jacobian=float(jacobians.min()),
        max_scaled_jacobian=float(jacobians.max()),
        max_aspect_ratio=float((edges.max(axis=1) / np.maximum(edges.min(axis=1), 1e-300)).max()),
        min_length=float(lengths[smallest]),
        smallest_element=smallest,
        stable_time_step=None if wave_speed is None else float(lengths[smallest] / wave_speed),
        wave_speed=wave_speed,
        block_counts={name: int(np.sum(mesh.element_block == i)) for i, name in enumerate(mesh.block_names)},
        refined_count=None if refined is None else int(refined.size),
    )


def dilatational_wave_speed(youngs_modulus: float, poisson_ratio: float, density: float) -> float:
    """c = sqrt((lambda + 2 mu) / rho) in mm/s from E (MPa), nu and rho (tonne/mm^3).

    >>> round(dilatational_wave_speed(3.08, 0.3, 1.0e-9) / 1e3, 1)  # mm/s -> m/s
    64.4
    """
    lam = youngs_modulus * poisson_ratio / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio))
    mu = youngs_modulus / (2 * (1 + poisson_ratio))
    return float(np.sqrt((lam + 2 * mu) / density))
