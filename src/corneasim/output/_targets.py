"""The validation targets of the built-in scenarios and a run's scores against them.

The targets are the papers' own accuracy: the needle paper's ABAQUS model scores an RMSE
of 0.039 N against its 1 mm/s experiment and 0.096 N against its 5 mm/s one (Table 2,
``docs/data.md``); a reproduction that calibrates at 1 mm/s should do better there than the
paper's own model (0.035 N) and as well at 5 mm/s, a prediction (0.095 N). These are the
targets of the needle's validation too (``validation/needle.py`` reads them here). The
trephination paper's simulation scores 0.0205 N on F_z; the targets are 0.020 N on F_z,
0.0135 N on the rotary cutting force's envelope and a peak F_z within 15% of the
experiment's. Both papers assume a quasi-static process, which holds while the kinetic
energy stays below 5% of the internal energy (the usual rule for explicit quasi-static
runs, Abaqus Analysis User's Guide, "Quasi-static analysis").

:func:`score` reads a ``summary.json`` dictionary and returns one row per score:
``(quantity, value, target text, met)``, ``met`` None where no target applies.
"""

from __future__ import annotations

NEEDLE_RMSE_N = {1.0: 0.035, 5.0: 0.095}
"""RMSE of the needle's force (Gaussian fit) against Table 2, by insertion speed (mm/s), N."""

TREPHINE_FZ_RMSE_N = 0.020
TREPHINE_FC_RMSE_N = 0.0135
TREPHINE_PEAK_FZ_REL = 0.15
"""Largest relative deviation of the peak F_z from the experiment's, dimensionless."""

KINETIC_TO_INTERNAL = 0.05
"""Largest kinetic / internal energy ratio after contact of a quasi-static run, dimensionless."""


def _at_most(value, limit):
    return None if value is None else bool(value <= limit)


def score(summary: dict, insertion_rate: float | None = None) -> list[tuple[str, float | None, str, bool | None]]:
    """The scores of a run's summary against the targets of its kind.

    Parameters
    ----------
    summary : dict
        As in ``summary.json``.
    insertion_rate : float, optional
        The needle's insertion speed, mm/s (picks the RMSE target; none for other speeds).

    Returns
    -------
    list of (quantity, value, target, met)
    """
    rows = []
    validation = summary.get("validation") or {}
    kind = summary.get("kind")
    if kind == "needle" and validation:
        limit = NEEDLE_RMSE_N.get(float(insertion_rate)) if insertion_rate is not None else None
        rmse = validation.get("rmse_N")
        rows.append((f"RMSE of the fitted force vs {validation.get('column')}, N", rmse,
                     f"<= {limit:g} N" if limit else "", _at_most(rmse, limit) if limit else None))
        rows.append(("maximum error of the fitted force, N", validation.get("max_abs_error_N"), "", None))
        rows.append(("RMSE of the raw force, N", validation.get("rmse_raw_N"), "", None))
        rows.append(("table depths compared", validation.get("n_points"), "", None))
    if kind == "trephine" and validation:
        fz, fc = validation.get("fz") or {}, validation.get("fc") or {}
        rows.append(("F_z RMSE vs the experiment, N", fz.get("rmse_N"), f"<= {TREPHINE_FZ_RMSE_N:g} N",
                     _at_most(fz.get("rmse_N"), TREPHINE_FZ_RMSE_N)))
        rows.append(("F_c envelope RMSE vs the experiment, N", fc.get("rmse_N"), f"<= {TREPHINE_FC_RMSE_N:g} N",
                     _at_most(fc.get("rmse_N"), TREPHINE_FC_RMSE_N)))
        peak, experiment = summary.get("peak_fz_N"), validation.get("peak_fz_experiment_table_N")
        if peak is not None and experiment:
            rows.append(("peak F_z, N", peak, f"within {100 * TREPHINE_PEAK_FZ_REL:g}% of {experiment:g} N",
                         abs(peak - experiment) <= TREPHINE_PEAK_FZ_REL * experiment))
        rows.append(("F_z trend against the experiment (Pearson r)", fz.get("pearson"), "", None))
        rows.append(("F_z magnitude / experiment", fz.get("magnitude_ratio"), "", None))
    run = summary.get("run") or {}
    if "max_kinetic_to_internal" in run:
        rows.append(("largest kinetic / internal energy after contact", run["max_kinetic_to_internal"],
                     f"< {KINETIC_TO_INTERNAL:g}", run["max_kinetic_to_internal"] < KINETIC_TO_INTERNAL))
    if run.get("energy_balance_error") is not None:
        rows.append(("largest energy balance error (relative)", run["energy_balance_error"], "", None))
    return rows
