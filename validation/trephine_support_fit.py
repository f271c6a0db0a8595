"""The stiffness of the trephine scenario's eye support from the experiment's first 20 s only.

Before the cut starts the trephine's push F_z is carried by the eye wall and by the holder in
series: F_z = K_series (d - d_0), 1/K_series = 1/K_eye + 1/K_support, d the descent (20 um/s)
and d_0 its value at first contact. The experiment's F_z (trephination paper Table 2) at its
rows up to 20 s gives K_series (least squares through the first contact); the hinged model eye
(``fixed = "xyz"``, no supports) gives K_eye (its F_z secant between first contact and 10 s,
with a cutting toughness no push reaches, so that nothing is cut); then

    K_support = 1 / (1/K_series - 1/K_eye)   (whole eye; the half model carries half of it).

Nothing after 20 s enters, so the support is not fitted on the curve that the validation
scores (docs/trephination.md, "Eye support"). About 3 min on the coarse mesh.

Usage::

    python validation/trephine_support_fit.py [--preset coarse|default] [--out results/trephine-support-fit]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import corneasim
from corneasim.data import load_dataset

FIT_UNTIL_S = 20.0
"""Experiment rows used, s."""

HINGED = ["supports=[]", "constraints.lower_hemisphere.fixed=xyz", "instrument.contact.cutting_toughness=1.0",
          "solver.end_time=10.0", "solver.field_count=0"]
"""The hinged eye, not cut (a push of 1 N per mm of edge: 23.6 N), to 10 s."""


def series_stiffness(time_s, fz_N, rate_mm_per_s: float, contact_s: float) -> float:
    """Least-squares K (N/mm) of F_z = K rate (t - t_contact) over the rows given."""
    descent = rate_mm_per_s * (np.asarray(time_s) - contact_s)
    keep = descent > 0.0
    return float(np.sum(descent[keep] * np.asarray(fz_N)[keep]) / np.sum(descent[keep] ** 2))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--preset", default="coarse", choices=["coarse", "default"])
    parser.add_argument("--out", type=Path, default=Path("results/trephine-support-fit"))
    arguments = parser.parse_args()
    table = load_dataset("trephination-force")
    time, fz = np.asarray(table.columns["time_s"], float), np.asarray(table.columns["experiment_Fz_N"], float)
    early = time <= FIT_UNTIL_S
    rate = 0.020  # mm/s, the scenario's insertion rate
    contact = float(time[early][np.flatnonzero(fz[early] == 0.0)[-1]])  # the last row without force
    k_series = series_stiffness(time[early], fz[early], rate, contact)
    result = corneasim.run_scenario("trephine", [f"mesh.preset={arguments.preset}", *HINGED],
                                    out_dir=arguments.out, progress=False)
    history = result.history
    touching = np.flatnonzero(np.asarray(history["fz_N"]) > 0.0)
    model_contact = float(history["time_s"][touching[0]]) if touching.size else float("nan")
    k_eye = series_stiffness(history["time_s"], history["fz_N"], rate, model_contact)
    k_support = 1.0 / (1.0 / k_series - 1.0 / k_eye)
    print(f"experiment rows t <= {FIT_UNTIL_S:g} s: first contact {contact:g} s, K_series = {k_series:.4g} N/mm")
    print(f"hinged {arguments.preset} eye: first contact {model_contact:.3g} s, K_eye = {k_eye:.4g} N/mm")
    print(f"K_support = {k_support:.4g} N/mm (whole eye), supports[0].stiffness = {k_support / 2:.4g} N/mm "
          "(half model)")


if __name__ == "__main__":
    main()
