"""Split a mesh along a surface: the nodes on it are duplicated for the elements on one side.

A cut whose path is known in advance (the trephine's cylinder r = R_cut) can be modelled by
separating the tissue along it instead of deleting elements: the surface nodes get a
second copy used by the elements on one side, and each (original, copy) pair is tied by a
cohesive law (:mod:`corneasim.fracture._ties`) that holds them together until the cut
opens it. This module only changes the topology; the coordinates of a copy are those of
its original, so the split mesh is the same body until the ties break.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from corneasim.errors import InputError
from corneasim.mesh import Mesh


def split_nodes(mesh: Mesh, nodes, moved_elements) -> tuple[Mesh, np.ndarray]:
    """Duplicate ``nodes`` for ``moved_elements``.

    Parameters
    ----------
    mesh : Mesh
    nodes : array-like of int
        Nodes on the split surface.
    moved_elements : array-like of int or bool mask (n_elements,)
        Elements on the side that takes the copies.

    Returns
    -------
    (Mesh, ndarray)
        The split mesh (copies appended after the original nodes; every node set that
        holds an original also holds its copy; element and surface sets are unchanged) and
        ``pairs`` (n_pairs, 2) int64: (original, copy). Only nodes used by elements on both
        sides are split; the others keep one node.
    """
    nodes = np.unique(np.asarray(nodes, dtype=np.int64))
    if nodes.size and (nodes[0] < 0 or nodes[-1] >= mesh.n_nodes):
        raise InputError(f"split: node indices must be in 0..{mesh.n_nodes - 1}")
    moved = np.zeros(mesh.n_elements, bool)
    moved[np.asarray(moved_elements)] = True
    on_surface = np.zeros(mesh.n_nodes, bool)
    on_surface[nodes] = True
    used_moved = np.zeros(mesh.n_nodes, bool)
    used_moved[mesh.cells[moved].ravel()] = True
    used_kept = np.zeros(mesh.n_nodes, bool)
    used_kept[mesh.cells[~moved].ravel()] = True
    split = np.flatnonzero(on_surface & used_moved & used_kept)
    copy_of = np.full(mesh.n_nodes, -1, np.int64)
    copy_of[split] = mesh.n_nodes + np.arange(split.size)
    cells = mesh.cells.copy()
    moved_cells = cells[moved]
    replace = copy_of[moved_cells] >= 0
    moved_cells[replace] = copy_of[moved_cells[replace]]
    cells[moved] = moved_cells
    node_sets = {}
    for name, members in mesh.node_sets.items():
        copies = copy_of[members]
        node_sets[name] = np.sort(np.concatenate([members, copies[copies >= 0]]))
    split_mesh = dataclasses.replace(
        mesh, points=np.concatenate([mesh.points, mesh.points[split]]), cells=cells,
        node_sets=node_sets, element_sets=dict(mesh.element_sets), surface_sets=dict(mesh.surface_sets))
    return split_mesh, np.column_stack([split, copy_of[split]])
