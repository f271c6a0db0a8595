"""The trephination paper's results: forces, punctures, fit and validation of a trephine run.

Forces on the trephine (tissue on instrument, whole eye: the half model's values times
``instrument.symmetry_factor``):

* the linear cutting force :math:`F_z`, the axial component (positive when the tissue
  pushes the trephine up);
* the rotary cutting force :math:`F_c = M_z / R`, the torque about the trephine axis over
  the cutting radius R = 3.75 mm: the tangential force at the cutting edge. The paper
  plots it without a formula (its Fig. 4c, 7b); its table gives positive, growing values
  while the simulated :math:`F_c` changes sign with the oscillating rotation, so the
  experiment is compared with the *envelope* :math:`\\max |F_c|` over one rotation
  period (:func:`fc_envelope`). A torque sensor reports exactly this amplitude.

The paper fits :math:`F_z(t)` with two Gaussians (its eq. 14) and compares with the robot
experiment at the Table 2 times; its own simulation is compared up to 65 s (the
cornea is cut through at 62.5 s), :data:`VALIDATION_END`.
"""

from __future__ import annotations

import math

import numpy as np

from corneasim.analysis import compare_to_experiment, fit_gaussian_sum

VALIDATION_END = 65.0
"""Last experimental time compared, s (trephination paper Table 2, cornea cut through at 62.5 s)."""

FIT_TERMS = 2
"""Gaussian terms of the trephination paper's fit of F_z (eq. 14)."""

FLAT_FORCE = 1e-6
"""Range (N) below which a force curve counts as flat (no trend to correlate)."""

FIGURE_5_INSTANTS = {"0.0s": 0.0, "3.5s": 3.5, "7.7s": 7.7, "38.5s": 38.5, "62.5s": 62.5, "65.0s": 65.0}
"""The paper's stress maps (Fig. 5 a-f): initial, contact, epithelium cut, stroma cut, cut through, broken; s."""

EXPERIMENT_COLUMNS = {"fz": "experiment_Fz_N", "fc": "experiment_Fc_N"}
"""Columns of the ``trephination-force`` dataset (paper Table 2, N)."""


def rotation_period(scenario) -> float | None:
    """Period of the trephine's oscillating rotation in the scenario's time, s (2 pi / circular frequency).

    None when the rotation is not a Fourier amplitude.
    """
    rotation = scenario.instrument.motion.rotation if scenario.instrument is not None else None
    if rotation is None or rotation.type != "fourier" or rotation.circular_frequency <= 0:
        return None
    return 2.0 * math.pi / rotation.circular_frequency


def figure_instants(scenario) -> dict[str, float]:
    """Fig. 5 instants (physical procedure time, s) inside the procedure of a scenario in solver time.

    ``scenario`` is :attr:`Setup.scenario <corneasim.scenarios._build.Setup>`: its physical
    end time is ``end_time * time_scaling``.
    """
    end = scenario.solver.end_time * scenario.solver.time_scaling
    return {name: t for name, t in FIGURE_5_INSTANTS.items() if t <= end}


def fc_envelope(time: np.ndarray, fc: np.ndarray, period: float | None) -> np.ndarray:
    """Amplitude of the rotary cutting force: max |F_c| over a window of one period centred at each time.

    Parameters
    ----------
    time : ndarray
        Increasing times, s.
    fc : ndarray
        Rotary cutting force, N.
    period : float or None
        Rotation period, s; None returns |F_c|.
    """
    magnitude = np.abs(fc)
    if period is None:
        return magnitude
    low = np.searchsorted(time, time - 0.5 * period, side="left")
    high = np.searchsorted(time, time + 0.5 * period, side="right")
    return np.array([magnitude[a:b].max() for a, b in zip(low, high)])


def _compare(time, simulated, data, column) -> dict | None:
    exp_t, exp_y = data.columns["time_s"], data.columns[column]
    keep = exp_t <= VALIDATION_END
    if not np.any((exp_t[keep] >= time.min()) & (exp_t[keep] <= time.max())):
        return None
    result = compare_to_experiment(time, simulated, exp_t[keep], exp_y[keep])
    return {"column": column, "rmse_N": result["rmse"], "max_abs_error_N": result["max_abs_error"],
            "n_points": result["n_points"], "n_outside": result["n_outside"]}


def validate(setup, time: np.ndarray, fz: np.ndarray, fz_fit, fc_amplitude: np.ndarray) -> dict | None:
    """RMSE and maximum error of F_z (its fit and raw) and of the F_c envelope against the experiment.

    Returns None without a ``[validation]`` table or when no table time up to
    :data:`VALIDATION_END` lies inside the simulated times.
    """
    if setup.scenario.validation is None:
        return None
    from corneasim.data import load_dataset

    name = setup.scenario.validation.dataset
    data = load_dataset(name)
    raw = _compare(time, fz, data, EXPERIMENT_COLUMNS["fz"])
    if raw is None:
        return None
    fz_entry = dict(raw, rmse_raw_N=raw["rmse_N"], max_abs_error_raw_N=raw["max_abs_error_N"])
    if fz_fit is not None:
        fitted = _compare(time, fz_fit(time), data, EXPERIMENT_COLUMNS["fz"])
        fz_entry.update(rmse_N=fitted["rmse_N"], max_abs_error_N=fitted["max_abs_error_N"])
    fz_entry["compared"] = "gaussian fit" if fz_fit is not None else "raw"
    fc_entry = _compare(time, fc_amplitude, data, EXPERIMENT_COLUMNS["fc"])
    fc_entry["compared"] = "envelope max |Fc| over one rotation period"
    peak = float(np.max(data.columns[EXPERIMENT_COLUMNS["fz"]]))
    fz_entry.update(agreement(time, fz_fit(time) if fz_fit is not None else fz, data))
    return {"dataset": name, "up_to_s": VALIDATION_END, "fz": fz_entry, "fc": fc_entry,
            "peak_fz_experiment_table_N": peak}


def agreement(time, simulated, data) -> dict:
    """Trend and magnitude of the simulated F_z against the experiment at the compared table times.

    ``pearson``: Pearson correlation coefficient r of simulated and experimental values (the
    trend, Table 1's "variation trend"; None with fewer than three points or a curve flat
    within :data:`FLAT_FORCE`). ``magnitude_ratio``: sum of simulated over sum of experimental values (the level,
    Table 1's "data area"; 1 is equal, None when the experiment sums to zero).
    """
    exp_t, exp_y = data.columns["time_s"], data.columns[EXPERIMENT_COLUMNS["fz"]]
    keep = (exp_t <= VALIDATION_END) & (exp_t >= time.min()) & (exp_t <= time.max())
    sim, exp = np.interp(exp_t[keep], time, simulated), exp_y[keep]
    pearson = (float(np.corrcoef(sim, exp)[0, 1])
               if keep.sum() >= 3 and np.ptp(sim) > FLAT_FORCE and np.ptp(exp) > FLAT_FORCE else None)
    ratio = float(sim.sum() / exp.sum()) if exp.sum() > 0 else None
    return {"pearson": pearson, "magnitude_ratio": ratio}


def energy_shares(history: dict, symmetry_factor: float) -> dict:
    """Damping energy of the procedure against the work of the trephine and the work done on the tissue.

    The trephine's work (mJ, whole eye) is W = ∫ (F_z ż + (−M_z) θ̇) dt: the axial force the
    tissue exerts times the descent rate ż (from ``displacement_mm``) plus the torque needed
    against the tissue's moment times the angular velocity (from ``angle_rad``), trapezoidal in
    time; most of it is dissipated by sliding friction. The damping energy and the external work
    on the tissue (pressure and contact forces times the tissue's own displacements) are the
    history's half-model values from the procedure start, times ``symmetry_factor``.

    Parameters
    ----------
    history : dict
        History columns (``time_s`` in s, ``displacement_mm`` in mm, ``angle_rad``, ``fz_N``,
        ``torque_Nmm``, ``damping_energy_mJ``, ``external_work_mJ``), procedure rows only.
    symmetry_factor : float
        Whole eye / model (2 for the half model), dimensionless.

    Returns
    -------
    dict
        ``damping_energy_mJ``, ``trephine_work_mJ``, ``external_work_on_tissue_mJ`` and the ratios
        ``damping_to_trephine_work`` and ``damping_to_external_work`` (None when the work is 0).
    """
    time = history["time_s"]
    descent_rate = np.gradient(history["displacement_mm"], time) if time.size > 1 else np.zeros(1)
    angular_velocity = np.gradient(history["angle_rad"], time) if time.size > 1 else np.zeros(1)
    power = history["fz_N"] * descent_rate - history["torque_Nmm"] * angular_velocity
    work = float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(time)))
    damping = float(history["damping_energy_mJ"][-1] - history["damping_energy_mJ"][0]) * symmetry_factor
    external = float(history["external_work_mJ"][-1] - history["external_work_mJ"][0]) * symmetry_factor
    return {"damping_energy_mJ": damping, "trephine_work_mJ": work, "external_work_on_tissue_mJ": external,
            "damping_to_trephine_work": damping / work if work > 0 else None,
            "damping_to_external_work": damping / external if external > 0 else None}


def trephine_summary(setup, history: dict, events: dict, status: str) -> dict:
    """The trephination entries of ``summary.json``.

    Keys: ``peak_fz_N``, ``peak_fc_N`` (max |F_c|), ``rotation_period_s``, ``punctures``
    (epithelium, stroma and cornea, the cut through: ``time_s``, ``displacement_mm``, ``fz_N``;
    :mod:`corneasim.scenarios._punctures`), ``puncture_force_N``
    (F_z when the epithelium is cut through, the paper's F_p), ``fit`` (eq. 14, a/b/c in N/s/s),
    ``energy`` (:func:`energy_shares`) and ``validation`` (:func:`validate`).
    """
    time, fz, fc = history["time_s"], history["fz_N"], history["fc_N"]
    period = rotation_period(setup.scenario)
    period = period * setup.scenario.solver.time_scaling if period is not None else None
    summary = {"peak_fz_N": float(fz.max()), "peak_fc_N": float(np.abs(fc).max()), "rotation_period_s": period}
    summary["punctures"] = [
        {"event": name, "time_s": t, "displacement_mm": float(np.interp(t, time, history["displacement_mm"])),
         "fz_N": float(np.interp(t, time, fz))}
        for name, t in events.items()]
    summary["puncture_force_N"] = (float(np.interp(events["epithelium"], time, fz))
                                   if "epithelium" in events else None)
    fit = None
    if status == "completed" and np.ptp(fz) > 0 and time.size >= 4 * FIT_TERMS:
        fit = fit_gaussian_sum(time, fz, FIT_TERMS, nonnegative=True)
        summary["fit"] = {"a": list(fit.a), "b": list(fit.b), "c": list(fit.c), "rmse_N": float(fit.rmse)}
    else:
        summary["fit"] = None
    factor = setup.scenario.instrument.symmetry_factor if setup.scenario.instrument is not None else 1.0
    summary["energy"] = energy_shares(history, factor)
    amplitude = fc_envelope(time, fc, period)
    summary["validation"] = validate(setup, time, fz, fit, amplitude) if status == "completed" else None
    return summary
