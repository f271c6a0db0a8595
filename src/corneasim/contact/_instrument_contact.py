"""One instrument in contact with the tissue: the per-step hook and the history outputs.

:class:`InstrumentContact` binds an instrument, its motion and the contact settings to a
model's contact nodes. Each step the integrator calls :meth:`InstrumentContact.add_forces`
(it adds the contact forces to ``f_ext``); :meth:`InstrumentContact.outputs` then names
what the instrument felt, including the trephination paper's linear cutting force F_z and
rotary cutting force F_c = M_z / R, for the history rows.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from corneasim.errors import InputError
from corneasim.mesh import element_sizes
from corneasim.contact._settings import ContactSettings
from corneasim.contact._node import (
    CONTACT_AREA, CONTACT_NODES, FORCE_X, FORCE_Y, FORCE_Z, FRICTION_POWER, MAX_PENETRATION, N_OUTPUTS,
    NORMAL_FORCE, TORQUE_Z, contact_candidates, current_positions, eval_contact)
from corneasim.contact._edge_law import (
    EDGE_FORCE_X, EDGE_FORCE_Y, EDGE_FORCE_Z, EDGE_FRICTION_POWER, EDGE_NORMAL, EDGE_PENETRATION,
    EDGE_POINTS, EDGE_TORQUE_Z)
from corneasim.contact._cutting import RingCut
from corneasim.contact._edge import EdgeContact
from corneasim.instruments import POSE_SIZE, POSE_VZ, POSE_X, POSE_Y, Motion, pose_at


CANDIDATE_MARGIN = 0.25
"""mm: the contact kernel visits the nodes within this distance of the instrument's bounding
shell, a list made anew every ``CANDIDATE_REFRESH`` steps from the whole contact set."""
EDGE_SPACING = 0.25
"""Spacing of the edge points of the edge contact as a fraction of the size of the smallest
face the edge meets first (the line springs then have four or more points per face)."""
EDGE_BAND = 1.0
"""mm: the edge contact considers the faces with a node this close to the edge radius."""
EDGE_MARGIN = 0.1
"""mm: reach of the edge contact's face lists beyond a face's own window, made anew with the
node candidates every ``CANDIDATE_REFRESH`` steps: tissue dragged along by the turning
trephine (up to 16 mm/s at its edge) moves 0.05 mm in the 10 steps of 3e-4 s."""
CANDIDATE_REFRESH = 10
"""Steps between two candidate lists. A node would have to move 0.25 mm in 10 steps (1,250
mm/s at the needle's 2e-5 s step) to reach the instrument unseen; should one do so, the next
list finds it inside the shell and a warning says so."""


def stable_penalty_fraction(safety_factor: float) -> float:
    """Largest alpha in k = alpha m / dt^2 that keeps central differences stable.

    With dt = s * 2 / omega_max the node's (omega dt)^2 is (2 s)^2 + alpha, which must stay
    below 4: alpha_max = 4 (1 - s^2) (0.76 for s = 0.9).
    """
    return 4.0 * (1.0 - safety_factor**2)


def nodal_contact_areas(points: np.ndarray, cells: np.ndarray, axisymmetric: bool) -> tuple[np.ndarray, float]:
    """Tributary contact area per node (an estimate) and the smallest element size.

    h_i is the mean size of the elements around node i; the area is h_i^2 in 3D and the
    ring 2 pi max(r_i, h_i / 8) h_i in the axisymmetric model (the floor gives a node on
    the axis the disc of diameter h_i).

    Returns
    -------
    (ndarray, float)
        Areas per node, mm^2, and the smallest element size, mm.
    """
    sizes = element_sizes(np.asarray(points, dtype=np.float64), np.asarray(cells, dtype=np.int64))
    total = np.bincount(cells.ravel(), weights=np.repeat(sizes, cells.shape[1]), minlength=len(points))
    count = np.bincount(cells.ravel(), minlength=len(points))
    h = np.divide(total, count, out=np.zeros(len(points)), where=count > 0)
    if axisymmetric:
        return 2.0 * np.pi * np.maximum(points[:, 0], h / 8.0) * h, float(sizes.min())
    return h * h, float(sizes.min())


class InstrumentContact:
    """External-force hook of the solver: an instrument, its motion and penalty contact.

    Follows the hook protocol of :mod:`corneasim.solver._run` (``name``, ``add_forces``,
    ``outputs``, ``checkpoint``, ``restore``).

    Parameters
    ----------
    instrument : Needle or Trephine
        The instrument (:mod:`corneasim.instruments._kinds`).
    motion : Motion
        Its prescribed motion.
    model : corneasim.solver.Model
        The model: its mesh, reference masses (the nodal contact areas) and ``safety_factor``
        are used; each step takes the masses of the state (variable mass scaling).
    settings : ContactSettings, optional
        Penalty, damping, friction and the contact node set (default: every node).
    name : str
        Prefix of the history columns.
    symmetry_factor : float
        Multiplies the reported forces, torque, counts, area and powers: 2 when the mesh is
        a half model cut by a symmetry plane through the instrument axis, so the outputs are
        those of the whole eye (see ``docs/contact.md`` for what this means for the torque).
        When the model's cut plane is under cyclic symmetry about the axis (u(RX) = R u(X),
        R the rotation by pi), the other half's sideways force is minus this half's, so the
        whole eye's ``force_x`` and ``force_y`` are reported as 0.
    """

    def __init__(self, instrument, motion: Motion, model, settings: ContactSettings | None = None,
                 name: str = "instrument", symmetry_factor: float = 1.0):
        if not symmetry_factor >= 1.0:
            raise InputError(f"symmetry_factor: expected >= 1 (2 for a half model), got {symmetry_factor}")
        self.name = name
        self.symmetry_factor = float(symmetry_factor)
        cyclic_half = symmetry_factor > 1.0 and model.cyclic_master.size > 0
        self.sideways_factor = 0.0 if cyclic_half else self.symmetry_factor
        self.instrument = instrument
        self.settings = settings if settings is not None else ContactSettings()
        mesh = model.mesh
        if mesh.axisymmetric and not instrument.axisymmetric:
            raise InputError("instrument: a bevelled needle is not a body of revolution; use it in a 3D model")
        if self.settings.node_set == "all":
            self.nodes = np.arange(mesh.n_nodes, dtype=np.int64)
        elif self.settings.node_set in mesh.node_sets:
            self.nodes = np.ascontiguousarray(mesh.node_sets[self.settings.node_set], dtype=np.int64)
        else:
            raise InputError(f"contact.node_set: '{self.settings.node_set}' is not a node set of the mesh "
                             f"(sets: {', '.join(sorted(mesh.node_sets)) or 'none'}; or 'all')")
        limit = stable_penalty_fraction(model.safety_factor)
        if self.settings.penalty_fraction > limit:
            raise InputError(
                f"contact.penalty_fraction: {self.settings.penalty_fraction} is unstable with the time-step "
                f"safety factor {model.safety_factor}; expected <= 4 (1 - s^2) = {limit:.3g}")
        self.points = np.ascontiguousarray(mesh.points, dtype=np.float64)
        self.node_area, self.smallest_element_size = nodal_contact_areas(mesh.points, mesh.cells, mesh.axisymmetric)
        self.motion = motion
        self.motion_packed = motion.pack()
        self.shape = instrument.pack()
        self.friction = self.settings.friction.pack()
        self.pose = np.zeros(POSE_SIZE)
        self.out = np.zeros(N_OUTPUTS)
        self.x = np.empty_like(self.points)
        self.anchor = np.zeros((mesh.n_nodes, 3))
        self.touching = np.zeros(mesh.n_nodes, np.uint8)
        self.hits = np.empty(self.nodes.size, np.int64)
        self.candidates = np.empty(self.nodes.size, np.int64)
        self.is_candidate = np.zeros(mesh.n_nodes, np.uint8)
        self.n_candidates = 0
        self._forget_candidates()
        self.largest_penetration = 0.0
        self.penetration_since_output = 0.0
        self._warned = False
        self.edge = self._edge_contact(mesh, model, limit) if self.settings.edge_contact else None
        self.cutting = (RingCut(self.settings.cutting_toughness, model.n_elements)
                        if self.settings.cutting_toughness is not None else None)
        self.cut = None
        self.edge_deletions = -1
        self.shifted_nodes = None
        self.shift = None

    def shift_nodes(self, nodes: np.ndarray, shift: np.ndarray) -> None:
        """Meet ``nodes`` (int64) at r - ``shift`` (mm, one per node) instead of r: a node of a cut's
        footprint meets the needle by its own sideways displacement, as a point of a slit's face
        does (``docs/cutting.md``, "The tip's split"). Axisymmetric models only."""
        self.shifted_nodes = np.ascontiguousarray(nodes, dtype=np.int64)
        self.shift = np.ascontiguousarray(shift, dtype=np.float64)

    def _edge_contact(self, mesh, model, limit: float) -> EdgeContact:
        """The edge contact of a trephine on a 3D hexahedral mesh (``contact.edge_contact``)."""
        if mesh.axisymmetric or mesh.cells.shape[1] != 8 or not hasattr(self.instrument, "edge_radius"):
            raise InputError("contact.edge_contact: needs a trephine (a circular cutting edge) and a 3D "
                             "hexahedral mesh")
        if 2.0 * self.settings.penalty_fraction > limit:
            raise InputError(
                f"contact.penalty_fraction: {self.settings.penalty_fraction} is unstable with edge_contact "
                f"(a node can take the node and the edge penalty) and the time-step safety factor "
                f"{model.safety_factor}; expected <= 2 (1 - s^2) = {limit / 2:.3g}")
        cut_nodes = model.dof_constrained.any(axis=1)
        cut_nodes[model.cyclic_master] = cut_nodes[model.cyclic_slave] = True
        return EdgeContact(mesh.points, mesh.cells, self.instrument.edge_radius,
                           EDGE_SPACING, EDGE_BAND, EDGE_MARGIN, cut_nodes)

    def add_forces(self, model, state, time: float, time_step: float, f_ext: np.ndarray) -> None:
        """Add the contact forces at ``time`` (s) to ``f_ext`` (N), with ``state.u`` at that time."""
        pose_at(self.motion_packed, float(time), self.pose)
        # The penalty follows the stable step, not a step shortened to land on an output time.
        penalty_step = max(float(time_step), float(state.next_time_step))
        refresh = self.steps_since_candidates >= CANDIDATE_REFRESH
        axis = (float(self.pose[POSE_X]), float(self.pose[POSE_Y]))
        self._meet_positions(state, refresh or self.edge is not None and self.edge.axis != axis)
        if refresh:
            self._make_candidates()
        self.steps_since_candidates += 1
        eval_contact(self.x, state.v, self.candidates[:self.n_candidates], state.node_active, state.mass,
                     self.node_area, self.shape, self.pose, self.settings.penalty_fraction,
                     self.settings.damping_ratio, penalty_step, self.friction, self.anchor, self.touching, f_ext,
                     self.out, self.hits)
        if self.edge is not None:
            self._add_edge_forces(state, penalty_step, f_ext)
        penetration = self.out[MAX_PENETRATION]
        self.penetration_since_output = max(self.penetration_since_output, penetration)
        self.largest_penetration = max(self.largest_penetration, penetration)
        # The lumped law's range is about the insertion speed: check it once the instrument
        # moves while in contact (a resting instrument, e.g. during a preload, is not sliding).
        if self.out[CONTACT_NODES] > 0 and self.pose[POSE_VZ] != 0.0 and not self._warned:
            self._warned = not self.settings.friction.check_speed(self.pose[POSE_VZ])

    def _meet_positions(self, state, every: bool) -> None:
        """Positions ``x`` (mm) of the nodes as the instrument meets them: every node's when
        ``every`` (a new candidate list, or the edge's band of faces moves or opens), else the
        candidates' (the node contact) and the edge's listed faces' nodes; then the split of a
        cohesive cut on the blade's path and the shifted nodes of a needle's slit."""
        if every:
            np.add(self.points, state.u, out=self.x)
        else:
            current_positions(self.points, state.u, self.candidates[:self.n_candidates], self.x)
            if self.edge is not None:
                current_positions(self.points, state.u, self.edge.listed_nodes, self.x)
        if self.edge is not None and self.edge.tie_lines is not None:  # a cohesive cut meets the blade on its path
            self.edge.place_split(state.u, self.pose, self.x)
        if self.shifted_nodes is not None:
            nodes = self.shifted_nodes
            self.x[nodes] = self.points[nodes] + state.u[nodes]
            # a node that moved inwards (r < R) meets the needle as one on the axis: pushed outwards
            self.x[nodes, 0] = np.maximum(self.x[nodes, 0] - self.shift, 0.0)

    def _add_edge_forces(self, state, penalty_step: float, f_ext: np.ndarray) -> None:
        """Edge contact forces into ``f_ext``, their resultant into the outputs. The face lists are
        made with the node candidates and whenever elements were deleted (new faces)."""
        deletions = state.deleted_time.size
        made_candidates = self.steps_since_candidates == 1  # add_forces made them this step
        if made_candidates or deletions != self.edge_deletions:
            if not made_candidates:  # faces opened by the deletion: every node's position
                self._meet_positions(state, every=True)
            self.edge.refresh(self.x, state.alive, self.pose)
            self.edge_deletions = deletions
        friction = self.settings.friction
        mu = friction.coefficient if friction.law == "coulomb" else 0.0
        edge = self.edge.add_forces(self.x, state.v, state.mass, self.pose, self.settings.penalty_fraction,
                                    self.settings.damping_ratio, mu, penalty_step, f_ext)
        self.out[FORCE_X] += edge[EDGE_FORCE_X]
        self.out[FORCE_Y] += edge[EDGE_FORCE_Y]
        self.out[FORCE_Z] += edge[EDGE_FORCE_Z]
        self.out[TORQUE_Z] += edge[EDGE_TORQUE_Z]
        self.out[NORMAL_FORCE] += edge[EDGE_NORMAL]
        self.out[FRICTION_POWER] += edge[EDGE_FRICTION_POWER]
        self.out[MAX_PENETRATION] = max(self.out[MAX_PENETRATION], edge[EDGE_PENETRATION])
        if self.cutting is not None:
            elements = self.edge.loaded
            self.cut = elements, self.cutting.failure_ratios(elements, float(self.out[FORCE_Z]),
                                                             self.edge.length_over_tissue())

    def cut_ratios(self) -> tuple[np.ndarray, np.ndarray] | None:
        """The cutting rule's result of the last step (:mod:`corneasim.contact._cutting`): the
        elements the edge presses and their ratios q_avg / toughness, which the time loop
        merges into the failure ratios (so the failure check deletes them, or starts their
        softening, and logs it like any failure); None without a cutting rule."""
        cut, self.cut = self.cut, None
        return cut

    def _forget_candidates(self) -> None:
        """Have the next step make a new candidate list, without checking it against this one
        (after a placement or a restart every node inside the shell would count as missed)."""
        self.is_candidate[:] = 0
        self.steps_since_candidates = CANDIDATE_REFRESH
        self.candidates_made = False

    def _make_candidates(self) -> None:
        """The nodes that can touch until the next list (``CANDIDATE_MARGIN``), from self.x."""
        count, missed = contact_candidates(self.x, self.nodes, self.shape, self.pose, CANDIDATE_MARGIN,
                                           self.is_candidate, self.touching, self.candidates)
        if missed and self.candidates_made:
            warnings.warn(f"{self.name}: {missed} node(s) reached the instrument between two contact "
                          f"candidate lists (they moved more than {CANDIDATE_MARGIN} mm in "
                          f"{CANDIDATE_REFRESH} steps); their first contact came late", stacklevel=2)
        self.n_candidates = count
        self.steps_since_candidates = 0
        self.candidates_made = True

    def outputs(self) -> dict[str, float]:
        """History columns of the last step (penetration: the largest since the previous row).

        Columns ``<name>_`` + ``force_x_N``, ``force_y_N``, ``force_z_N`` (tissue on instrument;
        the axisymmetric model has only z), ``torque_z_Nmm`` (about the instrument axis),
        ``contact_nodes``, ``contact_area_mm2``, ``max_penetration_mm``, ``normal_force_N``,
        ``friction_power_mJ_per_s``, ``linear_cutting_force_N`` (F_z) and
        ``rotary_cutting_force_N`` (F_c = M_z / R, R the cutting radius); with the edge contact
        also ``edge_contact_points`` (edge points in contact). The forces include the edge's.
        """
        out = self.out * self.symmetry_factor
        values = {
            "force_x_N": self.out[FORCE_X] * self.sideways_factor,
            "force_y_N": self.out[FORCE_Y] * self.sideways_factor,
            "force_z_N": out[FORCE_Z],
            "torque_z_Nmm": out[TORQUE_Z],
            "contact_nodes": out[CONTACT_NODES],
            "contact_area_mm2": out[CONTACT_AREA],
            "max_penetration_mm": self.penetration_since_output,
            "normal_force_N": out[NORMAL_FORCE],
            "friction_power_mJ_per_s": out[FRICTION_POWER],
            "linear_cutting_force_N": out[FORCE_Z],
            "rotary_cutting_force_N": out[TORQUE_Z] / self.instrument.cutting_radius,
        }
        if self.edge is not None:
            values["edge_contact_points"] = self.edge.out[EDGE_POINTS] * self.symmetry_factor
        self.penetration_since_output = 0.0
        return {f"{self.name}_{key}": float(value) for key, value in values.items()}

    def place(self, tip_position) -> None:
        """Move the instrument so that its tip is at ``tip_position`` (mm) at zero insertion.

        Used to set the instrument on the deformed tissue after a preload stage.
        """
        self.motion = dataclasses.replace(self.motion, tip_position=tuple(float(c) for c in tip_position))
        self.motion_packed = self.motion.pack()
        self._forget_candidates()  # a new list at the next step, around the new position

    def checkpoint(self) -> dict[str, np.ndarray]:
        """Arrays to save with a checkpoint.

        The candidate list and the edge contact's face lists are saved with their age: which
        faces an edge point may touch depends on when its list was made, so a resumed run
        rebuilding them at once would differ from the uninterrupted one.
        """
        arrays = {"out": self.out.copy(), "anchor": self.anchor.copy(), "touching": self.touching.copy(),
                  "penetration": np.array([self.largest_penetration, self.penetration_since_output]),
                  "tip_position": np.array(self.motion.tip_position, dtype=float),
                  "cut_load": self.cutting.load.copy() if self.cutting is not None else np.zeros(0),
                  "candidates": self.candidates[:self.n_candidates].copy(),
                  "candidate_state": np.array([self.steps_since_candidates, int(self.candidates_made)])}
        if self.edge is not None:
            arrays.update({f"edge_{key}": value for key, value in self.edge.checkpoint().items()})
            arrays["deletions_seen"] = np.array(self.edge_deletions)
        return arrays

    def restore(self, arrays: dict[str, np.ndarray]) -> None:
        """Restore what :meth:`checkpoint` saved."""
        self.out[:] = arrays["out"]
        self.anchor[:] = arrays["anchor"]
        self.touching[:] = arrays["touching"]
        self._forget_candidates()
        self.largest_penetration, self.penetration_since_output = (float(v) for v in arrays["penetration"])
        self.place(arrays["tip_position"])
        if self.cutting is not None:
            self.cutting.load[:] = arrays["cut_load"]
        count = arrays["candidates"].size
        self.candidates[:count] = arrays["candidates"]
        self.n_candidates = count
        self.is_candidate[self.candidates[:count]] = 1
        self.steps_since_candidates, made = (int(value) for value in arrays["candidate_state"])
        self.candidates_made = bool(made)
        if self.edge is not None:
            self.edge.restore({key[len("edge_"):]: value for key, value in arrays.items() if key.startswith("edge_")})
            self.edge_deletions = int(arrays["deletions_seen"])
