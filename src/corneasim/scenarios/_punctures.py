"""Puncture events: when the cut made by element deletion passes the epithelium, enters the
stroma and leaves the cornea.

This is the physical definition the papers' figures show (needle paper Fig. 10 b, c, e;
trephination paper Fig. 5 c, e); the force drops the papers read off the curves are
reported beside it (``force_drops``). Times are those of the deletions (procedure time).

**Needle.** Its tip runs down the axis, so the cut is read on that line: the column of
cornea elements with a corner on the axis, and where the axis crosses each of them
(:func:`path_column`). A depth is cut when an element the line crosses there is deleted;
the front is the deepest point above which every depth is cut. ``epithelium`` is the
front's arrival at the last depth crossed by epithelium elements only, ``stroma`` at the
first crossed by stroma elements only, ``cornea`` at the deepest (:func:`column_events`).

**Trephine.** The cut follows the edge only roughly in the reference mesh: the cornea
deforms under the edge, so the deleted elements lie on either side of the cutting radius
and not on one line. The cut is read in the section y = 0, x > 0 (the symmetry plane of the
half model) within :data:`SECTION_BAND` of the cutting radius: a path of deleted elements,
each sharing a face edge on the plane with the next, from the anterior surface
(:func:`cut_section`, :func:`section_events`). ``epithelium``: the path reaches an epithelium
element on the epithelium–stroma interface; ``stroma``: it reaches a stroma element;
``cornea``: it reaches the posterior surface (the ``inner_surface`` node set).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from corneasim.solver import EVENT_CORNEA, EVENT_EPITHELIUM, EVENT_STROMA

PLANE_TOLERANCE = 1e-9
"""Distance (mm) within which a node counts as on the axis (needle) or on the plane y = 0 (trephine)."""

SECTION_BAND = 0.5
"""Half-width (mm) of the trephine's section about the cutting radius: several element widths
(0.05-0.15 mm under the edge) either side of the 0.1 mm wall."""


def path_column(setup) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The cornea elements on the needle's axis, their blocks and where the axis crosses them.

    Returns
    -------
    elements : ndarray of int64
        Element indices with a corner on the axis r = 0, highest (most anterior) centre first.
    blocks : ndarray of str
        Block name of each.
    spans : ndarray (n, 2) float64
        Reference axial coordinates (z, mm) where the axis enters and leaves each element, top
        first (the element's edge on the axis; a corner's z when only a corner touches it).
    """
    mesh = setup.mesh
    corners = mesh.points[mesh.cells]
    elements = np.flatnonzero((corners[..., 0].min(axis=1) <= PLANE_TOLERANCE) & _cornea(mesh))
    elements = elements[np.argsort(-corners[elements].mean(axis=1)[:, -1])]
    spans = np.empty((elements.size, 2))
    for k, e in enumerate(elements):
        z = corners[e][corners[e][:, 0] <= PLANE_TOLERANCE, -1]
        spans[k] = z.max(), z.min()
    return elements, _blocks(mesh, elements), spans


def column_events(column, died: dict) -> dict[str, float]:
    """Event times on a needle column (:func:`path_column`), from ``died`` (element -> time, s)."""
    elements, blocks, spans = column
    if elements.size == 0:
        return {}
    times = np.array([died.get(int(e), math.inf) for e in elements])
    levels = np.unique(spans)[::-1]  # every span end, top first
    middles = 0.5 * (levels[:-1] + levels[1:])
    crossed = (spans[:, 1][None, :] <= middles[:, None]) & (spans[:, 0][None, :] >= middles[:, None])
    front = np.maximum.accumulate(np.where(crossed, times[None, :], math.inf).min(axis=1))
    events = {}
    only_epithelium = np.flatnonzero(crossed[:, blocks == "epithelium"].any(axis=1)
                                     & ~crossed[:, blocks != "epithelium"].any(axis=1))
    only_stroma = np.flatnonzero(crossed[:, blocks == "stroma"].any(axis=1)
                                 & ~crossed[:, blocks != "stroma"].any(axis=1))
    if only_epithelium.size:
        events["epithelium"] = float(front[only_epithelium[-1]])
    if only_stroma.size:
        events["stroma"] = float(front[only_stroma[0]])
        events["cornea"] = float(front[-1])
    return {name: time for name, time in events.items() if math.isfinite(time)}


@dataclass
class CutSection:
    """The trephine's section (:func:`cut_section`).

    Attributes
    ----------
    elements : ndarray of int64
        Cornea elements with a face on the plane y = 0, x > 0, centre within
        :data:`SECTION_BAND` of the cutting radius.
    neighbours : list of ndarray of int64
        For each, the positions (in ``elements``) of those sharing an edge on the plane.
    top, interface, stroma, bottom : ndarray of bool
        On the anterior surface; an epithelium element on the epithelium-stroma interface;
        in the stroma; on the posterior surface.
    """

    elements: np.ndarray
    neighbours: list
    top: np.ndarray
    interface: np.ndarray
    stroma: np.ndarray
    bottom: np.ndarray


def cut_section(setup) -> CutSection:
    """The trephine's section about the cutting radius in the plane y = 0, x > 0."""
    mesh = setup.mesh
    corners = mesh.points[mesh.cells]
    centres = corners.mean(axis=1)
    on_plane = np.abs(corners[..., 1]) <= PLANE_TOLERANCE
    radius = setup.scenario.instrument.shape.cutting_radius
    elements = np.flatnonzero(_cornea(mesh) & (on_plane.sum(axis=1) >= 3) & (centres[:, 0] > 0)
                              & (np.abs(np.hypot(centres[:, 0], centres[:, 1]) - radius) <= SECTION_BAND))
    plane_nodes = [frozenset(mesh.cells[e][on_plane[e]].tolist()) for e in elements]
    neighbours = [np.array([j for j, other in enumerate(plane_nodes) if j != i and len(nodes & other) >= 2],
                           dtype=np.int64) for i, nodes in enumerate(plane_nodes)]
    blocks = _blocks(mesh, elements)
    stroma_nodes = set(mesh.cells[mesh.element_block == mesh.block_names.index("stroma")].ravel().tolist()) \
        if "stroma" in mesh.block_names else set()
    anterior = set(mesh.node_sets.get("anterior_surface", np.empty(0, np.int64)).tolist())
    posterior = set(mesh.node_sets.get("inner_surface", np.empty(0, np.int64)).tolist())
    nodes = [set(mesh.cells[e].tolist()) for e in elements]
    return CutSection(
        elements=elements, neighbours=neighbours,
        top=np.array([bool(n & anterior) for n in nodes], dtype=bool),
        interface=np.array([b == "epithelium" and bool(n & stroma_nodes) for b, n in zip(blocks, nodes)], dtype=bool),
        stroma=blocks == "stroma",
        bottom=np.array([bool(n & posterior) for n in nodes], dtype=bool))


def section_events(section: CutSection, died: dict) -> dict[str, float]:
    """Event times of a trephine section (:func:`cut_section`), from ``died`` (element -> time, s):
    the first time a path of deleted elements from the anterior surface reaches each mark."""
    times = np.array([died.get(int(e), math.inf) for e in section.elements])
    marks = {"epithelium": section.interface, "stroma": section.stroma, "cornea": section.bottom}
    events: dict[str, float] = {}
    for time in np.unique(times[np.isfinite(times)]):
        reached = _reached(section, times <= time)
        for name, mark in marks.items():
            if name not in events and (reached & mark).any():
                events[name] = float(time)
        if len(events) == len(marks):
            break
    return events


def reached_marks(section: CutSection, died: dict) -> set[str]:
    """The marks of a trephine section (:func:`cut_section`) that a path of deleted elements from
    the anterior surface reaches now (``died``: element -> deletion time, every deletion so far)."""
    dead = np.array([int(e) in died for e in section.elements], dtype=bool)
    reached = _reached(section, dead)
    marks = {"epithelium": section.interface, "stroma": section.stroma, "cornea": section.bottom}
    return {name for name, mark in marks.items() if (reached & mark).any()}


def _reached(section: CutSection, dead: np.ndarray) -> np.ndarray:
    """Dead section elements joined to the anterior surface by dead neighbours (breadth first)."""
    reached = dead & section.top
    queue = list(np.flatnonzero(reached))
    while queue:
        for j in section.neighbours[queue.pop()]:
            if dead[j] and not reached[j]:
                reached[j] = True
                queue.append(j)
    return reached


def puncture_events(setup, deletions, path=None, state=None) -> dict[str, float]:
    """Procedure times (s) at which the cut passes the epithelium, enters the stroma, leaves the cornea.

    ``deletions``: (time s, element, block) tuples; ``path``: :func:`puncture_path`'s result,
    computed here when not given. A cohesive cut's events are those :class:`TieEvents`
    recorded in ``state.event_time``.
    """
    if setup.cohesive is not None:
        recorded = {name: float(state.event_time[index]) for name, index in EVENT_INDEX.items()} \
            if state is not None else {}
        return {name: setup.procedure_time(t) for name, t in recorded.items() if not math.isnan(t)}
    path = path if path is not None else puncture_path(setup)
    died = {element: time for time, element, _ in deletions}
    if isinstance(path, CutSection):
        return section_events(path, died)
    return column_events(path, died)


def puncture_path(setup):
    """Where the events are read: the trephine's :class:`CutSection`, the needle's :func:`path_column`."""
    if setup.scenario.instrument.shape.kind == "trephine":
        return cut_section(setup)
    return path_column(setup)


EVENT_INDEX = {"epithelium": EVENT_EPITHELIUM, "stroma": EVENT_STROMA, "cornea": EVENT_CORNEA}
"""``State.event_time`` entry of each puncture event."""


class PunctureEvents:
    """Event term of the time loop (:func:`corneasim.solver.run`): each puncture event once, in
    the step whose deletions reveal it.

    Records the event's solver time (the step's, that of the deletion completing the path) in
    ``state.event_time``; an event already recorded there (a resumed run) is not reported again.
    """

    def __init__(self, setup):
        self.setup = setup
        self.path = puncture_path(setup)

    def update(self, model, state) -> list[str]:
        """Names of the events revealed by the deletions of this step."""
        pending = [name for name, index in EVENT_INDEX.items() if math.isnan(state.event_time[index])]
        if not pending:
            return []
        died = dict(zip(state.deleted_element.tolist(), state.deleted_time.tolist()))
        happened = column_events(self.path, died) if not isinstance(self.path, CutSection) else \
            reached_marks(self.path, died)
        events = [name for name in pending if name in happened]
        for name in events:
            state.event_time[EVENT_INDEX[name]] = state.time
        return events


def _cornea(mesh) -> np.ndarray:
    return np.isin(mesh.element_block, [mesh.block_names.index(b) for b in ("epithelium", "stroma")
                                        if b in mesh.block_names])


def _blocks(mesh, elements) -> np.ndarray:
    return np.array([mesh.block_names[mesh.element_block[e]] for e in elements])


class TieEvents:
    """The puncture events of a cohesive cut, read from its ties (a hook of the time loop, after
    the ties'; adds no force).

    Around the whole ring: ``epithelium`` once every tie whose original node an epithelium
    element uses is cut; ``stroma`` once, besides, each through-thickness line's first tie
    below them is; ``cornea`` once every tie is, the disc free. It records the solver time in
    ``state.event_time`` and releases the pressures (``pressure_release``) at ``cornea``.
    """

    def __init__(self, setup):
        self.name = "tie_events"
        self.ties = setup.cohesive
        self.pressure_release = setup.pressure_release
        mesh, pairs = setup.mesh, setup.cohesive.pairs
        epithelium = np.zeros(mesh.n_nodes, bool)
        if "epithelium" in mesh.block_names:
            epithelium[mesh.cells[mesh.element_block == mesh.block_names.index("epithelium")].ravel()] = True
        self.epithelium = epithelium[pairs[:, 0]]
        start, order = setup.edge_work.line_start, setup.edge_work.line_pairs
        below = np.zeros(len(pairs), bool)
        for line in range(start.size - 1):
            stroma = [i for i in order[start[line]:start[line + 1]] if not self.epithelium[i]]
            if stroma:
                below[stroma[0]] = True
        self.entered = self.epithelium | below
        self.cut_count = -1  # ties cut when the events were last read (cuts are never undone)

    def add_forces(self, model, state, time: float, time_step: float, f_ext: np.ndarray) -> None:
        """Record the events the ties' cuts reveal at this step (read again only once more ties are cut)."""
        if not math.isnan(state.event_time[EVENT_CORNEA]):
            return
        count = int(np.count_nonzero(self.ties.cut))
        if count == self.cut_count:
            return
        self.cut_count = count
        cut = self.ties.cut.astype(bool)
        for name, mask in (("epithelium", self.epithelium), ("stroma", self.entered), ("cornea", None)):
            index = EVENT_INDEX[name]
            if math.isnan(state.event_time[index]) and (cut.all() if mask is None else cut[mask].all()):
                state.event_time[index] = float(time)
                if name == "cornea" and self.pressure_release is not None:
                    self.pressure_release.trigger(state, float(time))

    def outputs(self) -> dict[str, float]:
        """None."""
        return {}
