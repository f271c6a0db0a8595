"""Small structured meshes for the solver tests (imported by the other test_solver_* files).

Each builder returns a valid :class:`corneasim.mesh.Mesh` with named node and surface sets;
the tests at the bottom check the builders themselves (orientation, volumes, sets).
"""

import numpy as np

from corneasim.mesh import HEXAHEDRON_FACES, QUAD_FACES, Mesh


def _surface(cells, local_faces, on_surface):
    """(element, face) rows of the faces whose nodes all satisfy ``on_surface`` (n_nodes bool)."""
    rows = [(e, k) for e in range(cells.shape[0]) for k in range(local_faces.shape[0])
            if on_surface[cells[e, local_faces[k]]].all()]
    return np.array(rows, dtype=np.int64).reshape(-1, 2)


def box_hex(nx, ny, nz, lx, ly, lz, x_nodes=None):
    """Hexahedra filling [0, lx] x [0, ly] x [0, lz]; node sets and surfaces x0, x1, y0, ... z1.

    ``x_nodes`` optionally gives the x coordinates of the node planes (graded meshes).
    """
    x = np.linspace(0, lx, nx + 1) if x_nodes is None else np.asarray(x_nodes, dtype=float)
    y, z = np.linspace(0, ly, ny + 1), np.linspace(0, lz, nz + 1)
    X, Y, Z = np.meshgrid(x, y, z, indexing="ij")
    points = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])
    index = np.arange(points.shape[0]).reshape(nx + 1, ny + 1, nz + 1)
    i, j, k = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij")
    i, j, k = i.ravel(), j.ravel(), k.ravel()
    cells = np.column_stack([index[i, j, k], index[i + 1, j, k], index[i + 1, j + 1, k],
                             index[i, j + 1, k], index[i, j, k + 1], index[i + 1, j, k + 1],
                             index[i + 1, j + 1, k + 1], index[i, j + 1, k + 1]]).astype(np.int64)
    node_sets, surface_sets = {}, {}
    for axis, name, length in ((0, "x", x[-1]), (1, "y", ly), (2, "z", lz)):
        for end, value in (("0", 0.0), ("1", length)):
            on = np.isclose(points[:, axis], value)
            node_sets[name + end] = np.flatnonzero(on).astype(np.int64)
            surface_sets[name + end] = _surface(cells, HEXAHEDRON_FACES, on)
    return Mesh(points, cells, "hexahedron", np.zeros(len(cells), np.int64), ["solid"], False,
                node_sets, {}, surface_sets)


def box_quad(nr, nz, r0, r1, z0, z1):
    """Axisymmetric quads filling r0 <= r <= r1, z0 <= z <= z1; sets r0, r1, z0, z1."""
    r, z = np.linspace(r0, r1, nr + 1), np.linspace(z0, z1, nz + 1)
    R, Z = np.meshgrid(r, z, indexing="ij")
    points = np.column_stack([R.ravel(), Z.ravel()])
    index = np.arange(points.shape[0]).reshape(nr + 1, nz + 1)
    i, k = np.meshgrid(np.arange(nr), np.arange(nz), indexing="ij")
    i, k = i.ravel(), k.ravel()
    cells = np.column_stack([index[i, k], index[i + 1, k], index[i + 1, k + 1],
                             index[i, k + 1]]).astype(np.int64)
    node_sets, surface_sets = {}, {}
    for axis, name, lo, hi in ((0, "r", r0, r1), (1, "z", z0, z1)):
        for end, value in (("0", lo), ("1", hi)):
            on = np.isclose(points[:, axis], value)
            node_sets[name + end] = np.flatnonzero(on).astype(np.int64)
            surface_sets[name + end] = _surface(cells, QUAD_FACES, on)
    return Mesh(points, cells, "quad", np.zeros(len(cells), np.int64), ["solid"], True,
                node_sets, {}, surface_sets)


def sphere_quarter_quad(inner, outer, n_radial, n_angle):
    """Axisymmetric quarter section of a thick sphere (r >= 0, z >= 0); sets inner, outer, equator."""
    radius = np.linspace(inner, outer, n_radial + 1)
    angle = np.linspace(0.0, np.pi / 2, n_angle + 1)  # from the equator (z = 0) to the pole
    A, Rd = np.meshgrid(angle, radius, indexing="ij")
    points = np.column_stack([(Rd * np.cos(A)).ravel(), (Rd * np.sin(A)).ravel()])
    points[np.isclose(points[:, 0], 0.0, atol=1e-12), 0] = 0.0
    index = np.arange(points.shape[0]).reshape(n_angle + 1, n_radial + 1)
    a, i = np.meshgrid(np.arange(n_angle), np.arange(n_radial), indexing="ij")
    a, i = a.ravel(), i.ravel()
    cells = np.column_stack([index[a, i], index[a, i + 1], index[a + 1, i + 1],
                             index[a + 1, i]]).astype(np.int64)
    distance = np.hypot(points[:, 0], points[:, 1])
    inner_on, outer_on = np.isclose(distance, inner), np.isclose(distance, outer)
    node_sets = {"inner": np.flatnonzero(inner_on), "outer": np.flatnonzero(outer_on),
                 "equator": np.flatnonzero(np.isclose(points[:, 1], 0.0))}
    surface_sets = {"inner": _surface(cells, QUAD_FACES, inner_on),
                    "outer": _surface(cells, QUAD_FACES, outer_on)}
    return Mesh(points, cells, "quad", np.zeros(len(cells), np.int64), ["shell"], True,
                node_sets, {}, surface_sets)


def sphere_octant_hex(inner, outer, n_radial, n_face):
    """Octant (x, y, z >= 0) of a thick sphere from three projected cube faces.

    Sets: inner, outer (nodes and surfaces), x0, y0, z0 (symmetry planes).
    """
    s = np.linspace(0.0, 1.0, n_face + 1)
    directions, quads = [], []
    for axis in range(3):
        others = [c for c in range(3) if c != axis]
        base = len(directions)
        for p in s:
            for q in s:
                vector = np.zeros(3)
                vector[axis] = 1.0
                vector[others[0]], vector[others[1]] = p, q
                directions.append(vector / np.linalg.norm(vector))
        for ip in range(n_face):
            for iq in range(n_face):
                n0 = base + ip * (n_face + 1) + iq
                quads.append([n0, n0 + n_face + 1, n0 + n_face + 2, n0 + 1])
    directions = np.array(directions)
    key = np.round(directions * 1e9).astype(np.int64)
    _, unique, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    directions, quads = directions[unique], inverse.ravel()[np.array(quads)]
    radius = np.linspace(inner, outer, n_radial + 1)
    n_dir = directions.shape[0]
    points = (radius[:, None, None] * directions[None]).reshape(-1, 3)
    points[np.abs(points) < 1e-12] = 0.0
    cells = []
    for layer in range(n_radial):
        for quad in quads:
            bottom, top = quad + layer * n_dir, quad + (layer + 1) * n_dir
            cell = np.concatenate([bottom, top])
            x = points[cell]
            normal = np.cross(x[1] - x[0], x[3] - x[0])
            if np.dot(normal, x[4] - x[0]) < 0:
                cell = np.concatenate([bottom[::-1], top[::-1]])
            cells.append(cell)
    cells = np.array(cells, dtype=np.int64)
    distance = np.linalg.norm(points, axis=1)
    inner_on, outer_on = np.isclose(distance, inner), np.isclose(distance, outer)
    node_sets = {"inner": np.flatnonzero(inner_on), "outer": np.flatnonzero(outer_on)}
    for axis, name in enumerate("xyz"):
        node_sets[f"{name}0"] = np.flatnonzero(np.isclose(points[:, axis], 0.0))
    surface_sets = {"inner": _surface(cells, HEXAHEDRON_FACES, inner_on),
                    "outer": _surface(cells, HEXAHEDRON_FACES, outer_on)}
    return Mesh(points, cells, "hexahedron", np.zeros(len(cells), np.int64), ["shell"], False,
                node_sets, {}, surface_sets)


def _hex_volumes(mesh):
    """Volumes of hexahedra by splitting each into 6 tetrahedra (exact for planar faces)."""
    x = mesh.points[mesh.cells]
    tets = [(0, 1, 2, 6), (0, 2, 3, 6), (0, 3, 7, 6), (0, 7, 4, 6), (0, 4, 5, 6), (0, 5, 1, 6)]
    return sum(np.einsum("ei,ei->e", x[:, b] - x[:, a], np.cross(x[:, c] - x[:, a], x[:, d] - x[:, a]))
               for a, b, c, d in tets) / 6.0


def test_box_hex_is_valid_and_fills_the_box():
    mesh = box_hex(3, 2, 2, 3.0, 2.0, 1.0)
    mesh.validate()
    assert np.all(_hex_volumes(mesh) > 0)
    assert np.isclose(_hex_volumes(mesh).sum(), 6.0)
    assert mesh.surface_sets["x1"].shape == (4, 2)


def test_sphere_octant_is_valid_and_positive():
    mesh = sphere_octant_hex(1.0, 2.0, 2, 3)
    mesh.validate()
    assert np.all(_hex_volumes(mesh) > 0)
    exact = np.pi / 6 * (2.0 ** 3 - 1.0)
    assert abs(_hex_volumes(mesh).sum() - exact) / exact < 0.1
    assert len(mesh.surface_sets["inner"]) == 27


def test_sphere_quarter_is_counter_clockwise():
    mesh = sphere_quarter_quad(1.0, 2.0, 2, 4)
    mesh.validate()
    x = mesh.points[mesh.cells]
    area = 0.5 * ((x[:, 2, 0] - x[:, 0, 0]) * (x[:, 3, 1] - x[:, 1, 1])
                  - (x[:, 3, 0] - x[:, 1, 0]) * (x[:, 2, 1] - x[:, 0, 1]))
    assert np.all(area > 0)
    assert len(mesh.surface_sets["inner"]) == 4
