"""History rows in procedure time, the preload report and the summary of a run.

What a scenario kind adds (its columns and summary entries) comes from its object
(:mod:`corneasim.scenarios._kinds`); the puncture events from
:mod:`corneasim.scenarios._punctures` (the cut front read from the deletions).
"""

from __future__ import annotations

import numpy as np

from corneasim.analysis import compare_to_experiment, fit_gaussian_sum
from corneasim.output import compiled_in_process, describe_platform
from corneasim.scenarios._punctures import puncture_events
from corneasim.solver import out_of_balance
from corneasim.solver.elements import FORCE_KERNELS

def procedure_row(setup, raw: dict) -> dict:
    """A history row in procedure time (t = 0 when the instrument starts), with the scenario kind's columns."""
    absolute = raw["time_s"]
    row = {"time_s": setup.procedure_time(absolute)}
    instrument = setup.instrument
    if instrument is not None:
        row.update(setup.kind.instrument_columns(raw, instrument.motion.insertion(absolute),
                                                 instrument.motion.rotation(absolute)))
    for output in setup.scenario.reactions:
        row[f"{output.name}_N"] = raw[f"reaction_{output.node_set}_{output.component}_N"]
    for key, value in raw.items():
        if key != "time_s":
            row.setdefault(key, value)
    return row


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


def max_kinetic_to_internal(history: dict, until: float | None = None) -> float:
    """Largest kinetic / internal energy ratio after contact (the quasi-static check), dimensionless.

    Counted from the first history row with a nonzero instrument force (``force_N`` or
    ``fz_N``; every row without one), and only where the internal energy is at least 5% of
    its peak: at the instant of first contact both energies are near zero. ``until``
    (procedure time, s): only the rows before it (e.g. the cut through the cornea, after
    which a released pressure takes most of the internal energy away).
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
    if until is not None and "time_s" in history:
        loaded &= history["time_s"] < until
    ratio = kinetic[loaded] / internal[loaded]
    return float(ratio.max()) if ratio.size else 0.0


def _run_summary(setup, history, state, wall: float, cut_through: float | None = None) -> dict:
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
        "element_steps_per_s": model.n_elements * (steps - setup.steps_before) / wall if wall > 0 else None,
        "stable_time_step_s": float(np.min(model.element_time_step) * model.safety_factor),
        "max_kinetic_to_internal": max_ratio,
        "max_kinetic_to_internal_before_cut_through": (
            None if cut_through is None else max_kinetic_to_internal(history, until=cut_through)),
        "hourglass_to_internal": float(hourglass[-1] / internal[-1]) if internal[-1] > 0 else 0.0,
        "added_mass_fraction": float(state.added_mass_fraction),
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


def fit_and_validate(setup, x: np.ndarray, force: np.ndarray, terms: int, scale_x: float = 1.0) -> tuple:
    """Gaussian-sum fit of the force with ``terms`` terms (None when there are too few samples) and
    the validation against it.

    The fit (``summary["fit"]``, eq. 16) covers the whole run. The validation compares the
    experiment with a fit of the part of the run that the experiment covers
    (x <= its largest abscissa, ``validation.fit_range``; that fit is ``validation.fit`` when
    it is not the whole run's): a run taken further, e.g. through the cornea, would otherwise
    be judged by a fit bent by the forces after the table's last depth. For a run that ends
    at that abscissa both fits are the same one. With a validation dataset, no term is
    narrower than the table's spacing (0.05 mm for Table 2; the paper's eq. 16 has widths of
    0.15-0.2 mm): a narrower term, such as one fitted to a single deletion's force drop, only
    lands on or misses a table depth, which made the score jump by up to 0.015 N between
    neighbouring parameter values (docs/calibration.md, "Validation score").
    """
    if x.size < 4 * terms:
        return None, None
    spec = setup.scenario.validation
    exp_x = exp_y = min_width = None
    if spec is not None:
        from corneasim.data import load_dataset

        data = load_dataset(spec.dataset)
        exp_x = data.columns[spec.x_column] * scale_x
        exp_y = data.columns[spec.y_column]
        spacing = np.diff(np.unique(exp_x))
        min_width = float(spacing.min()) if spacing.size else None
    fit = fit_gaussian_sum(x, force, terms, nonnegative=True, min_width=min_width)
    fit_summary = {"a": list(fit.a), "b": list(fit.b), "c": list(fit.c), "rmse_N": float(fit.rmse)}
    validation = None
    if spec is not None:
        if not np.any((exp_x >= x.min()) & (exp_x <= x.max())):
            return fit_summary, None
        covered = x <= exp_x.max() + RANGE_TOLERANCE * max(1.0, abs(float(exp_x.max())))
        part = not covered.all()
        if part:
            x, force = x[covered], force[covered]
            if x.size < 4 * terms:
                return fit_summary, None
            fit = fit_gaussian_sum(x, force, terms, nonnegative=True, min_width=min_width)
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
    """The summary dictionary (``summary.json``): the run's, and the scenario kind's entries
    (:meth:`corneasim.scenarios._kinds.ScenarioKind.summary`)."""
    summary = {"scenario": setup.scenario.name, "kind": setup.kind.name, "status": status}
    if error:
        summary["error"] = error
    if not history:
        summary["run"] = {"steps": int(state.step), "wall_s": wall, "warnings": list(setup.warnings)}
        return summary
    if setup.cut_punctures is not None:
        events = setup.cut_punctures.events(setup, state)
    else:
        events = puncture_events(setup, deletions) if setup.instrument is not None else {}
    summary.update(setup.kind.summary(setup, history, events, status))
    summary["run"] = _run_summary(setup, history, state, wall, events.get("cornea"))
    return summary
