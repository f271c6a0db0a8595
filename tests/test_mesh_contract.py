"""The Mesh container checks its own consistency."""

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.mesh import Mesh


def unit_square(**changes):
    fields = dict(
        points=np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]),
        cells=np.array([[0, 1, 2, 3]]),
        cell_type="quad",
        element_block=np.array([0]),
        block_names=["stroma"],
        axisymmetric=True,
        surface_sets={"top": np.array([[0, 2]])},
    )
    fields.update(changes)
    return Mesh(**fields)


def test_valid_mesh_and_face_nodes():
    mesh = unit_square()
    mesh.validate()
    assert mesh.face_nodes("top").tolist() == [[2, 3]]


@pytest.mark.parametrize(
    "changes, fragment",
    [
        (dict(cells=np.array([[0, 1, 2, 7]])), "element 0"),
        (dict(cell_type="triangle"), "unsupported cell type"),
        (dict(block_names=["stroma", "sclera"]), "block 'sclera' has no elements"),
        (dict(node_sets={"axis": np.array([9])}), "node set 'axis'"),
        (dict(points=np.array([[-1.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])), "negative radius"),
    ],
)
def test_invalid_meshes_name_the_problem(changes, fragment):
    with pytest.raises(InputError, match=fragment):
        unit_square(**changes).validate()
