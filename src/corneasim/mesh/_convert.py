"""Quadratic elements split into the linear ones the kernels integrate, on import.

The element kernels are 4-node quads (axisymmetric) and 8-node hexahedra. A mesh of
8-node quads (Abaqus CAX8*), 20-node hexahedra (C3D20*) or 10-node tetrahedra (C3D10*)
is converted without losing a node or the geometry its midside nodes describe:

* **8-node quad** -> 4 quads: the 3 x 3 grid of its corners, midside nodes and a new
  centre node at the element's isoparametric centre
  x_c = -1/4 sum(corners) + 1/2 sum(midsides) (serendipity shape functions at xi = eta = 0).
* **20-node hexahedron** -> 8 hexahedra: the 3 x 3 x 3 grid of its corners, midside nodes,
  one new node per face at the face's serendipity centre (as above; shared by the two
  elements of an inner face) and one at the element centre
  x_c = -1/4 sum(corners) + 1/4 sum(midsides).
* **10-node tetrahedron** -> 4 hexahedra, one per corner, through its three edge midside
  nodes, its three face centres and the element centre (the standard tetrahedron-to-hexahedron
  split; the kernels have no tetrahedron). Face centres are the quadratic triangle at the
  centroid, x_f = -1/9 sum(corners) + 4/9 sum(midsides); the centre is the quadratic
  tetrahedron at L_i = 1/4, x_c = -1/8 sum(corners) + 1/4 sum(midsides).

Nodes keep their indices (new nodes are appended), so node sets are kept as they are;
element sets and blocks hold the children of their elements; a face of a surface becomes
the children's faces that tile it. The split linear mesh has the quadratic mesh's nodes,
so it is as fine as the quadratic mesh's node spacing (twice as many elements per
direction); a linear element is less accurate per node than a quadratic one, which is the
price of the explicit kernels (Belytschko, Liu & Moran, *Nonlinear Finite Elements*, 2000,
section 8.4, on lumped-mass quadratic elements in explicit codes).
Node orders are Abaqus's (= VTK's): corners first, then the midsides of the edges.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from corneasim.errors import InputError
from corneasim.mesh._mesh import HEXAHEDRON_FACES, QUAD_FACES

LINEAR_TYPE = {"quad8": "quad", "hexahedron20": "hexahedron", "tetra10": "hexahedron"}
"""Linear cell type each quadratic type is split into."""

NODES = {"quad": 4, "hexahedron": 8, "quad8": 8, "hexahedron20": 20, "tetra10": 10}
"""Nodes per cell of every type read."""

FACE_COUNT = {"quad": 4, "hexahedron": 6, "quad8": 4, "hexahedron20": 6, "tetra10": 4}
"""Faces per cell (the S1..Sn labels of an element-based surface)."""

DESCRIPTION = {"quad8": "8-node quads", "hexahedron20": "20-node hexahedra", "tetra10": "10-node tetrahedra"}

QUAD_CORNERS = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]])
HEXAHEDRON_CORNERS = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                               [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]])
QUAD8_EDGES = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
HEXAHEDRON20_EDGES = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4],
                               [0, 4], [1, 5], [2, 6], [3, 7]])
TETRA10_EDGES = np.array([[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]])
TETRA_FACES = np.array([[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]])
"""Corners of the faces S1..S4 of a tetrahedron (Abaqus order)."""
TETRA_FRAMES = np.array([[0, 1, 2, 3], [1, 2, 0, 3], [2, 0, 1, 3], [3, 0, 2, 1]])
"""Corner i and its neighbours (j, k, l) as an even permutation: the child hexahedron at i
spans c_i -> m_ij (xi), m_ik (eta), m_il (zeta) with the tetrahedron's orientation."""


@dataclass
class Split:
    """A quadratic mesh split into linear cells.

    Attributes
    ----------
    points : ndarray, shape (n_nodes + n_new, dim)
        The original nodes followed by the new face and centre nodes, mm.
    cells : ndarray, shape (n_elements * children, 4 or 8)
        Child cells; the children of element e are rows e * children ... e * children + children - 1.
    cell_type : str
        ``quad`` or ``hexahedron``.
    children : int
        Children per element.
    face_children : list of list of (int, int)
        For parent face f: the (child, child local face) pairs that tile it.
    face_centres : dict of tuple to int
        Sorted corner nodes of a parent face -> its new centre node (3D only).
    """

    points: np.ndarray
    cells: np.ndarray
    cell_type: str
    children: int
    face_children: list
    face_centres: dict


def check_midsides(points: np.ndarray, cells: np.ndarray, edges: np.ndarray, source: str) -> None:
    """Raise :class:`InputError` if a midside node is not near the middle of its edge.

    A midside node farther than half the edge length from the edge's midpoint means the
    connectivity is not in the expected order (corners first, then the edges' midsides).
    """
    a, b = points[cells[:, edges[:, 0]]], points[cells[:, edges[:, 1]]]
    m = points[cells[:, len(cells[0]) - len(edges):]]
    offset = np.linalg.norm(m - 0.5 * (a + b), axis=-1)
    length = np.linalg.norm(b - a, axis=-1)
    bad = np.argwhere(offset > 0.5 * length)
    if bad.size:
        element, edge = (int(v) for v in bad[0])
        raise InputError(f"{source}: element {element}: its node {cells.shape[1] - len(edges) + edge + 1} is not near the middle of "
                         f"the edge of its nodes {edges[edge, 0] + 1}-{edges[edge, 1] + 1} (expected the corners first, then the "
                         "midsides of the edges in Abaqus order)")


def _grid_split(points: np.ndarray, cells: np.ndarray, corners: np.ndarray, edges: np.ndarray,
                faces: np.ndarray, centre_weights: tuple[float, float]) -> Split:
    """Split quad8 (2D) or hexahedron20 (3D) cells through the 3^d grid of their natural coordinates."""
    dim = corners.shape[1]
    n = len(cells)
    natural = {tuple(c): k for k, c in enumerate(corners)}
    natural.update({tuple((corners[a] + corners[b]) // 2): len(corners) + k for k, (a, b) in enumerate(edges)})
    new_points = [points]
    next_node = len(points)
    grid: dict[tuple, np.ndarray] = {}  # natural coordinates -> (n,) global nodes
    face_centres: dict[tuple, int] = {}
    for key in itertools.product((-1, 0, 1), repeat=dim):
        if key in natural:
            grid[key] = cells[:, natural[key]]
    if dim == 3:
        for face in faces:
            key = tuple(corners[face].sum(axis=0) // 4)
            mids = [natural[tuple((corners[a] + corners[b]) // 2)] for a, b in zip(face, np.roll(face, -1))]
            centre = -0.25 * points[cells[:, face]].sum(axis=1) + 0.5 * points[cells[:, mids]].sum(axis=1)
            grid[key], next_node = _face_centre_nodes(cells[:, face], centre, face_centres, next_node,
                                                      new_points)
    weight_corner, weight_mid = centre_weights
    centre = weight_corner * points[cells[:, :len(corners)]].sum(axis=1) \
        + weight_mid * points[cells[:, len(corners):]].sum(axis=1)
    grid[(0,) * dim] = next_node + np.arange(n)
    new_points.append(centre)
    origins = list(itertools.product((-1, 0), repeat=dim))
    offsets = (corners + 1) // 2  # (k, dim) in {0, 1}
    child_keys = [[tuple(np.array(origin) + offset) for offset in offsets] for origin in origins]
    child_cells = np.stack([np.column_stack([grid[key] for key in keys]) for keys in child_keys], axis=1)
    linear_faces = QUAD_FACES if dim == 2 else HEXAHEDRON_FACES
    face_children = []
    for face in linear_faces:
        axis = int(np.flatnonzero(np.all(corners[face] == corners[face][0], axis=0))[0])
        side = corners[face][0, axis]
        tiles = [(child, local) for child, keys in enumerate(child_keys) for local, nodes in enumerate(linear_faces)
                 if all(keys[node][axis] == side for node in nodes)]
        face_children.append(tiles)
    return Split(np.concatenate(new_points), child_cells.reshape(n * len(origins), -1),
                 "quad" if dim == 2 else "hexahedron", len(origins), face_children, face_centres)


def _face_centre_nodes(face_corners: np.ndarray, centre: np.ndarray, face_centres: dict,
                       next_node: int, new_points: list) -> tuple[np.ndarray, int]:
    """Node numbers of the centres of one face of every cell, shared by the cells that share it.

    A face is known by its sorted corner nodes: a centre already numbered (in ``face_centres``,
    by a neighbour) is reused; new ones are numbered from ``next_node`` and their positions,
    taken from ``centre`` (one row per cell), appended to ``new_points``. Returns the cells'
    centre nodes and the next free node number.
    """
    unique, first, inverse = np.unique(np.sort(face_corners, axis=1), axis=0, return_index=True,
                                       return_inverse=True)
    known = np.array([face_centres.get(tuple(row), -1) for row in unique.tolist()], dtype=np.int64)
    fresh = np.flatnonzero(known < 0)
    known[fresh] = next_node + np.arange(fresh.size)
    new_points.append(centre[first[fresh]])
    face_centres.update({tuple(unique[i].tolist()): int(known[i]) for i in range(len(unique))})
    return known[inverse.ravel()], next_node + fresh.size


def _tetra_split(points: np.ndarray, cells: np.ndarray) -> Split:
    """Split tetra10 cells into 4 hexahedra each (see the module notes)."""
    n = len(cells)
    mid = {frozenset(edge.tolist()): 4 + k for k, edge in enumerate(TETRA10_EDGES)}
    new_points = [points]
    next_node = len(points)
    face_node: dict[frozenset, np.ndarray] = {}
    face_centres: dict[tuple, int] = {}
    for face in TETRA_FACES:
        mids = [mid[frozenset((a, b))] for a, b in zip(face, np.roll(face, -1))]
        centre = -points[cells[:, face]].sum(axis=1) / 9.0 + 4.0 * points[cells[:, mids]].sum(axis=1) / 9.0
        face_node[frozenset(face.tolist())], next_node = _face_centre_nodes(
            cells[:, face], centre, face_centres, next_node, new_points)
    centre_node = next_node + np.arange(n)
    new_points.append(-points[cells[:, :4]].sum(axis=1) / 8.0 + points[cells[:, 4:]].sum(axis=1) / 4.0)
    children = []
    for i, j, k, l in TETRA_FRAMES:
        children.append(np.column_stack([
            cells[:, i], cells[:, mid[frozenset((i, j))]], face_node[frozenset((i, j, k))], cells[:, mid[frozenset((i, k))]],
            cells[:, mid[frozenset((i, l))]], face_node[frozenset((i, j, l))], centre_node, face_node[frozenset((i, k, l))],
        ]))
    hex_face = {frozenset((1, 2)): 0, frozenset((1, 3)): 2, frozenset((2, 3)): 5}  # (xi, eta) / (xi, zeta) / (eta, zeta)
    face_children = []
    for face in TETRA_FACES:
        tiles = []
        for child, frame in enumerate(TETRA_FRAMES):
            if frame[0] in face:
                others = frozenset(int(np.flatnonzero(frame == c)[0]) for c in face if c != frame[0])
                tiles.append((child, hex_face[others]))
        face_children.append(tiles)
    return Split(np.concatenate(new_points), np.stack(children, axis=1).reshape(4 * n, 8), "hexahedron", 4,
                 face_children, face_centres)


def split_cells(points: np.ndarray, cells: np.ndarray, cell_type: str, source: str = "mesh") -> Split:
    """Split quadratic cells (``quad8``, ``hexahedron20``, ``tetra10``) into linear ones (module notes)."""
    if cell_type == "quad8":
        check_midsides(points, cells, QUAD8_EDGES, source)
        return _grid_split(points, cells, QUAD_CORNERS, QUAD8_EDGES, np.zeros((0, 2), int), (-0.25, 0.5))
    if cell_type == "hexahedron20":
        check_midsides(points, cells, HEXAHEDRON20_EDGES, source)
        return _grid_split(points, cells, HEXAHEDRON_CORNERS, HEXAHEDRON20_EDGES, HEXAHEDRON_FACES, (-0.25, 0.25))
    if cell_type == "tetra10":
        check_midsides(points, cells, TETRA10_EDGES, source)
        return _tetra_split(points, cells)
    raise InputError(f"{source}: cannot split cell type '{cell_type}' (expected quad8, hexahedron20 or tetra10)")


def children_of(elements: np.ndarray, children: int) -> np.ndarray:
    """Child cell indices of parent ``elements`` (children of e: e * children + 0 .. children - 1)."""
    return (np.asarray(elements, dtype=np.int64)[:, None] * children + np.arange(children)).ravel()


def child_faces(faces: np.ndarray, split: Split) -> np.ndarray:
    """(element, face) rows of parent faces -> the (child, face) rows that tile them."""
    rows = [(element * split.children + child, local) for element, face in np.asarray(faces).tolist()
            for child, local in split.face_children[face]]
    return np.array(rows, dtype=np.int64).reshape(-1, 2)


def face_node_children(faces: np.ndarray, split: Split) -> np.ndarray:
    """Quadratic faces as node rows (line3, triangle6, quad8; corners first) -> the linear faces tiling them."""
    faces = np.asarray(faces, dtype=np.int64)
    if faces.shape[1] == 3:  # line3: a, b, midside
        return np.concatenate([faces[:, [0, 2]], faces[:, [2, 1]]])
    corners = faces.shape[1] // 2
    centre = np.array([split.face_centres.get(tuple(sorted(row[:corners])), -1) for row in faces.tolist()])
    if (centre < 0).any():
        raise InputError(f"a face (nodes {faces[int(np.flatnonzero(centre < 0)[0])].tolist()}) is no element face")
    rows = []
    for k in range(corners):
        rows.append(np.column_stack([faces[:, k], faces[:, corners + k], centre, faces[:, corners + (k - 1) % corners]]))
    return np.concatenate(rows)


def conversion_note(source: str, cell_type: str, n_elements: int, split: Split, n_nodes: int) -> str:
    """The one line that says what the import did."""
    linear = "4-node quads" if split.cell_type == "quad" else "8-node hexahedra"
    return (f"{source}: {n_elements} {DESCRIPTION[cell_type]} split into {len(split.cells)} {linear} through their "
            f"midside nodes ({len(split.points) - n_nodes} new face/centre nodes); sets kept")
