"""The cut band of an axisymmetric model: its elements, its cracks' kernel pass and its axis.

:class:`RadialCracks` is the static part (``Model.radial_cracks``): the band's elements with
their reference radius, strength and toughness, and the pass that evaluates them
(:func:`corneasim.fracture._radial_cracks.band_forces`) after the fast kernels, which skip
them. :class:`CutAxis` is the external-force hook of the band's axis nodes.

**The axis.** An axisymmetric mesh holds u_r = 0 on the axis (``solver._loads``). The band's
axis nodes must leave it where the tissue is cut: the wall of the hole the cracks open is the
band's former axis edge. :func:`attach_radial_cracks` removes their axis condition, and
:class:`CutAxis` holds them there by a penalty (bilateral: the uncut axis) until one of their
elements has cracked or the instrument touches them (the point of a sharp instrument splits
the tissue at its apex: the crack tip runs with the needle tip, as in the cohesive needle
insertion of Oldfield et al., Comput. Methods Biomech. Biomed. Eng. 16 (2013)), then only
against crossing it (r >= 0, the mirror image of the other side). The penalty has the stiffness
k = beta m / dt^2 of the contact penalty (``docs/contact.md``; beta =
:data:`AXIS_PENALTY_FRACTION`); while it holds a node it has the contact's dashpot, the fraction
zeta of critical damping (an undamped penalty leaves a held node ringing at its own frequency). A released node is pushed off the axis by the instrument's
flank (the outward normal of a cone's inside at r = 0 points away from the axis) and pulled
by the radial stress of its cracked elements.

**The tip's split** (a conical needle, :meth:`CutAxis.follow`). A sharp point cuts a slit as wide
as its shaft (Shergold and Fleck, Proc. R. Soc. A 460 (2004) 3037), whatever hoop stress the
material under it carries: the footprint, the band elements whose reference radius R is below
the shaft's radius a, starts its cracks when the point enters their level
(:func:`corneasim.fracture._radial_cracks.tip_start`); their faces carry no traction. A point
of a slit's face moves sideways by the needle's half-width at its height, so the footprint's
nodes at 0 < R <= a meet the needle by their own displacement u_r = r - R (the contact's
``shift_nodes``), as the axis nodes do by r. The energy of the new crack area, n G_c per unit
area, is paid at the point: while the cone (axial length L) passes a footprint node, an axial
spring of stiffness beta m / dt^2 ties the node to the needle, capped at the node's share of
n G_c A / L (A the (r, z) area of the footprint elements around it, a quarter each), so a
node that slides the cone's length dissipates its share of n G_c A, and a deep insertion pays
n G_c a per unit depth (:func:`tip_drag`; the force is the instrument's).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from corneasim.errors import InputError
from corneasim.fracture._radial_cracks import (
    DISSIPATED, N_CRACK_FIELDS, N_OPEN, N_OUTPUTS, N_STARTED, OPENING, STARTED, STORED, band_forces, band_stress,
    band_time_steps, tip_start)
from corneasim.contact._node import FORCE_Z
from corneasim.instruments import POSE_VZ, POSE_Z
from corneasim.solver.elements._material_point import step_prony_coefficients

AXIS_TOLERANCE = 1e-9
"""mm: a node within this radius is on the axis (``solver._loads``)."""
AXIS_PENALTY_FRACTION = 0.2
"""beta of the axis penalty k = beta m / dt^2: with the contact's 0.5 on the same node the sum stays
below the stability bound 4 (1 - s^2) = 0.76 of the safety factor 0.9 (``docs/contact.md``)."""


class RadialCracks:
    """The cut band's static data (module notes; ``Model.radial_cracks``).

    Parameters
    ----------
    elements : ElementSet
        The model's element set (quads).
    band : ndarray (n_band,) int64
        The band's elements.
    strength, fracture_energy : ndarray (n_band,) float64
        sigma_c (MPa, > 0) and G_c (N/mm, > 0) per band element.
    count : int
        n, radial cracks (2: a slit; 3: a tri-facet point).
    """

    def __init__(self, elements, band, strength, fracture_energy, count: int):
        self.band = np.ascontiguousarray(band, dtype=np.int64)
        area = element_areas(elements.points, elements.cells[self.band])
        self.radius = np.ascontiguousarray(elements.volume[self.band] / (2.0 * math.pi * area))
        self.area = area
        self.strength = np.ascontiguousarray(strength, dtype=np.float64)
        self.toughness = np.ascontiguousarray(fracture_energy, dtype=np.float64)
        self.separation = np.ascontiguousarray(2.0 * self.toughness / self.strength)
        self.count = float(count)
        self.outside = np.ones(elements.n_elements, np.uint8)
        self.outside[self.band] = 0
        self.scratch = np.zeros((1, elements.n_history, 1))
        self.out = np.zeros(N_OUTPUTS)

    @property
    def n_band(self) -> int:
        return self.band.size

    def new_crack_state(self) -> np.ndarray:
        """The crack state of a new run: every crack closed, (n_band, N_CRACK_FIELDS)."""
        return np.zeros((self.n_band, N_CRACK_FIELDS))

    def kernel_alive(self, alive: np.ndarray) -> np.ndarray:
        """``alive`` without the band: what the fast kernels evaluate."""
        return alive & self.outside

    def internal_forces(self, state, dt: float, relaxed: bool) -> None:
        """Add the band's internal forces (N) to ``state.f_int`` and its energy rates; advance its
        cracks and history over the step ``dt`` (s)."""
        elements = state.elements
        prony_a, prony_b = step_prony_coefficients(elements.material_table, float(dt), relaxed)
        band_forces(elements.cells, elements.b, elements.hoop, elements.gamma, elements.volume,
                    elements.hourglass_stiffness, elements.bulk_linear, elements.bulk_quadratic,
                    elements.element_material, elements.material_table, elements.fibre_frame, prony_a, prony_b,
                    elements.block_size, state.u, float(dt), state.alive, state.history, self.band, self.radius,
                    self.strength, self.separation, self.count, state.crack, self.scratch, state.f_int,
                    state.energy_rates, self.out)
        state.failure_ratio[self.band] = 0.0

    def stress(self, state, cauchy: np.ndarray) -> None:
        """The band's rows of the field output's Cauchy stress (n_elements, 6), MPa: the material's
        stress at F_e (the kernels' :func:`element_stress` knows no cracks)."""
        elements = state.elements
        band_stress(elements.cells, elements.b, elements.hoop, elements.element_material, elements.material_table,
                    elements.fibre_frame, elements.block_size, state.u, state.history, self.band, self.radius,
                    self.count, state.crack, cauchy)

    def stable_time_steps(self, state, out: np.ndarray) -> None:
        """The band's rows of the element stable steps ``out`` (n_elements,), s, from F_e."""
        elements = state.elements
        band_time_steps(elements.points, elements.cells, elements.b, elements.hoop, elements.element_material,
                        elements.material_table, elements.fibre_frame, state.u, elements.bulk_viscosity_linear,
                        self.band, self.radius, self.count, state.crack, out)

    def opening(self, state) -> np.ndarray:
        """Crack opening delta per element (n_elements,), mm (0 outside the band)."""
        out = np.zeros(self.outside.size)
        out[self.band] = state.crack[:, OPENING]
        return out


def element_areas(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Areas in (r, z) of quads (n, 4), mm^2 (shoelace formula)."""
    x, y = points[cells, 0], points[cells, 1]
    return 0.5 * np.abs(np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1))


def band_elements(mesh, blocks, band_radius: float) -> np.ndarray:
    """Elements of ``blocks`` whose centroid lies within ``band_radius`` (mm) of the axis and that
    belong to the column reaching the axis (InputError when the band holds no axis element)."""
    in_blocks = np.isin(mesh.element_block, [mesh.block_names.index(block) for block in blocks])
    corners = mesh.points[mesh.cells]
    band = np.flatnonzero(in_blocks & (corners[..., 0].mean(axis=1) <= band_radius))
    if band.size == 0 or not np.any(corners[band, :, 0].min(axis=1) <= AXIS_TOLERANCE):
        raise InputError(f"cut.band_radius: {band_radius:g} mm holds no element of the "
                         f"{'/'.join(blocks)} blocks on the axis (the needle's path); expected a radius of "
                         "at least one element width")
    return band


def attach_radial_cracks(model, cracks: RadialCracks) -> np.ndarray:
    """Give ``model`` its cut band: ``model.radial_cracks``, no axis condition on the band's axis
    nodes (their dofs leave the constraint table), no distortion erosion of the band's elements.
    Returns the freed axis nodes."""
    mesh = model.mesh
    nodes = np.unique(mesh.cells[cracks.band])
    axis = nodes[mesh.points[nodes, 0] <= AXIS_TOLERANCE]
    dofs = axis * model.dim
    others = np.unique(mesh.cells[np.flatnonzero(cracks.outside)])
    shared = np.intersect1d(axis, others)
    if shared.size:  # an axis node shared with an uncut element stays on the axis
        axis = np.setdiff1d(axis, shared)
        dofs = axis * model.dim
    keep = ~np.isin(model.constraint_dof, dofs)
    for name in ("constraint_dof", "constraint_kind", "constraint_value", "constraint_amplitude", "constraint_set"):
        setattr(model, name, np.ascontiguousarray(getattr(model, name)[keep]))
    model.dof_constrained[axis, 0] = 0
    for name in ("constraint_node", "reaction_groups"):
        model.__dict__.pop(name, None)
    if model.distortion_limit > 0.0:
        # the band separates by its cracks: no corner ratio (NaN compares false), no erosion
        model.corner_inverse[cracks.band] = np.nan
    model.radial_cracks = cracks
    return axis


@njit(cache=True)
def tip_drag(points, u, v, mass, nodes, cap, tip, tip_speed, cone_length, stiffness_factor, anchor, active, f_ext):
    """The cut's resistance at the needle's point (module notes): each footprint node at the cone's
    height (0 <= z - tip <= cone length L) is held to the needle along the axis by a spring
    k = beta m / dt^2 (``stiffness_factor`` = beta / dt^2, 1/s^2) capped at its share ``cap`` (N) of
    n G_c A / L, and slides when the cap is reached. ``anchor`` (mm, the stick point's height above
    the tip) and ``active`` (1 while on the cone) are per node, in/out; forces into ``f_ext`` (N).
    Returns the axial force of the tissue on the needle (N) and the power the sliding dissipates
    (mJ/s)."""
    force = 0.0
    power = 0.0
    for k in range(nodes.shape[0]):
        i = nodes[k]
        height = points[i, 1] + u[i, 1] - tip
        if height < 0.0 or height > cone_length:
            active[k] = 0
            continue
        if not active[k]:
            anchor[k] = height
            active[k] = 1
        stiffness = stiffness_factor * mass[i]
        q = -stiffness * (height - anchor[k])
        if abs(q) > cap[k]:
            q = cap[k] if q > 0.0 else -cap[k]
            anchor[k] = height + q / stiffness
            power -= q * (v[i, 1] - tip_speed)
        f_ext[i, 1] += q
        force -= q
    return force, power


@njit(cache=True)
def axis_forces(u, v, mass, nodes, held, stiffness_factor, damping_ratio, f_ext):
    """Penalty of the freed axis nodes: where ``held`` (bilateral) a damped spring,

    .. math::

        f_r = -k\\,u_r - 2\\zeta\\sqrt{k\\,m}\\;v_r, \\qquad k = \\beta\\,m / \\Delta t^2,

    the contact's normal law (``docs/contact.md``) with the fraction zeta of critical damping; where
    released and u_r < 0 (unilateral) the spring f_r = -k u_r alone. The dashpot evaluated at the
    lagged velocity lowers the central-difference bound to w^2 dt^2 <= 4 - 2 c dt / m: a held node
    carries the element's 4 s^2 = 3.24 and the axis penalty's beta = 0.2 against 4 - 0.18, but a
    released node shares its budget with the contact's penalty and dashpot, which leave no room for
    a second dashpot. ``stiffness_factor`` = beta / dt^2 (1/s^2), ``v`` the velocity (mm/s).
    Returns the largest crossing of the axis, mm."""
    crossing = 0.0
    for k in range(nodes.shape[0]):
        i = nodes[k]
        r = u[i, 0]
        if held[k]:
            stiffness = stiffness_factor * mass[i]
            f_ext[i, 0] -= stiffness * r + 2.0 * damping_ratio * math.sqrt(stiffness * mass[i]) * v[i, 0]
        elif r < 0.0:
            f_ext[i, 0] -= stiffness_factor * mass[i] * r
        if r < 0.0:
            crossing = max(crossing, -r)
    return crossing


class CutAxis:
    """External-force hook of the cut band's freed axis nodes, and its history columns (module notes).

    Parameters
    ----------
    model : Model
        With ``model.radial_cracks`` (:func:`attach_radial_cracks`).
    nodes : ndarray (n,) int64
        The freed axis nodes.
    name : str
        Prefix of the history columns.
    damping_ratio : float
        zeta, the penalty's fraction of critical damping, dimensionless (the instrument contact's
        ``damping_ratio`` in a scenario).
    """

    def __init__(self, model, nodes, name: str = "cut", damping_ratio: float = 0.0):
        self.name = name
        self.damping_ratio = float(damping_ratio)
        self.cracks = model.radial_cracks
        self.nodes = np.ascontiguousarray(nodes, dtype=np.int64)
        band_cells = model.mesh.cells[self.cracks.band]
        # the band elements around each freed node (position in the band)
        self.around = [np.flatnonzero((band_cells == node).any(axis=1)) for node in self.nodes]
        self.held = np.ones(self.nodes.size, np.uint8)
        self.crossing = 0.0
        self.instrument = None  # the instrument's contact hook (:meth:`follow`)
        self.footprint = 0.0  # the shaft's radius a once a conical needle splits the band (:meth:`follow`)
        self.elements = model.elements
        self.drag_energy = 0.0

    def follow(self, instrument, model) -> None:
        """Let a conical needle's point split the band (module notes): ``instrument`` is its contact
        hook (``contact.InstrumentContact``). The footprint is the shaft's radius a: its band
        elements (reference radius below a) start their cracks when the point reaches them, the
        band's nodes at 0 < R <= a meet the needle by their own displacement, and the cone drags
        the footprint's nodes with n G_c per unit area cut."""
        self.instrument = instrument
        shape = instrument.instrument
        if getattr(shape, "tip", None) != "conical":
            return
        self.footprint = float(shape.radius)
        self.cone_length = float(shape.tip_height)
        mesh = model.mesh
        points = mesh.points
        inside = self.cracks.radius < self.footprint
        cells = mesh.cells[self.cracks.band[inside]]
        nodes = np.unique(cells)
        # each node's share of n G_c A over the footprint elements around it, paid over the cone's length
        work = self.cracks.count * self.cracks.toughness[inside] * self.cracks.area[inside]
        share = np.zeros(mesh.n_nodes)
        np.add.at(share, cells.ravel(), np.repeat(work / 4.0, 4))
        self.drag_nodes = nodes
        self.drag_cap = np.ascontiguousarray(share[nodes] / self.cone_length)
        self.drag_anchor = np.zeros(nodes.size)
        self.drag_active = np.zeros(nodes.size, np.uint8)
        off_axis = points[nodes, 0] > AXIS_TOLERANCE
        instrument.shift_nodes(nodes[off_axis], points[nodes[off_axis], 0])

    def add_forces(self, model, state, time: float, time_step: float, f_ext: np.ndarray) -> None:
        """Start the cracks the tip has reached and hold the freed axis nodes (module notes) at
        ``state.u``; forces in N."""
        step = max(float(time_step), float(state.next_time_step))
        if self.footprint > 0.0:
            elements, pose = self.elements, self.instrument.pose
            tip_start(elements.cells, elements.b, elements.hoop, elements.points, state.u, self.cracks.band,
                      self.cracks.radius, self.footprint, float(pose[POSE_Z]), state.crack)
            if step > 0.0:
                force, power = tip_drag(elements.points, state.u, state.v, state.mass, self.drag_nodes,
                                        self.drag_cap, float(pose[POSE_Z]), float(pose[POSE_VZ]), self.cone_length,
                                        AXIS_PENALTY_FRACTION / step ** 2, self.drag_anchor, self.drag_active,
                                        f_ext)
                self.instrument.out[FORCE_Z] += force
                self.drag_energy += power * float(time_step)
        if self.held.any():
            started = state.crack[:, STARTED] != 0.0
            touching = self.instrument.touching if self.instrument is not None else None
            for k in np.flatnonzero(self.held):
                if started[self.around[k]].any() or touching is not None and touching[self.nodes[k]]:
                    self.held[k] = 0
        if step <= 0.0:
            return
        self.crossing = axis_forces(state.u, state.v, state.mass, self.nodes, self.held,
                                    AXIS_PENALTY_FRACTION / step ** 2, self.damping_ratio, f_ext)

    def outputs(self) -> dict[str, float]:
        """History columns ``<name>_dissipated_energy_mJ`` (n G_c per unit crack area opened by
        stress, plus the work of the point's drag on the footprint), ``_stored_energy_mJ`` (the
        secant's recoverable crack energy), ``_open_elements`` (stress-started cracks past delta_f),
        ``_cracked_elements`` (started, by stress or by the tip) and ``_axis_crossing_mm``."""
        out = self.cracks.out
        return {f"{self.name}_dissipated_energy_mJ": float(out[DISSIPATED]) + self.drag_energy,
                f"{self.name}_stored_energy_mJ": float(out[STORED]),
                f"{self.name}_open_elements": float(out[N_OPEN]),
                f"{self.name}_cracked_elements": float(out[N_STARTED]),
                f"{self.name}_axis_crossing_mm": float(self.crossing)}

    def checkpoint(self) -> dict[str, np.ndarray]:
        """Which axis nodes are still held and the point's drag (the cracks themselves are in
        ``State.crack``)."""
        arrays = {"held": self.held.copy()}
        if self.footprint > 0.0:
            arrays.update(drag_anchor=self.drag_anchor.copy(), drag_active=self.drag_active.copy(),
                          drag_energy=np.array([self.drag_energy]))
        return arrays

    def restore(self, arrays: dict[str, np.ndarray]) -> None:
        """Restore what :meth:`checkpoint` saved."""
        if "held" in arrays:
            self.held[:] = arrays["held"]
        if "drag_anchor" in arrays:
            self.drag_anchor[:] = arrays["drag_anchor"]
            self.drag_active[:] = arrays["drag_active"]
            self.drag_energy = float(arrays["drag_energy"][0])
