"""Preview pictures of meshes (matplotlib, written as PNG).

Axisymmetric meshes: the (r, z) section coloured by block, with a close-up of the
apex region. 3D meshes: the outer surface of the half model seen obliquely, the front view of the
cornea (plan), and the section on the symmetry plane.
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
    from matplotlib.figure import Figure  # no pyplot: the caller's backend stays as it is

    path = Path(path)
    colours = _colours(mesh)
    refined = np.zeros(mesh.n_elements, dtype=bool)
    if "refined" in mesh.element_sets:
        refined[mesh.element_sets["refined"]] = True
    eye = "anterior_surface" in mesh.node_sets and "refined" in mesh.element_sets
    if mesh.axisymmetric:
        fig = Figure(figsize=(16, 5.5))
        axes = fig.subplots(1, 3, gridspec_kw={"width_ratios": [1, 2, 1.4]})
        polygons = mesh.points[mesh.cells]
        views = [("section (r, z), mm", None)]
        if eye:
            z_top = mesh.points[:, 1].max()
            views += [("cornea", ((0.0, 6.5), (z_top - 3.6, z_top + 0.2))),
                      ("apex close-up (darker: refined set)", ((0.0, 0.8), (z_top - 0.7, z_top + 0.05)))]
        for ax, (name, limits) in zip(axes, views):
            _draw_section(ax, polygons, mesh.element_block, colours, name, refined)
            if limits:
                ax.set_xlim(*limits[0])
                ax.set_ylim(*limits[1])
        for ax in axes[len(views):]:
            ax.set_axis_off()
    else:
        fig = Figure(figsize=(15, 10))
        ax3 = fig.add_subplot(2, 2, 1, projection="3d")
        _draw_boundary(ax3, mesh, colours, refined)
        _draw_plan(fig.add_subplot(2, 2, 2), mesh, colours, refined, eye)
        lower, upper = mesh.points.min(axis=0), mesh.points.max(axis=0)
        if eye:
            z_top = upper[2]
            section = ((-6.5, 6.5), (z_top - 3.5, z_top + 0.3))
            close_up = ((2.4, 5.9), (z_top - 3.0, z_top - 0.2))
        else:
            section = ((lower[0], upper[0]), (lower[2], upper[2]))
            close_up = ((0.5 * (lower[0] + upper[0]), upper[0]), (0.5 * (lower[2] + upper[2]), upper[2]))
        _draw_symmetry_section(fig.add_subplot(2, 2, 3), mesh, colours, refined,
                               "section on the symmetry plane y = 0 (x, z), mm", section)
        _draw_symmetry_section(fig.add_subplot(2, 2, 4), mesh, colours, refined,
                               "close-up around the trephine radius" if eye else "close-up", close_up)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    return path


def _outer_faces(mesh: Mesh) -> tuple[np.ndarray, np.ndarray]:
    """Boundary faces that are neither on the symmetry plane nor in ``inner_surface``: (faces, nodes)."""
    faces = boundary_faces(mesh.cells, mesh.cell_type)
    nodes = mesh.cells[faces[:, 0][:, None], local_faces(mesh.cell_type)[faces[:, 1]]]
    keep = np.abs(mesh.points[nodes, 1]).max(axis=1) > 1e-9
    if "inner_surface" in mesh.node_sets:
        inner = np.zeros(mesh.n_nodes, dtype=bool)
        inner[mesh.node_sets["inner_surface"]] = True
        keep &= ~inner[nodes].all(axis=1)
    return faces[keep], nodes[keep]


def _face_colours(mesh: Mesh, colours: list[str], refined: np.ndarray, elements: np.ndarray) -> list[str]:
    face = np.array(colours, dtype=object)[mesh.element_block[elements]]
    face[refined[elements]] = [_darker(c) for c in face[refined[elements]]]
    return list(face)


def _draw_boundary(ax, mesh: Mesh, colours: list[str], refined: np.ndarray) -> None:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    faces, nodes = _outer_faces(mesh)
    x = mesh.points[nodes]  # (n, 4, 3)
    ax.add_collection3d(Poly3DCollection(x, facecolors=_face_colours(mesh, colours, refined, faces[:, 0]),
                                         edgecolors="k", linewidths=0.1))
    lim = np.abs(mesh.points[:, :2]).max()
    z_top = mesh.points[:, 2].max()
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-0.5 * lim, 1.5 * lim)
    ax.set_zlim(z_top - 2 * lim, z_top)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=25, azim=-70)
    ax.set_title("outer surface of the half model (darker: refined set)", fontsize=9)


def _draw_plan(ax, mesh: Mesh, colours: list[str], refined: np.ndarray, eye: bool) -> None:
    from matplotlib.collections import PolyCollection

    faces, nodes = _outer_faces(mesh)
    x = mesh.points[nodes]
    z_mid = mesh.points[:, 2].min() + 0.5 * np.ptp(mesh.points[:, 2])
    top = x[:, :, 2].mean(axis=1) > z_mid
    ax.add_collection(PolyCollection(x[top][:, :, :2], facecolors=_face_colours(mesh, colours, refined, faces[top, 0]),
                                     edgecolors="k", linewidths=0.15))
    if eye:
        ax.set_xlim(-6.5, 6.5)
        ax.set_ylim(-0.3, 6.5)
    else:
        ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_title("seen from the front, along -z (x, y), mm", fontsize=9)


def _draw_symmetry_section(ax, mesh: Mesh, colours: list[str], refined: np.ndarray, title: str, limits) -> None:
    faces = boundary_faces(mesh.cells, mesh.cell_type)
    nodes = mesh.cells[faces[:, 0][:, None], local_faces(mesh.cell_type)[faces[:, 1]]]
    on_plane = np.abs(mesh.points[nodes, 1]).max(axis=1) < 1e-9
    polygons = mesh.points[nodes[on_plane]][:, :, [0, 2]]
    _draw_section(ax, polygons, mesh.element_block[faces[on_plane, 0]], colours, title, refined[faces[on_plane, 0]])
    ax.set_xlim(*limits[0])
    ax.set_ylim(*limits[1])
