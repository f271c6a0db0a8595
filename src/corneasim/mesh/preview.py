"""Preview pictures of meshes (matplotlib, written as PNG).

Axisymmetric meshes: the (r, z) section coloured by block, with a close-up of the
apex region. 3D meshes: the outer boundary faces of the half model seen obliquely, and
its section on the symmetry plane.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from corneasim.mesh._mesh import Mesh
from corneasim.mesh._sets import boundary_faces, local_faces

BLOCK_COLOURS = {"epithelium": "#e6a0a0", "stroma": "#a6c8e8", "sclera": "#e8e0b0"}
FALLBACK_COLOURS = ["#b8d8b0", "#d0b8e0", "#f0c890", "#c0c0c0"]


def _colours(mesh: Mesh) -> list[str]:
    return [BLOCK_COLOURS.get(name, FALLBACK_COLOURS[i % len(FALLBACK_COLOURS)])
            for i, name in enumerate(mesh.block_names)]


def _draw_section(ax, polygons: np.ndarray, blocks: np.ndarray, colours: list[str], title: str,
                  refined: np.ndarray | None = None) -> None:
    from matplotlib.collections import PolyCollection

    face = np.array(colours, dtype=object)[blocks]
    if refined is not None:
        face = face.copy()
        face[refined] = [_darker(c) for c in face[refined]]
    ax.add_collection(PolyCollection(polygons, facecolors=list(face), edgecolors="k", linewidths=0.15))
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=9)


def _darker(colour: str) -> str:
    rgb = [int(colour[i:i + 2], 16) for i in (1, 3, 5)]
    return "#" + "".join(f"{int(0.75 * v):02x}" for v in rgb)


def write_preview(mesh: Mesh, path: str | Path, title: str = "") -> Path:
    """Write a PNG picture of ``mesh`` to ``path``; returns the path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path = Path(path)
    colours = _colours(mesh)
    refined = np.zeros(mesh.n_elements, dtype=bool)
    if "refined" in mesh.element_sets:
        refined[mesh.element_sets["refined"]] = True
    if mesh.axisymmetric:
        fig, axes = plt.subplots(1, 2, figsize=(11, 5.5))
        polygons = mesh.points[mesh.cells]
        _draw_section(axes[0], polygons, mesh.element_block, colours, "section (r, z), mm", refined)
        _draw_section(axes[1], polygons, mesh.element_block, colours, "apex close-up (darker: refined set)", refined)
        z_top = mesh.points[:, 1].max()
        axes[1].set_xlim(0.0, 0.8)
        axes[1].set_ylim(z_top - 0.7, z_top + 0.05)
    else:
        fig = plt.figure(figsize=(12, 5.5))
        ax3 = fig.add_subplot(1, 2, 1, projection="3d")
        _draw_boundary(ax3, mesh, colours, refined)
        ax2 = fig.add_subplot(1, 2, 2)
        _draw_symmetry_section(ax2, mesh, colours, refined)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def _draw_boundary(ax, mesh: Mesh, colours: list[str], refined: np.ndarray) -> None:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    faces = boundary_faces(mesh.cells, mesh.cell_type)
    nodes = mesh.cells[faces[:, 0][:, None], local_faces(mesh.cell_type)[faces[:, 1]]]
    x = mesh.points[nodes]  # (n, 4, 3)
    outward = x[:, :, 2].mean(axis=1) > mesh.points[:, 2].min() + 0.5 * np.ptp(mesh.points[:, 2])
    keep = outward & (np.abs(x[:, :, 1]).max(axis=1) > 1e-9)
    face = np.array(colours, dtype=object)[mesh.element_block[faces[keep, 0]]]
    face[refined[faces[keep, 0]]] = [_darker(c) for c in face[refined[faces[keep, 0]]]]
    ax.add_collection3d(Poly3DCollection(x[keep], facecolors=list(face), edgecolors="k", linewidths=0.1))
    lim = np.abs(mesh.points[:, :2]).max()
    z_top = mesh.points[:, 2].max()
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-0.2 * lim, 1.8 * lim)
    ax.set_zlim(z_top - 2 * lim, z_top)
    ax.view_init(elev=35, azim=-60)
    ax.set_title("upper half of the half model (darker: refined set)", fontsize=9)


def _draw_symmetry_section(ax, mesh: Mesh, colours: list[str], refined: np.ndarray) -> None:
    faces = boundary_faces(mesh.cells, mesh.cell_type)
    nodes = mesh.cells[faces[:, 0][:, None], local_faces(mesh.cell_type)[faces[:, 1]]]
    on_plane = np.abs(mesh.points[nodes, 1]).max(axis=1) < 1e-9
    polygons = mesh.points[nodes[on_plane]][:, :, [0, 2]]
    _draw_section(ax, polygons, mesh.element_block[faces[on_plane, 0]], colours,
                  "cornea on the symmetry plane y = 0 (x, z), mm", refined[faces[on_plane, 0]])
    z_top = mesh.points[:, 2].max()
    ax.set_xlim(-6.5, 6.5)
    ax.set_ylim(z_top - 3.5, z_top + 0.3)
