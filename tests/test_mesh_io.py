"""Mesh files: export-import round trips keep everything; foreign files give blocks and sets."""

import xml.etree.ElementTree as ElementTree

import meshio
import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.mesh._axisymmetric import mesh_axisymmetric
from corneasim.mesh._hexahedral import mesh_3d
from corneasim.mesh._io import read_mesh, write_mesh


@pytest.fixture(scope="module")
def meshes():
    return {"quad": mesh_axisymmetric(preset="coarse"), "hexahedron": mesh_3d(preset="coarse")}


def assert_same(a, b):
    assert np.allclose(a.points, b.points, rtol=0, atol=1e-10)
    assert np.array_equal(a.cells, b.cells)
    assert a.cell_type == b.cell_type and a.axisymmetric == b.axisymmetric
    assert a.block_names == b.block_names
    assert np.array_equal(a.element_block, b.element_block)
    assert a.node_sets.keys() == b.node_sets.keys()
    assert a.element_sets.keys() == b.element_sets.keys()
    assert a.surface_sets.keys() == b.surface_sets.keys()
    for name in a.node_sets:
        assert np.array_equal(np.sort(a.node_sets[name]), np.sort(b.node_sets[name])), name
    for name in a.element_sets:
        assert np.array_equal(np.sort(a.element_sets[name]), np.sort(b.element_sets[name])), name
    for name in a.surface_sets:
        assert set(map(tuple, a.surface_sets[name].tolist())) == set(map(tuple, b.surface_sets[name].tolist()))


@pytest.mark.parametrize("kind", ["quad", "hexahedron"])
@pytest.mark.parametrize("suffix", [".inp", ".vtu"])
def test_round_trip_keeps_nodes_elements_and_sets(meshes, tmp_path, kind, suffix):
    mesh = meshes[kind]
    path = write_mesh(mesh, tmp_path / f"eye{suffix}")
    assert_same(mesh, read_mesh(path))


def test_inp_is_abaqus_input(meshes, tmp_path):
    text = write_mesh(meshes["quad"], tmp_path / "eye.inp").read_text()
    assert "*ELEMENT, TYPE=CAX4R, ELSET=epithelium" in text
    assert "*SURFACE, TYPE=ELEMENT, NAME=inner_surface" in text
    assert "*NSET, NSET=lower_hemisphere" in text
    text = write_mesh(meshes["hexahedron"], tmp_path / "eye3d.inp").read_text()
    assert "TYPE=C3D8R" in text


def test_xdmf_is_xml_with_topology_and_sets(meshes, tmp_path):
    mesh = meshes["hexahedron"]
    root = ElementTree.parse(write_mesh(mesh, tmp_path / "eye.xdmf")).getroot()
    topology = root.find("./Domain/Grid/Topology")
    assert topology.get("TopologyType") == "Hexahedron"
    assert int(topology.get("NumberOfElements")) == mesh.n_elements
    names = {attribute.get("Name") for attribute in root.iter("Attribute")}
    assert {"block", "elset:refined", "nset:symmetry_plane", "surface:inner_surface"} <= names


def gmsh_square(tmp_path, cell_type="quad"):
    """Two quads (r in [0, 2], z in [0, 1]) with physical groups, written by meshio as Gmsh 2.2."""
    points = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]], float)
    if cell_type == "quad":
        cells = [("quad", np.array([[0, 1, 4, 3], [1, 2, 5, 4]]))]
        physical = [np.array([1, 2])]
    else:
        cells = [("triangle", np.array([[0, 1, 4], [0, 4, 3]]))]
        physical = [np.array([1, 1])]
    cells += [("line", np.array([[3, 4], [4, 5]])), ("line", np.array([[0, 3]]))]
    physical += [np.array([3, 3]), np.array([4])]
    mesh = meshio.Mesh(points, cells, cell_data={"gmsh:physical": physical, "gmsh:geometrical": physical},
                       field_data={"stroma": np.array([1, 2]), "epithelium": np.array([2, 2]),
                                   "top": np.array([3, 1]), "axis": np.array([4, 1])})
    path = tmp_path / "square.msh"
    meshio.write(path, mesh, file_format="gmsh22", binary=False)
    return path


def test_gmsh_physical_groups_become_blocks_and_sets(tmp_path):
    mesh = read_mesh(gmsh_square(tmp_path), axisymmetric=True)
    assert mesh.axisymmetric and mesh.points.shape == (6, 2)
    assert mesh.block_names == ["stroma", "epithelium"]
    assert mesh.element_block.tolist() == [0, 1]
    assert sorted(mesh.node_sets["top"].tolist()) == [3, 4, 5]
    assert sorted(mesh.node_sets["axis"].tolist()) == [0, 3]
    assert sorted(map(tuple, mesh.surface_sets["top"].tolist())) == [(0, 2), (1, 2)]  # face 2: nodes 2-3
    assert mesh.face_nodes("axis").tolist() == [[3, 0]]


def test_hand_written_inp_with_generate_and_surface(tmp_path):
    path = tmp_path / "block.inp"
    path.write_text(
        "*NODE\n1, 0, 0\n2, 1, 0\n3, 1, 1\n4, 0, 1\n5, 2, 0\n6, 2, 1\n"
        "*ELEMENT, TYPE=CAX4R, ELSET=disc\n10, 1, 2, 3, 4\n11, 2, 5, 6, 3\n"
        "*NSET, NSET=bottom, GENERATE\n1, 2, 1\n*NSET, NSET=corner\n5\n*NSET, NSET=edge\nbottom, corner\n"
        "*ELSET, ELSET=right\n11\n"
        "*SURFACE, TYPE=ELEMENT, NAME=top\nright, S3\n10, S3\n"
    )
    mesh = read_mesh(path)
    assert mesh.block_names == ["disc"] and mesh.n_elements == 2
    assert mesh.node_sets["bottom"].tolist() == [0, 1]
    assert mesh.node_sets["edge"].tolist() == [0, 1, 4]
    assert mesh.element_sets["right"].tolist() == [1]
    assert sorted(mesh.face_nodes("top").tolist()) == [[2, 3], [5, 2]]


@pytest.mark.parametrize(
    "text, fragment",
    [
        ("*NODE\n1, 0, 0\n2, 1, 0\n3, 1, 1\n*ELEMENT, TYPE=CAX3\n1, 1, 2, 3\n", "unsupported element type 'CAX3'"),
        ("*NODE\n1,0,0\n2,1,0\n3,1,1\n4,0,1\n*ELEMENT, TYPE=CAX4R\n1, 1, 2, 3, 4\n*NSET, NSET=a\nmissing\n",
         "unknown set 'missing'"),
        ("*NODE\n1,0,0\n2,1,0\n3,1,1\n4,0,1\n*ELEMENT, TYPE=CAX4R\n1, 1, 2, 4, 3\n", "element 0 .* inverted"),
        ("*NODE\n1,0,0\n2,1,0\n3,1,1\n4,0,1\n*ELEMENT, TYPE=CAX4R\n1, 1, 2, 3, 9\n", "node 9"),
        ("*NODE\n1,0,0\n2,1,0\n3,1,1\n4,0,1\n*ELEMENT, TYPE=CAX4R\n1, 1, 2, 3, 4\n"
         "*SURFACE, NAME=s\n1, S7\n", "'S7'"),
    ],
)
def test_bad_inp_files_are_one_line_errors(tmp_path, text, fragment):
    path = tmp_path / "bad.inp"
    path.write_text(text)
    with pytest.raises(InputError, match=fragment) as error:
        read_mesh(path)
    assert "\n" not in str(error.value)


def test_bad_files_and_flags_are_one_line_errors(tmp_path, meshes):
    with pytest.raises(InputError, match="unsupported cell type 'triangle'"):
        read_mesh(gmsh_square(tmp_path, "triangle"))
    with pytest.raises(InputError, match="not found"):
        read_mesh(tmp_path / "none.inp")
    (tmp_path / "eye.stl").write_text("solid")
    with pytest.raises(InputError, match="unknown mesh format"):
        read_mesh(tmp_path / "eye.stl")
    with pytest.raises(InputError, match="unknown mesh format"):
        write_mesh(meshes["quad"], tmp_path / "eye.obj")
    path = write_mesh(meshes["quad"], tmp_path / "eye.vtu")
    with pytest.raises(InputError, match="axisymmetric = true"):
        read_mesh(path, axisymmetric=False)
