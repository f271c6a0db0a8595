"""Boundary faces and the named sets of the eye meshes."""

from __future__ import annotations

import numpy as np

from corneasim.mesh._mesh import HEXAHEDRON_FACES, QUAD_FACES


def local_faces(cell_type: str) -> np.ndarray:
    """Local node indices of each face of a cell type, shape (n_faces, nodes_per_face)."""
    return QUAD_FACES if cell_type == "quad" else HEXAHEDRON_FACES


def boundary_faces(cells: np.ndarray, cell_type: str) -> np.ndarray:
    """(element, local face) rows of the faces that belong to exactly one element."""
    local = local_faces(cell_type)
    n_elements, n_faces = cells.shape[0], local.shape[0]
    nodes = np.sort(cells[:, local], axis=2).reshape(n_elements * n_faces, -1)  # (n*f, k)
    _, inverse, counts = np.unique(nodes, axis=0, return_inverse=True, return_counts=True)
    single = np.flatnonzero(counts[inverse.ravel()] == 1)
    return np.stack([single // n_faces, single % n_faces], axis=1).astype(np.int64)


def faces_where(cells: np.ndarray, cell_type: str, faces: np.ndarray, node_flag: np.ndarray) -> np.ndarray:
    """The rows of ``faces`` whose nodes all carry ``node_flag``."""
    local = local_faces(cell_type)
    nodes = cells[faces[:, 0][:, None], local[faces[:, 1]]]  # (n, k)
    return faces[node_flag[nodes].all(axis=1)]


def face_node_set(cells: np.ndarray, cell_type: str, faces: np.ndarray) -> np.ndarray:
    """Sorted unique node indices of a face set."""
    local = local_faces(cell_type)
    return np.unique(cells[faces[:, 0][:, None], local[faces[:, 1]]]).astype(np.int64)


def eye_sets(points: np.ndarray, cells: np.ndarray, cell_type: str, outer: np.ndarray,
             inner: np.ndarray, cornea: np.ndarray, globe_centre: float) -> tuple[dict, dict]:
    """Surface and node sets shared by every eye mesh.

    Parameters
    ----------
    points : ndarray, shape (n, 2 or 3)
    outer, inner, cornea : ndarray of bool, shape (n,)
        Nodes on the outer surface, on the inner surface, and on the cornea (s <= s_limbus).
    globe_centre : float
        z of the globe centre (mm): nodes at or below it form the lower hemisphere.

    Returns
    -------
    surface_sets, node_sets : dict
    """
    faces = boundary_faces(cells, cell_type)
    inner_faces = faces_where(cells, cell_type, faces, inner)
    anterior_faces = faces_where(cells, cell_type, faces, outer & cornea)
    z = points[:, -1]
    surface_sets = {"inner_surface": inner_faces, "anterior_surface": anterior_faces}
    node_sets = {
        "inner_surface": face_node_set(cells, cell_type, inner_faces),
        "anterior_surface": face_node_set(cells, cell_type, anterior_faces),
        "lower_hemisphere": np.flatnonzero(z <= globe_centre + 1e-9).astype(np.int64),
    }
    return surface_sets, node_sets
