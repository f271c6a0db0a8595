"""Element numbering for the fast kernels: grouped by block, local in the nodes.

The fast element kernels work on blocks of 32-64 consecutive elements
(``solver/elements/_fast_quad.py``). A kernel block whose elements share one material reads
its constants once; a mixed one gathers them per element. Its nodes are gathered and its
forces scattered through the element-node table, so consecutive elements with nearby node
numbers keep that traffic in cache (block-major data layout: ``docs/performance.md``).
The eye generators build their meshes layer by layer, which interleaves the blocks
(epithelium, stroma, sclera) along the kernel blocks. Measured on the needle scenario's
default mesh (16,745 quads, 2 threads): 251 of 524 kernel blocks were mixed, and the
internal-force call took 466 µs. Renumbered, 2 blocks are mixed and the call takes 298 µs.
"""

from __future__ import annotations

import numpy as np

from corneasim.mesh._mesh import Mesh


def grouped_by_block(mesh: Mesh) -> Mesh:
    """The same mesh with its elements sorted by block, then by their smallest node index.

    Nodes, node sets and block names are unchanged; element sets and surface sets are
    renumbered to the new element indices. The sort is stable, so elements with the same
    block and smallest node keep their order.

    Parameters
    ----------
    mesh : Mesh
        Any mesh.

    Returns
    -------
    Mesh
        A new mesh: ``cells[k] = mesh.cells[order[k]]`` with
        ``order = lexsort((cells.min(axis=1), element_block))``.
    """
    order = np.lexsort((mesh.cells.min(axis=1), mesh.element_block))
    new_index = np.empty_like(order)
    new_index[order] = np.arange(order.size)
    element_sets = {name: np.sort(new_index[elements]) for name, elements in mesh.element_sets.items()}
    surface_sets = {}
    for name, faces in mesh.surface_sets.items():
        renumbered = np.column_stack([new_index[faces[:, 0]], faces[:, 1]]) if len(faces) else faces
        surface_sets[name] = renumbered.astype(np.int64)
    return Mesh(points=mesh.points, cells=np.ascontiguousarray(mesh.cells[order]), cell_type=mesh.cell_type,
                element_block=np.ascontiguousarray(mesh.element_block[order]), block_names=list(mesh.block_names),
                axisymmetric=mesh.axisymmetric, node_sets=dict(mesh.node_sets), element_sets=element_sets,
                surface_sets=surface_sets)
