"""Abaqus/CalculiX ``.inp`` mesh files: nodes, elements by block, node/element sets, surfaces.

Written by hand rather than through meshio, whose Abaqus format knows neither the
axisymmetric element CAX4R nor ``*SURFACE``. Blocks are written as the ``ELSET`` of
their ``*ELEMENT`` section; surfaces as element-based ``*SURFACE`` definitions whose
face labels S1..S4 (quad) / S1..S6 (hexahedron) are the contract's face k + 1.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from corneasim.errors import InputError
from corneasim.mesh._mesh import Mesh
from corneasim.mesh._convert import FACE_COUNT, NODES

ABAQUS_TYPES = {"quad": "CAX4R", "hexahedron": "C3D8R"}
READ_TYPES = {
    **{name: "quad" for name in ("CAX4", "CAX4R", "CAX4H", "CAX4RH", "CGAX4", "CGAX4R")},
    **{name: "hexahedron" for name in ("C3D8", "C3D8R", "C3D8H", "C3D8RH", "C3D8I")},
    **{name: "quad8" for name in ("CAX8", "CAX8R", "CAX8H", "CAX8RH", "CGAX8", "CGAX8R", "CGAX8H", "CGAX8RH")},
    **{name: "hexahedron20" for name in ("C3D20", "C3D20R", "C3D20H", "C3D20RH")},
    **{name: "tetra10" for name in ("C3D10", "C3D10M", "C3D10H", "C3D10MH", "C3D10I")},
}
"""Element types read, and the cell type each is (quadratic ones are split on import: ``convert``)."""

REFUSED = {
    "S": "a shell element: the kernels are solids; mesh the thickness with C3D8 / C3D20 / C3D10 elements, "
         "or with CAX4 / CAX8 quads if the body is axisymmetric",
    "CPE": "a plane-strain element: 2D meshes are read as axisymmetric (r, z); use CAX4 / CAX8 or a 3D mesh",
    "CPS": "a plane-stress element: 2D meshes are read as axisymmetric (r, z); use CAX4 / CAX8 or a 3D mesh",
}
"""Families that are refused, with the reason (prefix of the type name -> reason)."""


@dataclass
class RawMesh:
    """A mesh as read from a file, before blocks and faces are resolved (0-based indices)."""

    points: np.ndarray
    cell_type: str
    cells: np.ndarray
    blocks: list[tuple[str, np.ndarray]]  # (name, element indices) in file order
    element_sets: dict[str, np.ndarray] = field(default_factory=dict)
    node_sets: dict[str, np.ndarray] = field(default_factory=dict)
    face_sets: dict[str, np.ndarray] = field(default_factory=dict)  # name -> (n, k) face node indices
    surface_sets: dict[str, np.ndarray] = field(default_factory=dict)  # name -> (element, face) rows


def _rows(values: np.ndarray, per_line: int = 16) -> str:
    values = [str(int(v)) for v in values]
    return "\n".join(", ".join(values[i:i + per_line]) for i in range(0, len(values), per_line)) + "\n"


def write_inp(mesh: Mesh, path: Path) -> None:
    """Write ``mesh`` as an Abaqus input file (1-based numbering, axisymmetric as CAX4R)."""
    element_type = ABAQUS_TYPES[mesh.cell_type]
    lines = ["** corneasim mesh; units mm", "*HEADING",
             f"corneasim {'axisymmetric (r, z)' if mesh.axisymmetric else '3D (x, y, z)'} mesh, mm", "*NODE"]
    ids = np.arange(1, mesh.n_nodes + 1)
    lines += [f"{i}, " + ", ".join(f"{v:.12g}" for v in row) for i, row in zip(ids, mesh.points)]
    text = "\n".join(lines) + "\n"
    parts = [text]
    order = []
    for index, name in enumerate(mesh.block_names):
        elements = np.flatnonzero(mesh.element_block == index)
        order.append(elements)
        parts.append(f"*ELEMENT, TYPE={element_type}, ELSET={name}\n")
        table = np.column_stack([elements + 1, mesh.cells[elements] + 1])
        parts.append("\n".join(", ".join(map(str, row)) for row in table.tolist()) + "\n")
    for name, elements in mesh.element_sets.items():
        parts.append(f"*ELSET, ELSET={name}\n" + _rows(np.sort(elements) + 1))
    for name, nodes in mesh.node_sets.items():
        parts.append(f"*NSET, NSET={name}\n" + _rows(np.sort(nodes) + 1))
    for name, faces in mesh.surface_sets.items():
        lines = []
        for face in np.unique(faces[:, 1]):
            label = f"{name}_S{face + 1}"
            parts.append(f"*ELSET, ELSET={label}\n" + _rows(np.sort(faces[faces[:, 1] == face, 0]) + 1))
            lines.append(f"{label}, S{face + 1}")
        parts.append(f"*SURFACE, TYPE=ELEMENT, NAME={name}\n" + "\n".join(lines) + "\n")
    path.write_text("".join(parts))


def _parameters(line: str) -> tuple[str, dict[str, str]]:
    fields = [part.strip() for part in line[1:].split(",")]
    keyword = fields[0].upper()
    params = {}
    for part in fields[1:]:
        if part:
            key, _, value = part.partition("=")
            params[key.strip().upper()] = value.strip()
    return keyword, params


def read_inp(path: Path) -> RawMesh:
    """Read nodes, elements (:data:`READ_TYPES`), ``*NSET``, ``*ELSET`` and element-based ``*SURFACE``."""
    node_ids, coordinates = [], []
    element_ids, connectivity, blocks = [], [], []
    raw_sets: dict[str, list[tuple[list[str], bool, int]]] = {}  # "KIND:name" -> data blocks (tokens, generate, line)
    surfaces: dict[str, list[tuple[str, str, int]]] = {}
    cell_type = None
    section, current, pending = None, None, False
    with path.open() as handle:
        for number, line in enumerate(handle, start=1):
            line = line.strip()
            if not line or line.startswith("**"):
                continue
            if line.startswith("*"):
                pending = False
                keyword, params = _parameters(line)
                section = keyword
                if keyword == "ELEMENT":
                    name = params.get("TYPE", "").upper()
                    if name not in READ_TYPES:
                        reason = next((why for prefix, why in REFUSED.items()
                                       if re.fullmatch(rf"{prefix}\d.*", name)), None)
                        raise InputError(f"{path}:{number}: unsupported element type '{name}'"
                                         + (f": {reason}" if reason else " (expected CAX4* / CAX8* axisymmetric "
                                            "quads, C3D8* / C3D20* hexahedra or C3D10* tetrahedra)"))
                    if cell_type not in (None, READ_TYPES[name]):
                        raise InputError(f"{path}:{number}: mixes element types ({cell_type} and "
                                         f"{READ_TYPES[name]}): one element type per mesh")
                    cell_type = READ_TYPES[name]
                    current = params.get("ELSET", f"block{len(blocks)}")
                    blocks.append((current, []))
                elif keyword in ("NSET", "ELSET"):
                    current = params.get(keyword, "")
                    raw_sets.setdefault(f"{keyword}:{current}", []).append(([], "GENERATE" in params, number))
                elif keyword == "SURFACE":
                    current = params.get("NAME", "")
                    surfaces[current] = []
                    if params.get("TYPE", "ELEMENT").upper() != "ELEMENT":
                        raise InputError(f"{path}:{number}: only element-based *SURFACE is supported")
                continue
            tokens = [token.strip() for token in line.split(",") if token.strip()]
            try:
                if section == "NODE":
                    node_ids.append(int(tokens[0]))
                    coordinates.append([float(v) for v in tokens[1:]])
                elif section == "ELEMENT":  # an element's nodes may continue on the next lines
                    if pending:
                        connectivity[-1].extend(int(v) for v in tokens)
                    else:
                        element_ids.append(int(tokens[0]))
                        connectivity.append([int(v) for v in tokens[1:]])
                        blocks[-1][1].append(len(element_ids) - 1)
                    pending = len(connectivity[-1]) < NODES[cell_type]
            except ValueError:
                raise InputError(f"{path}:{number}: expected numbers, got '{line}'") from None
            if section in ("NSET", "ELSET"):
                raw_sets[f"{section}:{current}"][-1][0].extend(tokens)
            elif section == "SURFACE":
                surfaces[current].append((tokens[0], tokens[1].upper() if len(tokens) > 1 else "", number))
    if cell_type is None:
        raise InputError(f"{path}: no *ELEMENT section with CAX4*, CAX8*, C3D8*, C3D20* or C3D10* elements")
    return _resolve(path, node_ids, coordinates, element_ids, connectivity, blocks, raw_sets, surfaces, cell_type)


def _resolve(path, node_ids, coordinates, element_ids, connectivity, blocks, raw_sets, surfaces, cell_type):
    if not coordinates:
        raise InputError(f"{path}: no *NODE section")
    dim = max(len(c) for c in coordinates)
    node_order = np.argsort(node_ids, kind="stable")  # nodes and elements in label order
    points = np.array([c + [0.0] * (dim - len(c)) for c in coordinates])[node_order]
    if cell_type in ("quad", "quad8"):
        points = points[:, :2]
    node_ids = [node_ids[i] for i in node_order]
    element_order = np.argsort(element_ids, kind="stable")
    position = np.empty(len(element_ids), dtype=np.int64)
    position[element_order] = np.arange(len(element_ids))
    element_ids = [element_ids[i] for i in element_order]
    connectivity = [connectivity[i] for i in element_order]
    node_index = {n: i for i, n in enumerate(node_ids)}
    element_index = {e: i for i, e in enumerate(element_ids)}
    k = NODES[cell_type]
    if any(len(row) != k for row in connectivity):
        raise InputError(f"{path}: every {cell_type} element needs {k} nodes")
    try:
        cells = np.array([[node_index[n] for n in row] for row in connectivity], dtype=np.int64)
    except KeyError as error:
        raise InputError(f"{path}: an element refers to node {error.args[0]}, which is not defined") from None
    element_sets = {name: position[np.array(items, dtype=np.int64)] for name, items in blocks}

    def members(key: str, lookup: dict, seen: tuple = ()) -> np.ndarray:
        """Indices of set ``key``; repeated definitions add up, names refer to other sets."""
        kind = key.split(":", 1)[0]
        found: list[np.ndarray] = []
        for tokens, generate, number in raw_sets[key]:
            ids: list[int] = []
            for token in tokens:
                if re.fullmatch(r"-?\d+", token):
                    ids.append(int(token))
                elif f"{kind}:{token}" in raw_sets and f"{kind}:{token}" not in (key, *seen):
                    found.append(members(f"{kind}:{token}", lookup, (*seen, key)))
                elif kind == "ELSET" and token in element_sets:
                    found.append(element_sets[token])
                else:
                    raise InputError(f"{path}:{number}: {kind} refers to unknown set '{token}'")
            if generate:
                start, stop, step = (ids + [1])[:3]
                ids = list(range(start, stop + 1, step))
            try:
                found.append(np.array([lookup[i] for i in ids], dtype=np.int64))
            except KeyError as error:
                raise InputError(f"{path}:{number}: {kind} refers to {error.args[0]}, which is not defined") from None
        return np.unique(np.concatenate(found)).astype(np.int64)

    node_sets, more_element_sets = {}, {}
    for key in raw_sets:
        kind, name = key.split(":", 1)
        if kind == "NSET":
            node_sets[name] = members(key, node_index)
        else:
            more_element_sets[name] = members(key, element_index)
    surface_sets = {}
    n_faces = FACE_COUNT[cell_type]
    for name, rows in surfaces.items():
        collected = []
        for target, label, number in rows:
            match = re.fullmatch(r"S(\d)", label)
            if not match or not 1 <= int(match.group(1)) <= n_faces:
                raise InputError(f"{path}:{number}: surface '{name}': face label '{label}' is not S1..S{n_faces}")
            if re.fullmatch(r"\d+", target):
                if int(target) not in element_index:
                    raise InputError(f"{path}:{number}: surface '{name}' refers to element {target}, not defined")
                elements = np.array([element_index[int(target)]])
            elif target in more_element_sets:
                elements = more_element_sets[target]
            elif target in element_sets:
                elements = element_sets[target]
            else:
                raise InputError(f"{path}:{number}: surface '{name}' refers to unknown element set '{target}'")
            collected.append(np.column_stack([elements, np.full(elements.size, int(match.group(1)) - 1)]))
        surface_sets[name] = np.concatenate(collected).astype(np.int64) if collected else np.zeros((0, 2), np.int64)
    used_for_surfaces = {target for name, rows in surfaces.items() for target, _, _ in rows  # write_inp's helpers
                         if re.fullmatch(rf"{re.escape(name)}_S\d", target)}
    more_element_sets = {n: v for n, v in more_element_sets.items() if n not in used_for_surfaces}
    return RawMesh(points, cell_type, cells, [(n, v) for n, v in element_sets.items()],
                   more_element_sets, node_sets, {}, surface_sets)
