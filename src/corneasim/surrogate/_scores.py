"""Scores of a surrogate on cases it was not trained on: curve RMSE, puncture error, band coverage.

For a left-out case with samples :math:`(a_i, F_i)`, :math:`a_i \\le a_{max}`, and the
surrogate's mean :math:`\\hat F` and band :math:`[L, U]` at its inputs:

.. math::

    \\mathrm{RMSE} = \\sqrt{\\tfrac1n \\sum_i (\\hat F(a_i) - F_i)^2}, \\quad
    \\text{relative RMSE} = \\mathrm{RMSE} / \\max_i F_i, \\quad
    \\text{coverage} = \\tfrac1n \\#\\{i : L(a_i) \\le F_i \\le U(a_i)\\},

and the puncture error :math:`|\\hat\\lambda_e - \\lambda_e|` per event. Aggregates: the largest
and mean relative RMSE, the largest puncture error per event, the coverage over all samples.
"""

from __future__ import annotations

import numpy as np


def case_scores(model, case, maximum: float) -> dict:
    """Scores of ``model`` on one ``case`` (see the module docstring); forces in N, abscissae in mm or s."""
    inputs = dict(zip(model.inputs, case.inputs))
    inside = case.abscissa <= maximum
    result = {"case": case.name, "channels": {}}
    for name in model.channels:
        truth = case.forces[name][inside]
        mean, lower, upper = model.predict(case.abscissa[inside], name, extrapolate=True, **inputs)
        rmse = float(np.sqrt(np.mean((mean - truth) ** 2)))
        peak = float(np.max(np.abs(truth)))
        result["channels"][name] = {"rmse_N": rmse, "peak_N": peak, "relative_rmse": rmse / max(peak, 1e-300),
                                    "inside": int(np.sum((truth >= lower) & (truth <= upper))),
                                    "samples": int(truth.size)}
    predicted = model.punctures(extrapolate=True, **inputs)
    result["puncture_error"] = {e: abs(predicted[e][0] - case.events[e]) for e in model.events}
    result["puncture_inside"] = {e: bool(predicted[e][1] <= case.events[e] <= predicted[e][2])
                                 for e in model.events}
    return result


def scores(models, training) -> dict:
    """Aggregate scores over ``models``: pairs of (surrogate, the cases it did not see)."""
    maximum = training.abscissa["max"]
    per_case = [case_scores(model, case, maximum) for model, cases in models for case in cases]
    if not per_case:
        return {}
    summary = {"cases": len(per_case), "channels": {}, "puncture_error_max": {}, "puncture_inside": {}}
    for channel in training.channels:
        name = channel["name"]
        rows = [c["channels"][name] for c in per_case]
        summary["channels"][name] = {
            "relative_rmse_max": max(r["relative_rmse"] for r in rows),
            "relative_rmse_mean": float(np.mean([r["relative_rmse"] for r in rows])),
            "rmse_N_max": max(r["rmse_N"] for r in rows),
            "coverage": sum(r["inside"] for r in rows) / sum(r["samples"] for r in rows),
        }
    for event in training.events:
        summary["puncture_error_max"][event] = max(c["puncture_error"][event] for c in per_case)
        summary["puncture_inside"][event] = float(np.mean([c["puncture_inside"][event] for c in per_case]))
    summary["per_case"] = per_case
    return summary
