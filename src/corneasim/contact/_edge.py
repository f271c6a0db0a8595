"""The edge contact of a trephine: its face lists, points and memory across steps.

:class:`EdgeContact` owns what the edge contact law (:mod:`corneasim.contact._edge_law`)
needs between two steps: the band of faces the edge can meet, the face lists of its points
(:mod:`corneasim.contact._edge_faces`), each point's depth in the step before and the
elements it pressed; it saves them with a checkpoint so that a resumed run continues bit
for bit. On a cohesive cut (:meth:`EdgeContact.hold_by_fronts`) the edge rests on the cut's
front instead of the faces next to the split (:mod:`corneasim.contact._edge_front`).
"""

from __future__ import annotations

import math

import numpy as np

from corneasim.contact._edge_faces import edge_directions, edge_face_lists, face_boxes, face_list_nodes, face_slots
from corneasim.contact._edge_front import eval_front_contact, front_segments, split_on_blade
from corneasim.contact._edge_law import N_EDGE_OUTPUTS, N_HOLD, _holding_faces, eval_edge_contact
from corneasim.mesh import face_table
from corneasim.instruments import POSE_OMEGA, POSE_VX, POSE_VZ, POSE_X, POSE_Y, POSE_Z


class EdgeContact:
    """The edge contact of a trephine on a hexahedral mesh (module notes).

    Parameters
    ----------
    points : ndarray (n_nodes, 3) float64
        Reference coordinates, mm.
    cells : ndarray (n_elements, 8) int64
        Hexahedra (VTK order).
    radius : float
        Edge radius, mm.
    spacing : float
        Distance between two edge points as a fraction of the smallest face that meets the
        edge first (a face of the band that faces up in the reference mesh), dimensionless.
    band : float
        Faces with a node within ``band`` (mm) of the edge radius, about the instrument axis,
        in the reference mesh are the ones the edge can meet (the instrument moves along its
        axis and turns about it).
    margin : float
        Growth of the face lists' reach, mm (as the node contact's candidate margin).
    cut_nodes : ndarray (n_nodes,) bool
        Nodes on the model's cuts (symmetry planes, cyclic-symmetry cut planes, supports): a
        face with all four nodes there bounds the model, not the tissue, and is left out
        (:attr:`cut_faces`, which :meth:`hold_by_fronts` extends by the faces at a split).
    """

    def __init__(self, points, cells, radius: float, spacing: float, band: float,
                 margin: float, cut_nodes):
        self.points = np.asarray(points, dtype=np.float64)
        self.cells = np.asarray(cells, dtype=np.int64)
        self.face_nodes, self.face_owner, self.face_neighbour = face_table(self.points, cells)
        self.cut_faces = np.asarray(cut_nodes, dtype=bool)[self.face_nodes].all(axis=1)
        self.radius = float(radius)
        self.spacing = float(spacing)
        self.n_points = 8
        self.band = float(band)
        self.margin = float(margin)
        self.axis = None
        self.band_faces = np.zeros(0, dtype=np.int64)
        self.open_faces = np.zeros(0, dtype=np.int64)
        self.open_faces_dead = -1
        self.point_start = np.zeros(self.n_points + 1, dtype=np.int64)
        self.point_faces = np.zeros(0, dtype=np.int64)
        self.face_slot = np.full(self.face_nodes.shape[0], -1, dtype=np.int64)
        self.node_mark = np.zeros(self.points.shape[0], dtype=np.uint8)
        self.tie_lines = None
        self.fronts = None
        self.front_depth_before = np.zeros(self.n_points)
        self._index_lists()
        self.directions = edge_directions(self.n_points)
        self.depth_before = np.zeros(self.n_points)
        self.out = np.zeros(N_EDGE_OUTPUTS)
        n_elements = np.asarray(cells).shape[0]
        self.element_points = np.zeros(n_elements, dtype=np.int64)
        self.loaded = np.zeros(0, dtype=np.int64)
        self.loaded_buffer = np.zeros(0, dtype=np.int64)

    def hold_by_fronts(self, pairs, line_start, line_pairs, cut) -> None:
        """Rest the edge on the fronts of a cohesive cut instead of the faces next to it
        (:mod:`corneasim.contact._edge_front`).

        Parameters
        ----------
        pairs : ndarray (n_pairs, 2) int64
            The ties' (original, copy) node pairs.
        line_start, line_pairs : ndarray int64
            The ties by through-thickness line, each from the anterior surface down
            (:func:`corneasim.fracture._edge_work.tie_lines`).
        cut : ndarray (n_pairs,) uint8
            The ties' cut flags, read at every step (the ties' own array).
        """
        pairs = np.ascontiguousarray(pairs, dtype=np.int64)
        self.tie_lines = (pairs, np.ascontiguousarray(line_start, dtype=np.int64),
                          np.ascontiguousarray(line_pairs, dtype=np.int64), cut)
        on_split = np.zeros(self.points.shape[0], dtype=bool)
        on_split[pairs.ravel()] = True
        self.cut_faces = self.cut_faces | on_split[self.face_nodes].any(axis=1)
        self.split_shift = np.zeros(line_start.size - 1)
        self.axis = None  # the band without the split's faces at the next refresh
        self._index_lists()

    def place_split(self, u, pose, x) -> None:
        """Write into ``x`` (mm) the split's nodes where the instrument meets them, on the blade's
        cylinder (:func:`corneasim.contact._edge_front.split_on_blade`); ``u``: displacements, mm."""
        split_on_blade(self.points, u, *self.tie_lines, np.asarray(pose[POSE_X:POSE_Y + 1], dtype=np.float64),
                       self.radius, self.split_shift, x)

    def _make_fronts(self, axis) -> None:
        """The front segments between the tie lines, in azimuth about the instrument ``axis`` (x, y), mm."""
        self.fronts = (*self.tie_lines, *front_segments(self.points, self.cells, *self.tie_lines[:3], center=axis))

    def refresh(self, x, alive, pose) -> None:
        """New face lists from the current positions ``x`` (mm), ``alive`` and ``pose``.

        ``x`` must be current for the nodes of the band's boundary faces (after a deletion, of
        the faces it opened too), and for every node when the instrument axis has moved since
        the last call. Between two calls :meth:`add_forces` reads only the nodes of the listed
        faces, :attr:`listed_nodes`, and on a cohesive cut the split's, which :meth:`place_split`
        writes at every step."""
        axis = (float(pose[POSE_X]), float(pose[POSE_Y]))
        if axis != self.axis:
            r = np.hypot(self.points[:, 0] - axis[0], self.points[:, 1] - axis[1])
            near = np.abs(r - self.radius) <= self.band
            reachable = near[self.face_nodes].any(axis=1) & ~self.cut_faces
            self.band_faces = np.flatnonzero(reachable).astype(np.int64)
            self.axis = axis
            corners = self.points[self.face_nodes[self.band_faces]]
            normal = np.cross(corners[:, 2] - corners[:, 0], corners[:, 3] - corners[:, 1])
            area = 0.5 * np.linalg.norm(normal, axis=1)
            level = normal[:, 2] > 0.5 * np.linalg.norm(normal, axis=1)
            size = np.sqrt(area[level].min()) if level.any() else 0.1
            self.n_points = max(8, int(math.ceil(2.0 * math.pi * self.radius / (self.spacing * size))))
            self.depth_before = np.zeros(self.n_points)  # new points: none held a face before
            if self.tie_lines is not None:
                self._make_fronts(axis)
                self.front_depth_before = np.zeros(self.n_points)
            self.directions = edge_directions(self.n_points)
            self.open_faces_dead = -1
        dead = alive.size - int(np.count_nonzero(alive))
        if dead != self.open_faces_dead:  # elements were deleted: the boundary changed
            self.open_faces = self._boundary(self.band_faces, alive)
            self.open_faces_dead = dead
        self.point_start, self.point_faces = edge_face_lists(
            x, self.face_nodes, self.face_owner, self.face_neighbour, self.open_faces, alive,
            np.asarray(pose[POSE_X:POSE_Z + 1], dtype=np.float64), self.radius, float(pose[POSE_Z]), self.margin,
            self.n_points)
        self._index_lists()

    def _index_lists(self) -> None:
        """The distinct faces of the point lists, each entry's index among them, their nodes and
        a buffer for their plan-view boxes (:func:`face_slots`, :func:`face_boxes`)."""
        listed = np.empty(self.point_faces.size, dtype=np.int64)
        self.point_slots = np.empty(self.point_faces.size, dtype=np.int64)
        n = face_slots(self.point_faces, self.face_slot, listed, self.point_slots)
        self.listed_faces = listed[:n]
        self.listed_nodes = face_list_nodes(self.face_nodes, self.listed_faces, self.node_mark)
        self.boxes = np.empty((n, 4))

    def _boundary(self, faces, alive) -> np.ndarray:
        """The faces of ``faces`` on the tissue's boundary: live owner, no live element across.
        ``edge_face_lists`` tests the same; listing them once per deletion spares it the
        interior faces of the band (most of them) at every refresh."""
        neighbour = self.face_neighbour[faces]
        across_dead = (neighbour < 0) | (alive[np.maximum(neighbour, 0)] == 0)
        return faces[(alive[self.face_owner[faces]] != 0) & across_dead]

    def checkpoint(self) -> dict[str, np.ndarray]:
        """The face lists, the pressed elements and the points' depths of the last step (for a
        bit-for-bit restart)."""
        axis = np.full(2, np.nan) if self.axis is None else np.array(self.axis)
        arrays = {"axis": axis, "band_faces": self.band_faces.copy(), "n_points": np.array(self.n_points),
                "point_start": self.point_start.copy(), "point_faces": self.point_faces.copy(),
                "loaded": self.loaded.copy(), "element_points": self.element_points[self.loaded].copy(),
                "depth_before": self.depth_before.copy()}
        if self.fronts is not None:
            arrays["front_depth_before"] = self.front_depth_before.copy()
        if self.tie_lines is not None:
            arrays["split_shift"] = self.split_shift.copy()
        return arrays

    def restore(self, arrays: dict[str, np.ndarray]) -> None:
        """Take back what :meth:`checkpoint` saved."""
        axis = arrays["axis"]
        self.axis = None if np.isnan(axis).any() else (float(axis[0]), float(axis[1]))
        self.band_faces = np.array(arrays["band_faces"], dtype=np.int64)
        self.open_faces_dead = -1
        self.n_points = int(arrays["n_points"])
        self.directions = edge_directions(self.n_points)
        self.depth_before = np.array(arrays["depth_before"], dtype=np.float64)
        if self.tie_lines is not None and self.axis is not None:
            self._make_fronts(self.axis)
            self.front_depth_before = np.array(arrays["front_depth_before"], dtype=np.float64)
        if self.tie_lines is not None:
            self.split_shift[:] = arrays["split_shift"]
        self.point_start = np.array(arrays["point_start"], dtype=np.int64)
        self.point_faces = np.array(arrays["point_faces"], dtype=np.int64)
        self._index_lists()
        self.element_points[:] = 0
        self.loaded = np.array(arrays["loaded"], dtype=np.int64)
        self.element_points[self.loaded] = arrays["element_points"]

    def add_forces(self, x, v, node_mass, pose, penalty_fraction: float, damping_ratio: float, friction: float,
                   dt: float, f_ext) -> np.ndarray:
        """Add the edge forces (N) to ``f_ext``; returns :attr:`out` (``N_EDGE_OUTPUTS``).
        ``node_mass`` (n_nodes,): the lumped (scaled) masses, tonne; ``friction``: Coulomb
        coefficient of the edge, dimensionless."""
        self.element_points[self.loaded] = 0
        if self.loaded_buffer.size < self.n_points:
            self.loaded_buffer = np.empty(self.n_points, dtype=np.int64)
        n_loaded = eval_edge_contact(
            x, v, self.face_nodes, self.face_owner, self.point_start, self.point_faces, self.point_slots,
            self.listed_faces, self.boxes, self.directions, node_mass, pose[POSE_X:POSE_Z + 1],
            pose[POSE_VX:POSE_VZ + 1], float(pose[POSE_OMEGA]), self.radius, float(pose[POSE_Z]), penalty_fraction,
            damping_ratio, friction, dt, f_ext, self.element_points, self.loaded_buffer, self.depth_before, self.out)
        self.loaded = self.loaded_buffer[:n_loaded]
        if self.fronts is not None:
            pairs, line_start, line_pairs, cut, segments, length, spacing, width = self.fronts
            eval_front_contact(
                x, v, pairs, line_start, line_pairs, cut, segments, length, spacing, width, node_mass,
                np.asarray(pose[POSE_X:POSE_Z + 1], dtype=np.float64),
                np.asarray(pose[POSE_VX:POSE_VZ + 1], dtype=np.float64), float(pose[POSE_OMEGA]), self.radius,
                float(pose[POSE_Z]), self.point_start.size - 1, penalty_fraction, damping_ratio, friction, dt,
                f_ext, self.front_depth_before, self.out)
        return self.out

    def holding_faces(self, x, pose) -> tuple[np.ndarray, np.ndarray]:
        """The face holding each edge point at the positions ``x`` (mm) and ``pose``, as
        :meth:`add_forces` would find it after the last step, without adding forces or
        changing the points' remembered depths: (held (n_points,) int64, -1 for none; contact
        geometry (n_points, N_HOLD), columns ``HOLD_*``, valid where held)."""
        n_points = self.point_start.size - 1  # the points the current lists were made for
        held = np.empty(n_points, dtype=np.int64)
        contact = np.empty((n_points, N_HOLD))
        _holding_faces(x, self.face_nodes, self.point_start, self.point_faces, self.point_slots,
                       self.listed_faces, self.boxes, self.directions,
                       np.asarray(pose[POSE_X:POSE_Z + 1], dtype=np.float64), self.radius, float(pose[POSE_Z]), self.depth_before, held, contact)
        return held, contact

    @property
    def point_spacing(self) -> float:
        """Length of edge each point stands for, mm."""
        return 2.0 * math.pi * self.radius / self.n_points

    def length_over_tissue(self) -> float:
        """Length of edge above the tissue, mm: the points with faces listed under them (the
        whole circle, or half of it over a half model)."""
        return max(int(np.count_nonzero(np.diff(self.point_start))), 1) * self.point_spacing
