"""The mesh: reference geometry, connectivity, blocks and named sets.

Conventions (every mesher, importer and solver kernel relies on them):

* Axisymmetric meshes are 2D in the (r, z) half-plane: column 0 is the radius
  r >= 0 (mm), column 1 the axial coordinate z (mm) along the optical axis, the
  anterior corneal apex at the largest z. Cells are 4-node quadrilaterals
  numbered counter-clockwise in (r, z), so their Jacobian is positive.
* 3D meshes are 8-node hexahedra in VTK/Abaqus C3D8 order: the bottom face
  0-1-2-3 counter-clockwise seen from above, the top face 4-5-6-7 above it in the
  same order (positive Jacobian); x, y, z in mm with z the optical axis. A half model
  occupies y >= 0 with the symmetry plane y = 0.
* Faces are (element, local face) pairs. Quadrilateral face k joins local nodes
  k and (k + 1) % 4. Hexahedron faces, outward normal for a positive element:
  0: (0, 3, 2, 1), 1: (4, 5, 6, 7), 2: (0, 1, 5, 4), 3: (1, 2, 6, 5),
  4: (2, 3, 7, 6), 5: (3, 0, 4, 7).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from corneasim.errors import InputError

QUAD_FACES = np.array([[0, 1], [1, 2], [2, 3], [3, 0]], dtype=np.int64)
"""Local node pairs of the quadrilateral faces (edges)."""

HEXAHEDRON_FACES = np.array(
    [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]],
    dtype=np.int64,
)
"""Local node quadruples of the hexahedron faces, outward normal by the right-hand rule."""

NODES_PER_CELL = {"quad": 4, "hexahedron": 8}


@dataclass
class Mesh:
    """A finite-element mesh with element blocks and named node, element and face sets.

    Attributes
    ----------
    points : ndarray, shape (n_nodes, dim), float64, mm
        Reference coordinates; (r, z) when ``axisymmetric``, (x, y, z) otherwise.
    cells : ndarray, shape (n_elements, nodes_per_cell), int64
        Node indices of each element (``quad``: 4, ``hexahedron``: 8).
    cell_type : str
        ``"quad"`` or ``"hexahedron"``.
    element_block : ndarray, shape (n_elements,), int64
        Index into ``block_names`` of each element's block (one material per block).
    block_names : list of str
        Names of the blocks, e.g. ``["epithelium", "stroma", "sclera"]``.
    axisymmetric : bool
        True for a 2D axisymmetric (r, z) mesh.
    node_sets : dict of str to ndarray of int64
        Named node sets (sorted, unique node indices).
    element_sets : dict of str to ndarray of int64
        Named element sets (element indices); blocks are not repeated here.
    surface_sets : dict of str to ndarray, shape (n_faces, 2), int64
        Named face sets as (element index, local face index) rows.
    """

    points: np.ndarray
    cells: np.ndarray
    cell_type: str
    element_block: np.ndarray
    block_names: list[str]
    axisymmetric: bool = False
    node_sets: dict[str, np.ndarray] = field(default_factory=dict)
    element_sets: dict[str, np.ndarray] = field(default_factory=dict)
    surface_sets: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def n_nodes(self) -> int:
        """Number of nodes."""
        return int(self.points.shape[0])

    @property
    def n_elements(self) -> int:
        """Number of elements."""
        return int(self.cells.shape[0])

    @property
    def dim(self) -> int:
        """Spatial dimension of ``points`` (2 for axisymmetric, 3 otherwise)."""
        return int(self.points.shape[1])

    def block_elements(self, name: str) -> np.ndarray:
        """Indices of the elements of block ``name``."""
        if name not in self.block_names:
            raise InputError(f"block '{name}' does not exist (blocks: {', '.join(self.block_names)})")
        return np.flatnonzero(self.element_block == self.block_names.index(name))

    def validate(self) -> None:
        """Check shapes, index ranges and set contents; raise :class:`InputError` on the first problem.

        Element orientation (positive Jacobians) is checked by the quality module.
        """
        if self.cell_type not in NODES_PER_CELL:
            raise InputError(f"unsupported cell type '{self.cell_type}' (expected quad or hexahedron)")
        expected_dim = 2 if self.axisymmetric else 3
        if self.points.ndim != 2 or self.points.shape[1] != expected_dim:
            raise InputError(f"points must have shape (n_nodes, {expected_dim}), got {self.points.shape}")
        if not np.all(np.isfinite(self.points)):
            raise InputError("points contain NaN or infinite coordinates")
        k = NODES_PER_CELL[self.cell_type]
        if self.cells.ndim != 2 or self.cells.shape[1] != k:
            raise InputError(f"{self.cell_type} cells must have shape (n_elements, {k}), got {self.cells.shape}")
        if self.cells.size and (self.cells.min() < 0 or self.cells.max() >= self.n_nodes):
            bad = int(np.flatnonzero((self.cells < 0).any(1) | (self.cells >= self.n_nodes).any(1))[0])
            raise InputError(f"element {bad} refers to a node that does not exist")
        if self.element_block.shape != (self.n_elements,):
            raise InputError("element_block must have one entry per element")
        if self.n_elements and (self.element_block.min() < 0 or self.element_block.max() >= len(self.block_names)):
            raise InputError("element_block refers to a block that does not exist")
        for index, name in enumerate(self.block_names):
            if not np.any(self.element_block == index):
                raise InputError(f"block '{name}' has no elements")
        if self.axisymmetric and self.points[:, 0].min() < -1e-12:
            raise InputError("axisymmetric mesh has nodes at negative radius")
        for name, nodes in self.node_sets.items():
            if nodes.size and (nodes.min() < 0 or nodes.max() >= self.n_nodes):
                raise InputError(f"node set '{name}' refers to a node that does not exist")
        for name, elements in self.element_sets.items():
            if elements.size and (elements.min() < 0 or elements.max() >= self.n_elements):
                raise InputError(f"element set '{name}' refers to an element that does not exist")
        n_faces = 4 if self.cell_type == "quad" else 6
        for name, faces in self.surface_sets.items():
            if faces.ndim != 2 or faces.shape[1] != 2:
                raise InputError(f"surface set '{name}' must have shape (n_faces, 2)")
            if faces.size and (
                faces[:, 0].min() < 0 or faces[:, 0].max() >= self.n_elements
                or faces[:, 1].min() < 0 or faces[:, 1].max() >= n_faces
            ):
                raise InputError(f"surface set '{name}' refers to a face that does not exist")

    def face_nodes(self, surface: str) -> np.ndarray:
        """Global node indices of each face of surface set ``surface``, shape (n_faces, 2 or 4)."""
        if surface not in self.surface_sets:
            raise InputError(f"surface set '{surface}' does not exist")
        faces = self.surface_sets[surface]
        local = QUAD_FACES if self.cell_type == "quad" else HEXAHEDRON_FACES
        return self.cells[faces[:, 0][:, None], local[faces[:, 1]]]
