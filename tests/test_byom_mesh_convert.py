"""Quadratic meshes (8-node quads, 20-node hexahedra, 10-node tetrahedra) split on import.

Independent truths: a tensor-product grid of quadratic elements, split through its
midside nodes, is the linear grid of twice the density on the same coordinates (the
serendipity centre of a tensor-product element is its mid-grid point); a straight-edged
10-node tetrahedron's children have its edge midpoints, face centroids and centroid as
nodes and fill its volume; sets are the same nodes, elements and faces.
"""

import warnings

import meshio
import numpy as np
import pytest

from corneasim.cli.main import main as cli_main
from corneasim.errors import InputError
from corneasim.mesh import read_mesh
from corneasim.mesh import MeshConversion, element_measures
from corneasim.mesh._quality import corner_jacobians

R_GRID = np.array([0.0, 0.3, 0.7, 1.2, 2.0])  # graded node coordinates, mm (quadratic: corners at even indices)
Z_GRID = np.array([0.0, 0.25, 0.5, 1.0, 1.5])


def _lines(rows, per_line=8):
    out = []
    for row in rows:
        tokens = [str(v) for v in row]
        out.append(",\n".join(", ".join(tokens[i:i + per_line]) for i in range(0, len(tokens), per_line)))
    return "\n".join(out)


def _grid_nodes(*axes):
    grids = np.meshgrid(*axes, indexing="ij")
    points = np.column_stack([g.ravel() for g in grids])
    index = np.arange(len(points)).reshape([len(a) for a in axes])
    return points, index


def quad8_inp(path):
    """2 x 2 CAX8R elements on the (R_GRID, Z_GRID) corners/midsides; sets bottom, top_surface, left elements."""
    points, node = _grid_nodes(R_GRID, Z_GRID)
    used = [(i, j) for i in range(5) for j in range(5) if not (i % 2 and j % 2)]
    label = {key: k + 1 for k, key in enumerate(used)}
    elements = []
    for j in (0, 2):
        for i in (0, 2):
            corners = [(i, j), (i + 2, j), (i + 2, j + 2), (i, j + 2)]
            mids = [(i + 1, j), (i + 2, j + 1), (i + 1, j + 2), (i, j + 1)]
            elements.append([len(elements) + 1] + [label[c] for c in corners + mids])
    text = "*NODE\n" + "\n".join(f"{label[(i, j)]}, {R_GRID[i]}, {Z_GRID[j]}" for i, j in used)
    text += "\n*ELEMENT, TYPE=CAX8R, ELSET=solid\n" + _lines(elements)
    text += "\n*NSET, NSET=bottom\n" + ", ".join(str(label[(i, 0)]) for i in range(5))
    text += "\n*ELSET, ELSET=left\n1, 3\n*ELSET, ELSET=top_faces\n3, 4\n"
    text += "*SURFACE, TYPE=ELEMENT, NAME=top_surface\ntop_faces, S3\n"
    path.write_text(text)
    return path


def test_8_node_quads_read_as_the_split_4_node_grid(tmp_path):
    with pytest.warns(MeshConversion, match="4 8-node quads split into 16 4-node quads .* \\(4 new face/centre nodes\\)"):
        mesh = read_mesh(quad8_inp(tmp_path / "quad8.inp"))
    assert mesh.cell_type == "quad" and mesh.axisymmetric and mesh.n_elements == 16 and mesh.n_nodes == 25
    points, node = _grid_nodes(R_GRID, Z_GRID)
    expected = {tuple(sorted(map(tuple, np.round(points[[node[i, j], node[i + 1, j], node[i + 1, j + 1], node[i, j + 1]]], 12))))
                for i in range(4) for j in range(4)}
    got = {tuple(sorted(map(tuple, np.round(mesh.points[cell], 12)))) for cell in mesh.cells}
    assert got == expected
    assert (corner_jacobians(mesh) > 0).all()
    assert element_measures(mesh).sum() == pytest.approx(2.0 * 1.5)
    np.testing.assert_allclose(np.sort(mesh.points[mesh.node_sets["bottom"], 0]), R_GRID)
    assert np.all(mesh.points[mesh.node_sets["bottom"], 1] == 0.0)
    left = mesh.points[mesh.cells[mesh.element_sets["left"]]]
    assert len(mesh.element_sets["left"]) == 8 and left[..., 0].max() == pytest.approx(0.7)
    top = mesh.points[mesh.face_nodes("top_surface")]  # (faces, 2, 2)
    assert len(top) == 4 and np.all(top[..., 1] == 1.5)
    np.testing.assert_allclose(np.sort(np.unique(top[..., 0])), R_GRID)


def hex20_inp(path):
    """1 x 1 x 2 C3D20R elements (a stack of two) with a bottom surface and a node set."""
    x, y, z = np.array([0.0, 0.4, 1.0]), np.array([0.0, 0.5, 1.0]), np.array([0.0, 0.3, 0.8, 1.1, 1.6])
    points, node = _grid_nodes(x, y, z)
    corners = np.array([[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0], [0, 0, 2], [2, 0, 2], [2, 2, 2], [0, 2, 2]])
    edges = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)]
    rows, used = [], set()
    for k in (0, 2):
        grid = [tuple(c + [0, 0, k]) for c in corners] + [tuple((corners[a] + corners[b]) // 2 + [0, 0, k])
                                                          for a, b in edges]
        used.update(grid)
        rows.append([len(rows) + 1] + [int(node[g]) + 1 for g in grid])
    text = "*NODE\n" + "\n".join(f"{int(node[g]) + 1}, {', '.join(map(str, points[node[g]]))}" for g in sorted(used))
    text += "\n*ELEMENT, TYPE=C3D20R, ELSET=block\n" + _lines(rows, per_line=16)
    text += "\n*NSET, NSET=base\n" + ", ".join(str(int(node[g]) + 1) for g in sorted(used) if g[2] == 0)
    text += "\n*SURFACE, TYPE=ELEMENT, NAME=floor\n1, S1\n"
    path.write_text(text)
    return path, points, node


def test_20_node_hexahedra_read_as_the_split_8_node_grid(tmp_path):
    path, points, node = hex20_inp(tmp_path / "hex20.inp")
    with pytest.warns(MeshConversion, match="2 20-node hexahedra split into 16 8-node hexahedra"):
        mesh = read_mesh(path)
    assert mesh.n_elements == 16 and mesh.n_nodes == points.shape[0]
    expected = set()
    for i, j, k in np.ndindex(2, 2, 4):
        cube = [node[i + a, j + b, k + c] for a in (0, 1) for b in (0, 1) for c in (0, 1)]
        expected.add(tuple(sorted(map(tuple, np.round(points[cube], 12)))))
    assert {tuple(sorted(map(tuple, np.round(mesh.points[cell], 12)))) for cell in mesh.cells} == expected
    assert (corner_jacobians(mesh) > 0).all()
    assert element_measures(mesh).sum() == pytest.approx(1.6)
    assert len(mesh.node_sets["base"]) == 8 and np.all(mesh.points[mesh.node_sets["base"], 2] == 0.0)
    floor = mesh.points[mesh.face_nodes("floor")]
    assert floor.shape == (4, 4, 3) and np.all(floor[..., 2] == 0.0)
    assert len({tuple(sorted(map(tuple, face))) for face in floor}) == 4


def cube_tetra10(path):
    """The unit cube as 5 straight-edged C3D10 tetrahedra (with a 'bottom' surface on z = 0)."""
    cube = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    tets = [[0, 1, 3, 4], [1, 2, 3, 6], [1, 4, 5, 6], [3, 6, 7, 4], [1, 3, 4, 6]]
    points, index = list(cube), {}
    rows = []
    for tet in tets:
        a, b, c, d = tet
        if np.dot(np.cross(cube[b] - cube[a], cube[c] - cube[a]), cube[d] - cube[a]) < 0:
            tet = [a, c, b, d]
        mids = []
        for p, q in ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)):
            key = frozenset((tet[p], tet[q]))
            if key not in index:
                index[key] = len(points)
                points.append(0.5 * (cube[tet[p]] + cube[tet[q]]))
            mids.append(index[key])
        rows.append(tet + mids)
    text = "*NODE\n" + "\n".join(f"{k + 1}, {p[0]}, {p[1]}, {p[2]}" for k, p in enumerate(points))
    text += "\n*ELEMENT, TYPE=C3D10, ELSET=cube\n" + _lines([[e + 1] + [v + 1 for v in r] for e, r in enumerate(rows)])
    faces = []
    for e, r in enumerate(rows):
        for label, face in enumerate(([0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]), start=1):
            if all(cube[r[v]][2] == 0 for v in face):
                faces.append(f"{e + 1}, S{label}")
    text += "\n*NSET, NSET=corners\n1, 2, 3, 4, 5, 6, 7, 8\n*SURFACE, TYPE=ELEMENT, NAME=bottom\n" + "\n".join(faces)
    path.write_text(text + "\n")
    return path, np.array(points), np.array(rows), cube


def test_10_node_tetrahedra_become_4_hexahedra_each(tmp_path):
    path, points, rows, cube = cube_tetra10(tmp_path / "tet10.inp")
    with pytest.warns(MeshConversion, match="5 10-node tetrahedra split into 20 8-node hexahedra"):
        mesh = read_mesh(path)
    assert mesh.n_elements == 20 and (corner_jacobians(mesh) > 0).all()
    assert element_measures(mesh).sum() == pytest.approx(1.0)
    expected = {tuple(p) for p in points}  # corners and edge midpoints
    c = cube[rows[:, :4]]  # (5, 4, 3)
    expected |= {tuple(v) for v in c.mean(axis=1)}
    for face in ([0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]):
        expected |= {tuple(v) for v in c[:, face].mean(axis=1)}
    got = {tuple(p) for p in np.round(mesh.points, 12)}
    assert got == {tuple(np.round(p, 12)) for p in expected}
    assert mesh.n_nodes == len(expected)  # shared face centres are one node
    np.testing.assert_array_equal(mesh.node_sets["corners"], np.arange(8))
    bottom = mesh.points[mesh.face_nodes("bottom")]
    assert np.all(bottom[..., 2] == 0.0) and len(bottom) == 6  # 2 triangles x 3 quads
    area = 0.5 * np.linalg.norm(np.cross(bottom[:, 2] - bottom[:, 0], bottom[:, 3] - bottom[:, 1]), axis=-1)
    assert area.sum() == pytest.approx(1.0)


def test_meshio_quad8_file_is_split_like_the_inp(tmp_path):
    with pytest.warns(MeshConversion):
        reference = read_mesh(quad8_inp(tmp_path / "quad8.inp"))
    points, node = _grid_nodes(R_GRID, Z_GRID)
    cells = [[node[i, j], node[i + 2, j], node[i + 2, j + 2], node[i, j + 2],
              node[i + 1, j], node[i + 2, j + 1], node[i + 1, j + 2], node[i, j + 1]] for j in (0, 2) for i in (0, 2)]
    path = tmp_path / "quad8.vtu"
    meshio.write(path, meshio.Mesh(np.column_stack([points, np.zeros(len(points))]), [("quad8", np.array(cells))]))
    with pytest.warns(MeshConversion):
        mesh = read_mesh(path)
    assert {tuple(sorted(map(tuple, mesh.points[c]))) for c in mesh.cells} == \
        {tuple(sorted(map(tuple, reference.points[c]))) for c in reference.cells}


@pytest.mark.parametrize("element, fragment", [("S8R", "shell element"), ("CPE8", "plane-strain"),
                                                ("C3D6", "expected CAX4")])
def test_unsupported_types_say_why(tmp_path, element, fragment):
    path = tmp_path / "bad.inp"
    path.write_text(f"*NODE\n1, 0, 0\n*ELEMENT, TYPE={element}\n1, 1, 1, 1, 1, 1, 1, 1, 1\n")
    with pytest.raises(InputError, match=fragment):
        read_mesh(path)


def test_midside_out_of_order_is_input_error(tmp_path):
    text = quad8_inp(tmp_path / "quad8.inp").read_text().replace("1, 1, 9, 11, 3, 6, 10, 7,", "1, 1, 9, 11, 3, 10, 6, 7,")
    assert text != (tmp_path / "quad8.inp").read_text()
    (tmp_path / "swapped.inp").write_text(text)
    with pytest.raises(InputError, match="element 0: its node 5 is not near the middle of the edge of its nodes 1-2"):
        read_mesh(tmp_path / "swapped.inp")


def test_cli_mesh_convert_writes_the_linear_mesh(tmp_path, capsys):
    source = quad8_inp(tmp_path / "quad8.inp")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(SystemExit) as stop:
            cli_main(["mesh", "convert", str(source), str(tmp_path / "linear.inp")])
    assert stop.value.code == 0
    out = capsys.readouterr().out
    assert "split into 16 4-node quads" in out and "linear.inp" in out
    again = read_mesh(tmp_path / "linear.inp")
    assert again.n_elements == 16 and set(again.node_sets) == {"bottom"} and "top_surface" in again.surface_sets
    with pytest.raises(SystemExit) as stop:
        cli_main(["mesh", "convert", str(source)])
    assert stop.value.code == 2
