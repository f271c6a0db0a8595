"""Element renumbering for the kernels (mesh/_order.py): same mesh, blocks contiguous."""

import numpy as np

from corneasim.mesh import Mesh
from corneasim.mesh._order import grouped_by_block
from corneasim.mesh._axisymmetric import mesh_axisymmetric


def _interleaved_mesh():
    """A 4 x 3 strip of quads whose rows alternate between two blocks, with sets."""
    nx, ny = 4, 3
    x, y = np.meshgrid(np.arange(nx + 1.0), np.arange(ny + 1.0))
    points = np.column_stack([x.ravel(), y.ravel()])
    node = lambda i, j: j * (nx + 1) + i  # noqa: E731
    cells = np.array([[node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)]
                      for i in range(nx) for j in range(ny)])
    blocks = np.array([j % 2 for i in range(nx) for j in range(ny)])
    return Mesh(points=points, cells=cells, cell_type="quad", element_block=blocks, block_names=["a", "b"],
                axisymmetric=True, node_sets={"left": np.array([0, 5, 10, 15])},
                element_sets={"corner": np.array([0, 11])},
                surface_sets={"bottom": np.array([[0, 0], [3, 0], [6, 0], [9, 0]])})


def test_renumbered_mesh_is_the_same_mesh_with_contiguous_blocks():
    mesh = _interleaved_mesh()
    renumbered = grouped_by_block(mesh)
    assert np.all(np.diff(renumbered.element_block) >= 0)  # blocks contiguous, in block order
    # the same cells with the same blocks (as a set of rows)
    before = {tuple(c) + (b,) for c, b in zip(mesh.cells.tolist(), mesh.element_block)}
    after = {tuple(c) + (b,) for c, b in zip(renumbered.cells.tolist(), renumbered.element_block)}
    assert before == after and len(after) == mesh.n_elements
    # sets name the same cells and faces
    cells_of = lambda m, elements: {tuple(m.cells[e]) for e in elements}  # noqa: E731
    assert cells_of(mesh, mesh.element_sets["corner"]) == cells_of(renumbered, renumbered.element_sets["corner"])
    faces_before = {tuple(mesh.cells[e][[f, (f + 1) % 4]]) for e, f in mesh.surface_sets["bottom"]}
    faces_after = {tuple(renumbered.cells[e][[f, (f + 1) % 4]]) for e, f in renumbered.surface_sets["bottom"]}
    assert faces_before == faces_after
    np.testing.assert_array_equal(renumbered.node_sets["left"], mesh.node_sets["left"])
    renumbered.validate()


def test_needle_mesh_has_few_mixed_kernel_blocks():
    mesh = mesh_axisymmetric(preset="coarse")
    block = 32
    starts = np.arange(0, mesh.n_elements, block)
    mixed = sum(np.unique(mesh.element_block[s:s + block]).size > 1 for s in starts)
    assert mixed <= len(mesh.block_names) - 1  # only where one block ends and the next begins
