"""Mesh files: export to ParaView (VTU, XDMF) and Abaqus/CalculiX (.inp); import any of them or Gmsh.

Mapping of a file's groups to :class:`~corneasim.mesh.Mesh` (see ``docs/geometry.md``):

* **Formats**: ``.inp`` by our own reader/writer (CAX4R / C3D8R, ``*SURFACE``); ``.vtu``,
  ``.vtk`` and Gmsh ``.msh`` through meshio; ``.xdmf`` written by :mod:`._xdmf` (inline XML);
  reading ``.xdmf`` goes through meshio and needs the optional h5py package.
* **Elements** are the quads (2D, read as axisymmetric (r, z)) or hexahedra (3D) of the
  file. Lines in 2D and quads in 3D are boundary faces; vertices and other lower
  cells only carry sets. Quadratic cells (8-node quads, 20-node hexahedra, 10-node
  tetrahedra; faces: 3-node lines, 8-node quads, 6-node triangles) are split into linear
  ones on import (:mod:`.convert`), with one warning line that says so. Any other cell type
  (triangles, linear tetrahedra, wedges) is rejected.
* **Blocks** (one material each): the ``*ELEMENT, ELSET=`` sections of an ``.inp``;
  the Gmsh physical groups of the element dimension; our ``block:NAME`` cell-data masks
  in VTU/XDMF; otherwise one block per cell block (``block0``, ...).
* **Element sets**: ``*ELSET`` (and meshio cell sets) that are not blocks; ``elset:NAME``.
* **Node sets**: ``*NSET``, point sets, ``nset:NAME`` point data, and the nodes of every
  lower-dimensional Gmsh physical group.
* **Surface sets**: element-based ``*SURFACE``; Gmsh physical groups of faces (lines in
  2D, quads in 3D), matched to element faces; ``surface:NAME`` cell-data bit masks (bit k:
  local face k).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from corneasim.errors import InputError
from corneasim.mesh._abaqus import RawMesh, read_inp, write_inp
from corneasim.mesh._mesh import Mesh
from corneasim.mesh._sets import local_faces
from corneasim.mesh._xdmf import write_xdmf
from corneasim.mesh._convert import (
    FACE_COUNT, LINEAR_TYPE, child_faces, children_of, conversion_note, face_node_children, split_cells)
from corneasim.mesh._quality import check_elements

MESHIO_SUFFIXES = (".vtu", ".vtk", ".xdmf", ".xmf")
READ_SUFFIXES = (".inp", ".msh", *MESHIO_SUFFIXES)
FACE_TYPE = {"quad": "line", "hexahedron": "quad"}
QUADRATIC_FACE_TYPES = {"quad8": ("line3",), "hexahedron20": ("quad8",), "tetra10": ("triangle6",)}
"""Face cell types of a Gmsh/VTU file of quadratic cells (their groups become surfaces)."""
FACE_DIMENSION = {"vertex": 0, "line": 1, "line3": 1, "quad": 2, "quad8": 2, "triangle6": 2}


class MeshConversion(UserWarning):
    """Issued (one line) when a mesh of quadratic cells is split into linear cells on import."""


def write_mesh(mesh: Mesh, path: str | Path) -> Path:
    """Write ``mesh`` to ``path``; the format follows the suffix (.inp, .vtu, .vtk, .xdmf)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".inp":
        write_inp(mesh, path)
    elif suffix in (".xdmf", ".xmf"):
        data = to_meshio(mesh)
        write_xdmf(path, data.points, mesh.cell_type, mesh.cells,
                   {name: values[0] for name, values in data.cell_data.items()}, data.point_data)
    elif suffix in MESHIO_SUFFIXES:
        to_meshio(mesh).write(path)
    else:
        raise InputError(f"{path}: unknown mesh format '{suffix}' (expected .inp, .vtu, .vtk or .xdmf)")
    return path


def to_meshio(mesh: Mesh):
    """A meshio mesh with blocks, sets and surfaces as cell and point data (see module notes)."""
    import meshio

    points = mesh.points if mesh.dim == 3 else np.column_stack([mesh.points, np.zeros(mesh.n_nodes)])
    cell_data = {"block": [mesh.element_block.astype(np.int32)]}
    for index, name in enumerate(mesh.block_names):
        cell_data[f"block:{name}"] = [(mesh.element_block == index).astype(np.int8)]
    for name, elements in mesh.element_sets.items():
        mask = np.zeros(mesh.n_elements, dtype=np.int8)
        mask[elements] = 1
        cell_data[f"elset:{name}"] = [mask]
    for name, faces in mesh.surface_sets.items():
        bits = np.zeros(mesh.n_elements, dtype=np.int32)
        np.bitwise_or.at(bits, faces[:, 0], 1 << faces[:, 1])
        cell_data[f"surface:{name}"] = [bits]
    point_data = {}
    for name, nodes in mesh.node_sets.items():
        mask = np.zeros(mesh.n_nodes, dtype=np.int8)
        mask[nodes] = 1
        point_data[f"nset:{name}"] = mask
    return meshio.Mesh(points, [(mesh.cell_type, mesh.cells)], point_data=point_data, cell_data=cell_data)


def read_mesh(path: str | Path, axisymmetric: bool | None = None) -> Mesh:
    """Read a mesh file (.inp, Gmsh .msh, .vtu, .vtk, .xdmf) with its named sets.

    Parameters
    ----------
    path : str or Path
    axisymmetric : bool, optional
        For 2D (quad) meshes: must be True or None (2D meshes are axisymmetric (r, z));
        for 3D meshes False or None.

    Returns
    -------
    Mesh
        Validated, with positive Jacobians (clockwise files are renumbered).
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: mesh file not found")
    suffix = path.suffix.lower()
    if suffix not in READ_SUFFIXES:
        raise InputError(f"{path}: unknown mesh format '{suffix}' (expected {', '.join(READ_SUFFIXES)})")
    try:
        raw = read_inp(path) if suffix == ".inp" else _read_meshio(path)
    except UnicodeDecodeError as error:
        raise InputError(f"{path}: not a text mesh file (not UTF-8 at byte {error.start})") from None
    if raw.cell_type in LINEAR_TYPE:
        raw, note = linear_mesh(raw, str(path))
        warnings.warn(note, MeshConversion, stacklevel=2)
    if raw.cell_type == "quad" and axisymmetric is False:
        raise InputError(f"{path}: a 2D quad mesh is read as axisymmetric (r, z); set axisymmetric = true")
    if raw.cell_type == "hexahedron" and axisymmetric:
        raise InputError(f"{path}: a hexahedral mesh cannot be axisymmetric")
    return assemble(raw, str(path))


def linear_mesh(raw: RawMesh, source: str) -> tuple[RawMesh, str]:
    """A raw mesh of quadratic cells split into linear cells (:mod:`.convert`), and the line saying so.

    Node sets are kept (nodes keep their indices); blocks and element sets hold the children
    of their elements; surfaces the faces that tile theirs.
    """
    split = split_cells(raw.points, raw.cells, raw.cell_type, source)
    try:
        face_sets = {name: face_node_children(faces, split) for name, faces in raw.face_sets.items()}
    except InputError as error:
        raise InputError(f"{source}: {error}") from None
    linear = RawMesh(
        split.points, split.cell_type, split.cells,
        [(name, children_of(elements, split.children)) for name, elements in raw.blocks],
        {name: children_of(elements, split.children) for name, elements in raw.element_sets.items()},
        dict(raw.node_sets), face_sets,
        {name: child_faces(faces, split) for name, faces in raw.surface_sets.items()})
    return linear, conversion_note(source, raw.cell_type, len(raw.cells), split, len(raw.points))


def _read_meshio(path: Path) -> RawMesh:
    import contextlib
    import io

    import meshio

    printed = io.StringIO()  # meshio prints its complaints (and may exit): they become the one line
    try:
        with contextlib.redirect_stdout(printed), contextlib.redirect_stderr(printed):
            data = meshio.read(path)
    except (Exception, SystemExit) as error:  # meshio raises many types for unreadable files, even SystemExit
        reason = "" if isinstance(error, SystemExit) else " ".join(str(error).split())
        reason = reason or " ".join(printed.getvalue().split()) or type(error).__name__
        raise InputError(f"{path}: cannot read mesh: {reason}") from None
    types = [block.type for block in data.cells]
    cell_type = next((name for name in ("hexahedron20", "tetra10", "hexahedron", "quad8", "quad") if name in types),
                     None)
    allowed = {"vertex", "line", cell_type, *QUADRATIC_FACE_TYPES.get(cell_type, ())}
    if cell_type == "hexahedron":
        allowed.add("quad")
    for name in types:
        if cell_type is None or name not in allowed:
            raise InputError(f"{path}: unsupported cell type '{name}' (expected quad or quad8 (axisymmetric), "
                             "hexahedron, hexahedron20 or tetra10)")
    points = np.asarray(data.points, dtype=float)
    if cell_type in ("quad", "quad8"):
        if points.shape[1] == 3 and np.abs(points[:, 2]).max(initial=0.0) > 1e-9:
            raise InputError(f"{path}: a quad mesh must lie in the (r, z) plane (third coordinate 0)")
        points = points[:, :2]
    volume = [i for i, name in enumerate(types) if name == cell_type]
    offsets = np.cumsum([0] + [len(data.cells[i].data) for i in volume])
    cells = np.concatenate([data.cells[i].data for i in volume]).astype(np.int64)
    raw = RawMesh(points, cell_type, cells, [])
    physical = data.cell_data.get("gmsh:physical")
    names = {}  # (physical tag, dimension) -> name
    for name, value in data.field_data.items():
        value = np.asarray(value).ravel()
        if value.size >= 2:
            names[(int(value[0]), int(value[1]))] = name
    dim = 2 if cell_type in ("quad", "quad8") else 3
    if any(key.startswith("block:") for key in data.cell_data):
        _read_conventions(data, volume, raw)
    elif physical is not None:
        _read_gmsh_groups(data, volume, offsets, physical, names, dim, raw)
    else:
        _read_cell_sets(data, volume, offsets, raw)
    for name, nodes in data.point_sets.items():
        raw.node_sets[name] = np.unique(np.asarray(nodes, dtype=np.int64))
    return raw


def _volume_data(data, key: str, volume: list[int]) -> np.ndarray:
    return np.concatenate([np.asarray(data.cell_data[key][i]).ravel() for i in volume])


def _read_conventions(data, volume, raw: RawMesh) -> None:
    for key in data.cell_data:
        kind, _, name = key.partition(":")
        if not name:
            continue
        values = _volume_data(data, key, volume).astype(np.int64)
        if kind == "block":
            raw.blocks.append((name, np.flatnonzero(values)))
        elif kind == "elset":
            raw.element_sets[name] = np.flatnonzero(values)
        elif kind == "surface":
            rows = [np.column_stack([np.flatnonzero(values & (1 << k)), np.full(np.count_nonzero(values & (1 << k)), k)])
                    for k in range(FACE_COUNT[raw.cell_type])]
            raw.surface_sets[name] = np.concatenate(rows).astype(np.int64)
    for key, values in data.point_data.items():
        kind, _, name = key.partition(":")
        if kind == "nset" and name:
            raw.node_sets[name] = np.flatnonzero(np.asarray(values).ravel())


def _read_gmsh_groups(data, volume, offsets, physical, names, dim, raw: RawMesh) -> None:
    tags = np.concatenate([np.asarray(physical[i]).ravel() for i in volume]).astype(np.int64)
    for tag in dict.fromkeys(tags.tolist()):
        raw.blocks.append((names.get((tag, dim), f"group{tag}"), np.flatnonzero(tags == tag)))
    face_types = (FACE_TYPE[raw.cell_type],) if raw.cell_type in FACE_TYPE else QUADRATIC_FACE_TYPES[raw.cell_type]
    groups: dict[str, list[np.ndarray]] = {}
    faces: dict[str, list[np.ndarray]] = {}
    for i, block in enumerate(data.cells):
        if i in volume:
            continue
        block_tags = np.asarray(physical[i]).ravel().astype(np.int64)
        for tag in np.unique(block_tags):
            group_dim = FACE_DIMENSION[block.type]
            name = names.get((int(tag), group_dim), f"group{tag}")
            selected = np.asarray(block.data)[block_tags == tag]
            groups.setdefault(name, []).append(selected.ravel())
            if block.type in face_types:
                faces.setdefault(name, []).append(selected)
    for name, nodes in groups.items():
        raw.node_sets[name] = np.unique(np.concatenate(nodes)).astype(np.int64)
    for name, rows in faces.items():
        raw.face_sets[name] = np.concatenate(rows).astype(np.int64)


def _read_cell_sets(data, volume, offsets, raw: RawMesh) -> None:
    block_names = {}
    for name, per_block in data.cell_sets.items():
        members = [np.asarray(per_block[i]).ravel() if i < len(per_block) and per_block[i] is not None
                   else np.zeros(0, np.int64) for i in range(len(data.cells))]
        elements = np.concatenate([members[i] + offsets[k] for k, i in enumerate(volume)]).astype(np.int64)
        whole = [k for k, i in enumerate(volume) if members[i].size == len(data.cells[i].data)]
        if len(whole) == 1 and elements.size == len(data.cells[volume[whole[0]]].data) and whole[0] not in block_names:
            block_names[whole[0]] = name
        elif elements.size:
            raw.element_sets[name] = np.unique(elements)
    for k in range(len(volume)):
        raw.blocks.append((block_names.get(k, f"block{k}"), np.arange(offsets[k], offsets[k + 1])))


def _face_lookup(cells: np.ndarray, cell_type: str) -> dict:
    local = local_faces(cell_type)
    nodes = np.sort(cells[:, local], axis=2)  # (n, f, k)
    return {tuple(row): (e, f) for e, per_element in enumerate(nodes.tolist()) for f, row in enumerate(per_element)}


def assemble(raw: RawMesh, source: str) -> Mesh:
    """Blocks, sets and faces of a raw mesh resolved into a validated :class:`Mesh`."""
    cells = raw.cells.copy()
    local = local_faces(raw.cell_type)
    face_sets = dict(raw.face_sets)
    for name, faces in raw.surface_sets.items():
        face_sets[name] = cells[faces[:, 0][:, None], local[faces[:, 1]]]
    cells = _reorient(raw.points, cells, raw.cell_type)
    element_block = np.full(len(cells), -1, dtype=np.int64)
    block_names = []
    for name, elements in raw.blocks:
        free = elements[element_block[elements] < 0]
        if free.size:
            element_block[free] = len(block_names)
            block_names.append(name)
    if (element_block < 0).any():
        element_block[element_block < 0] = len(block_names)
        block_names.append("unassigned")
    surface_sets = {}
    if face_sets:
        lookup = _face_lookup(cells, raw.cell_type)
        for name, nodes in face_sets.items():
            rows = []
            for face in np.sort(nodes, axis=1).tolist():
                if tuple(face) not in lookup:
                    raise InputError(f"{source}: surface '{name}' has a face (nodes {face}) that is no element face")
                rows.append(lookup[tuple(face)])
            surface_sets[name] = np.array(rows, dtype=np.int64).reshape(-1, 2)
    mesh = Mesh(
        points=raw.points, cells=cells, cell_type=raw.cell_type, element_block=element_block,
        block_names=block_names, axisymmetric=raw.cell_type == "quad",
        node_sets=dict(raw.node_sets), element_sets=dict(raw.element_sets), surface_sets=surface_sets,
    )
    try:
        mesh.validate()
        check_elements(mesh)
    except InputError as error:
        raise InputError(f"{source}: {error}") from None
    return mesh


def _reorient(points: np.ndarray, cells: np.ndarray, cell_type: str) -> np.ndarray:
    """Renumber all cells if every one of them is negatively oriented (a clockwise file)."""
    x = points[cells]
    if cell_type == "quad":
        sign = np.sum(x[..., 0] * np.roll(x[..., 1], -1, 1) - np.roll(x[..., 0], -1, 1) * x[..., 1], 1)
        if cells.size and (sign < 0).all():
            return cells[:, ::-1].copy()
        return cells
    d_xi = x[:, 1] - x[:, 0] + x[:, 2] - x[:, 3] + x[:, 5] - x[:, 4] + x[:, 6] - x[:, 7]
    d_eta = x[:, 3] - x[:, 0] + x[:, 2] - x[:, 1] + x[:, 7] - x[:, 4] + x[:, 6] - x[:, 5]
    d_zeta = (x[:, 4:] - x[:, :4]).sum(axis=1)
    sign = np.einsum("ni,ni->n", np.cross(d_xi, d_eta), d_zeta)
    if cells.size and (sign < 0).all():
        return np.concatenate([cells[:, 4:], cells[:, :4]], axis=1)
    return cells
