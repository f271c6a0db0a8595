"""Scenario-specific history columns and summaries (needle insertion, trephination, general).

Puncture events are read from the *deletion front* on the instrument path: the column of
elements the instrument cuts through (those with a node within the instrument radius of
the axis for the needle, those crossed by the trephine's cutting circle for the trephine),
ordered from the anterior surface down. A layer is punctured when the contiguous run of
deleted elements from the anterior surface has passed through all of that layer's column
elements; ``stroma`` is the moment the cut front enters the stroma, ``cornea`` the moment it
has passed the whole cornea (posterior surface reached). This is the physical definition
the papers' figures show (needle paper Fig. 10 b, c, e; trephination paper Fig. 5 c, e); the
force drops the papers read off the curves are reported beside it (``force_drops``).
"""

from __future__ import annotations

import math

import numpy as np

from corneasim.analysis import compare_to_experiment, detect_force_drops, fit_gaussian_sum
from corneasim.output.platform import compiled_in_process, describe_platform
from corneasim.scenarios.trephine import trephine_summary
from corneasim.solver import out_of_balance
from corneasim.solver.elements import FORCE_KERNELS

LEAD_COLUMNS = {
    "needle": ["time_s", "depth_mm", "force_N", "kinetic_energy_mJ", "internal_energy_mJ", "deleted_elements"],
    "trephine": ["time_s", "displacement_um", "angle_rad", "fz_N", "fc_N", "torque_Nmm", "kinetic_energy_mJ",
                 "internal_energy_mJ", "deleted_elements"],
    "general": ["time_s", "kinetic_energy_mJ", "internal_energy_mJ", "deleted_elements"],
}
FIT_TERMS = {"needle": 3}
"""Gaussian terms of the needle paper's fit (eq. 16); the trephine's: :mod:`corneasim.scenarios.trephine`."""


def procedure_row(setup, raw: dict) -> dict:
    """A history row in procedure time (t = 0 when the instrument starts), with the scenario's lead columns."""
    absolute = raw["time_s"]
    row = {"time_s": setup.procedure_time(absolute)}
    instrument = setup.instrument
    if instrument is not None:
        depth = instrument.motion.insertion(absolute)
        angle = instrument.motion.rotation(absolute)
        kind = setup.scenario.kind
        if kind == "trephine":
            row.update(displacement_um=1000.0 * depth, angle_rad=angle,
                       fz_N=raw["instrument_linear_cutting_force_N"],
                       fc_N=raw["instrument_rotary_cutting_force_N"],
                       torque_Nmm=raw["instrument_torque_z_Nmm"])
        else:
            row.update(depth_mm=depth, force_N=raw["instrument_force_z_N"])
    for output in setup.scenario.reactions:
        row[f"{output.name}_N"] = raw[f"reaction_{output.node_set}_{output.component}_N"]
    for key, value in raw.items():
        if key != "time_s":
            row.setdefault(key, value)
    return row


PLANE_TOLERANCE = 1e-9
"""Distance (mm) within which a node counts as on the plane y = 0 (trephine) or the axis (needle)."""


def path_column(setup) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The cornea elements on the instrument's path, their blocks and where the path crosses them.

    The needle's path is the axis r = 0; the trephine's is the line under the cutting circle
    in the half-plane y = 0, x > 0 (the symmetry plane of the half model), at any meshing
    strategy. The column holds the cornea elements with a corner on that line's plane (the
    axis; the plane y = 0) that span it (r = 0; r = cutting radius), most anterior first.

    Returns
    -------
    elements : ndarray of int64
        Element indices, highest (most anterior) centre first.
    blocks : ndarray of str
        Block name of each.
    spans : ndarray (n, 2) float64
        Reference axial coordinates (z, mm) where the path line enters and leaves each
        element, top first: an element's edges on the plane cut by the line (the whole
        element's z range when none of its edges lies on the plane).
    """
    mesh = setup.mesh
    corners = mesh.points[mesh.cells]
    centres = corners.mean(axis=1)
    cornea = np.isin(mesh.element_block, [mesh.block_names.index(b) for b in ("epithelium", "stroma")
                                          if b in mesh.block_names])
    shape = setup.scenario.instrument.shape
    if shape.kind == "trephine":
        line = shape.cutting_radius
        across = corners[..., 0]  # x on the plane y = 0
        on_plane = np.abs(corners[..., 1]) <= PLANE_TOLERANCE
        radius = np.hypot(corners[..., 0], corners[..., 1])
        on_path = ((radius.min(axis=1) <= line) & (radius.max(axis=1) >= line) & on_plane.any(axis=1)
                   & (centres[:, 0] > 0))
    else:
        line = 0.0
        across = corners[..., 0]  # r
        on_plane = np.ones(across.shape, dtype=bool)
        on_path = across.min(axis=1) <= PLANE_TOLERANCE
    selected = np.flatnonzero(on_path & cornea)
    elements = selected[np.argsort(-centres[selected, -1])]
    spans = np.array([_span(across[e][on_plane[e]], corners[e][on_plane[e], -1], corners[e][:, -1], line)
                      for e in elements]).reshape(-1, 2)
    return elements, np.array([mesh.block_names[mesh.element_block[e]] for e in elements]), spans


def _span(a: np.ndarray, z: np.ndarray, z_all: np.ndarray, line: float) -> tuple[float, float]:
    """(top, bottom) z where the line a = ``line`` crosses the segments between the corners
    (a, z) on the plane; the whole range ``z_all`` when they do not reach it."""
    hits = []
    for i in range(a.size):
        for j in range(i, a.size):
            low, high = min(a[i], a[j]), max(a[i], a[j])
            if not low - PLANE_TOLERANCE <= line <= high + PLANE_TOLERANCE:
                continue
            if high - low <= PLANE_TOLERANCE:  # a segment along the line, or a corner on it
                hits += [z[i], z[j]]
            else:
                w = (line - a[i]) / (a[j] - a[i])
                hits.append(z[i] + w * (z[j] - z[i]))
    if not hits:
        return float(z_all.max()), float(z_all.min())
    return float(max(hits)), float(min(hits))


def puncture_events(setup, deletions, column=None) -> dict[str, float]:
    """Procedure times at which the cut front passes the epithelium, enters the stroma, leaves the cornea.

    The front has reached a depth on the path line when, at every depth above it, an element
    that the line crosses there is deleted (one is enough: two elements side by side at a
    depth, as on either side of the trephine's cutting radius, need not both go). The
    epithelium event is the front's arrival at the last depth crossed by epithelium elements
    only, the stroma event at the first crossed by stroma elements only, the cornea event at
    the deepest. ``column`` is :func:`path_column`'s result, computed here when not given.
    """
    elements, blocks, spans = column if column is not None else path_column(setup)
    if elements.size == 0:
        return {}
    died = {element: time for time, element, _ in deletions}
    times = np.array([died.get(int(e), math.inf) for e in elements])
    levels = np.unique(spans)[::-1]  # every span end, top first
    middles = 0.5 * (levels[:-1] + levels[1:])
    crossed = (spans[:, 1][None, :] <= middles[:, None]) & (spans[:, 0][None, :] >= middles[:, None])
    front = np.maximum.accumulate(np.where(crossed, times[None, :], math.inf).min(axis=1))
    events = {}
    epithelium = np.flatnonzero(crossed[:, blocks == "epithelium"].any(axis=1)
                                & ~crossed[:, blocks != "epithelium"].any(axis=1))
    stroma = np.flatnonzero(crossed[:, blocks == "stroma"].any(axis=1)
                            & ~crossed[:, blocks != "stroma"].any(axis=1))
    if epithelium.size:
        events["epithelium"] = float(front[epithelium[-1]])
    if stroma.size:
        events["stroma"] = float(front[stroma[0]])
        events["cornea"] = float(front[-1])
    return {name: time for name, time in events.items() if math.isfinite(time)}


class PunctureTracker:
    """Reports each puncture event once, as soon as the deletions reveal it (for field snapshots)."""

    def __init__(self, setup):
        self.setup = setup
        self.column = path_column(setup)
        self.seen: set[str] = set()

    def update(self, deletions) -> list[str]:
        """Names of the events that happened since the previous call."""
        events = [name for name in puncture_events(self.setup, deletions, self.column) if name not in self.seen]
        self.seen.update(events)
        return events


def _at(history: dict, column: str, time: float) -> float:
    return float(np.interp(time, history["time_s"], history[column]))


PRELOAD_OUT_OF_BALANCE_LIMIT = 1e-4
"""A preload ending further than this from equilibrium (relative out-of-balance force) is
reported as not settled. Needle preloads ending below it had the apex within 1% of its
settled IOP displacement; ones ending at 2e-4 to 2e-3 were 1.4-40% off, with nodes still
moving at 2-14% of the needle's speed (docs/solver.md, "Preload stage")."""


def preload_report(setup, state) -> dict:
    """How settled the model is at the end of the preload; warns (``setup.warnings``) if it is not.

    Returns ``duration_s`` (s), ``out_of_balance`` (||f_ext - f_int|| / ||f_ext|| over the free
    dofs, :func:`corneasim.solver.out_of_balance`) and ``max_speed_mm_per_s`` (largest
    nodal speed, in physical time), also stored as ``setup.preload_end``.
    """
    scaling = setup.scenario.solver.time_scaling
    ratio = out_of_balance(setup.model, state)
    active = state.node_active != 0
    speed = float(np.sqrt((state.v[active] ** 2).sum(axis=1)).max()) / scaling if active.any() else 0.0
    report = {"duration_s": setup.preload_duration * scaling, "out_of_balance": ratio,
              "max_speed_mm_per_s": speed}
    if ratio > PRELOAD_OUT_OF_BALANCE_LIMIT:
        setup.warnings.append(
            f"the preload did not settle: out-of-balance force {ratio:.2g} of the applied load (above "
            f"{PRELOAD_OUT_OF_BALANCE_LIMIT:g}), nodes still moving at up to {speed:.3g} mm/s; lengthen "
            "preload.duration or tune preload.damping")
    setup.preload_end = report
    return report


def max_kinetic_to_internal(history: dict) -> float:
    """Largest kinetic / internal energy ratio after contact (the quasi-static check), dimensionless.

    Counted from the first history row with a nonzero instrument force (``force_N`` or
    ``fz_N``; every row without one), and only where the internal energy is at least 5% of
    its peak: at the instant of first contact both energies are near zero.
    """
    internal = history.get("internal_energy_mJ", np.zeros(1))
    kinetic = history.get("kinetic_energy_mJ", np.zeros(1))
    contact = np.ones_like(internal, dtype=bool)
    force_column = "force_N" if "force_N" in history else "fz_N" if "fz_N" in history else None
    if force_column is not None:
        touching = np.flatnonzero(np.abs(history[force_column]) > 0)
        contact = np.zeros_like(internal, dtype=bool)
        if touching.size:
            contact[touching[0]:] = True
    loaded = contact & (internal >= 0.05 * internal.max()) & (internal > 0)
    ratio = kinetic[loaded] / internal[loaded]
    return float(ratio.max()) if ratio.size else 0.0


def _run_summary(setup, history, state, wall: float) -> dict:
    model = setup.model
    steps = int(state.step)
    internal = history.get("internal_energy_mJ", np.zeros(1))
    hourglass = history.get("hourglass_energy_mJ", np.zeros(1))
    max_ratio = max_kinetic_to_internal(history)
    warnings = list(setup.warnings)
    if max_ratio > 0.05:
        warnings.append(f"kinetic energy reached {100 * max_ratio:.1f}% of the internal energy after contact "
                        "(above 5%: the quasi-static assumption of the papers is not met)")
    balance = history.get("energy_balance_error", np.zeros(1))
    return {
        "elements": model.n_elements,
        "nodes": model.n_nodes,
        "steps": steps,
        "wall_s": wall,
        "element_steps_per_s": model.n_elements * steps / wall if wall > 0 else None,
        "stable_time_step_s": float(np.min(model.element_time_step) * model.safety_factor),
        "max_kinetic_to_internal": max_ratio,
        "hourglass_to_internal": float(hourglass[-1] / internal[-1]) if internal[-1] > 0 else 0.0,
        "added_mass_fraction": float(model.added_mass_fraction),
        "time_scaling": setup.scenario.solver.time_scaling,
        "energy_balance_error": float(np.nanmax(np.abs(balance))) if balance.size else None,
        "preload": setup.preload_end,
        "warnings": warnings,
        "platform": {**describe_platform(),
                     "kernels_compiled_in_run": compiled_in_process(FORCE_KERNELS)},
    }


RANGE_TOLERANCE = 1e-9
"""Relative tolerance of "within the experiment's range" (a history row at the table's last
abscissa carries the round-off of the accumulated time steps)."""


def _fit_and_validate(setup, x: np.ndarray, force: np.ndarray, kind: str, scale_x: float = 1.0) -> tuple:
    """Gaussian-sum fit of the force (None when there are too few samples) and the validation against it.

    The fit (``summary["fit"]``, eq. 16) covers the whole run. The validation compares the
    experiment with a fit of the part of the run that the experiment covers
    (x <= its largest abscissa, ``validation.fit_range``; that fit is ``validation.fit`` when
    it is not the whole run's): a run taken further, e.g. through the cornea, would otherwise
    be judged by a fit bent by the forces after the table's last depth. For a run that ends
    at that abscissa both fits are the same one.
    """
    if x.size < 4 * FIT_TERMS[kind]:
        return None, None
    fit = fit_gaussian_sum(x, force, FIT_TERMS[kind], nonnegative=True)
    fit_summary = {"a": list(fit.a), "b": list(fit.b), "c": list(fit.c), "rmse_N": float(fit.rmse)}
    validation = None
    if setup.scenario.validation is not None:
        from corneasim.data import load_dataset

        spec = setup.scenario.validation
        data = load_dataset(spec.dataset)
        exp_x = data.columns[spec.x_column] * scale_x
        exp_y = data.columns[spec.y_column]
        if not np.any((exp_x >= x.min()) & (exp_x <= x.max())):
            return fit_summary, None
        covered = x <= exp_x.max() + RANGE_TOLERANCE * max(1.0, abs(float(exp_x.max())))
        part = not covered.all()
        if part:
            x, force = x[covered], force[covered]
            if x.size < 4 * FIT_TERMS[kind]:
                return fit_summary, None
            fit = fit_gaussian_sum(x, force, FIT_TERMS[kind], nonnegative=True)
        on_fit = compare_to_experiment(x, fit(x), exp_x, exp_y)
        raw = compare_to_experiment(x, force, exp_x, exp_y)
        validation = {"dataset": spec.dataset, "column": spec.y_column,
                      "rmse_N": on_fit["rmse"], "max_abs_error_N": on_fit["max_abs_error"],
                      "n_points": on_fit["n_points"], "rmse_raw_N": raw["rmse"],
                      "max_abs_error_raw_N": raw["max_abs_error"],
                      "fit_range": [float(x.min()), float(x.max())]}
        if part:
            validation["fit"] = {"a": list(fit.a), "b": list(fit.b), "c": list(fit.c), "rmse_N": float(fit.rmse)}
    return fit_summary, validation


def summarise(setup, history: dict, deletions, state, wall: float, status: str, error: str | None) -> dict:
    """The summary dictionary (``summary.json``)."""
    kind = setup.scenario.kind
    summary = {"scenario": setup.scenario.name, "kind": kind, "status": status}
    if error:
        summary["error"] = error
    if not history:
        summary["run"] = {"steps": int(state.step), "wall_s": wall, "warnings": list(setup.warnings)}
        return summary
    events = puncture_events(setup, deletions) if setup.instrument is not None else {}
    if kind == "needle":
        depth, force = history["depth_mm"], history["force_N"]
        summary["peak_force_N"] = float(force.max())
        summary["punctures"] = [
            {"event": name, "time_s": t, "depth_mm": _at(history, "depth_mm", t), "force_N": _at(history, "force_N", t)}
            for name, t in events.items()]
        drops = detect_force_drops(force, depth)
        summary["force_drops"] = [{"depth_mm": float(d.x), "force_N": float(d.force), "drop_N": float(d.drop)}
                                  for d in drops]
        if status == "completed" and np.ptp(force) > 0:
            summary["fit"], summary["validation"] = _fit_and_validate(setup, depth, force, kind)
    elif kind == "trephine":
        summary.update(trephine_summary(setup, history, events, status))
    else:
        named = {f"{output.name}_N" for output in setup.scenario.reactions}
        summary["reactions"] = {k: float(np.abs(v).max()) for k, v in history.items()
                                if k.startswith("reaction_") or k in named}
    summary["run"] = _run_summary(setup, history, state, wall)
    return summary
