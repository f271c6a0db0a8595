"""Text outputs of the material library: preset summaries and fitted-law TOML blocks."""

from __future__ import annotations

import numpy as np

from corneasim.materials._fibre_homogeneous import DIRECTIONS, directional_cauchy_stress
from corneasim.materials._fitting import FitResult
from corneasim.materials._homogeneous import nominal_stress
from corneasim.materials._laws import fibre_constants
from corneasim.materials._spec import MaterialSpec
from corneasim.materials._stability import StabilityReport

REPORT_STRETCHES = (0.9, 1.05, 1.1, 1.2)
"""Stretches at which the summary lists the uniaxial nominal stress."""

_CONSTANT_UNITS = {"c10": "MPa", "c01": "MPa", "c20": "MPa", "c30": "MPa",
                   "youngs_modulus": "MPa", "poisson_ratio": "dimensionless", "d1": "1/MPa",
                   "k1": "MPa", "k2": "dimensionless", "kappa": "dimensionless", "fibre_angle": "degrees"}


def material_summary(material: MaterialSpec, stability: StabilityReport) -> str:
    """A readable multi-line summary of one material (constants, moduli, stability, stresses)."""
    law = material.hyperelastic
    constants = ", ".join(f"{key} = {value:g} {_CONSTANT_UNITS.get(key, 'MPa')}"
                          for key, value in law.model_dump().items() if key != "model")
    fibres = fibre_constants(material.model, material.parameters()) is not None
    lines = [
        f"{material.name}: {material.description}",
        f"  law            {law.model}: {constants}",
        f"  small strain   mu0 = {material.initial_shear_modulus:.4g} MPa, K = {material.bulk_modulus:.4g} MPa, "
        + (f"E = {material.youngs_modulus:.4g} MPa, nu = {material.poisson_ratio:.4f}"
           if material.initial_shear_modulus > 0.0 else "E and nu undefined (mu0 <= 0: unstable at zero strain)")
        + (" (ground matter)" if fibres else ""),
        f"  density        {material.density:.4g} tonne/mm^3",
    ]
    lines.append(f"  wave speed     {material.kernel_form().wave_speed:.4g} mm/s "
                 "(instantaneous, dilatational" + (", with the fibres' bound at rest)" if fibres else ")"))
    if material.viscoelastic is not None:
        weights = material.viscoelastic.weights()
        pairs = ", ".join(f"{g:.4f}@{t:g}s" for g, t in zip(weights, material.viscoelastic.relaxation_times))
        lines.append(f"  Prony g@tau    {pairs} (long-term fraction {1.0 - weights.sum():.4f})")
    failure = material.failure
    lines.append(f"  failure        {failure.criterion}" + ("" if failure.criterion == "none" else
                                                             f" >= {failure.limit:g} MPa"))
    stresses = nominal_stress(material.model, material.parameters(), "uniaxial", np.array(REPORT_STRETCHES))
    lines.append("  uniaxial P     " + ", ".join(f"{s:g}: {p:.4g} MPa" for s, p in zip(REPORT_STRETCHES, stresses))
                 + " (incompressible, nominal" + (", along the fibres' bisector)" if fibres else ")"))
    for direction in DIRECTIONS[1:] if fibres else ():
        cauchy = directional_cauchy_stress(material.model, material.parameters(), "uniaxial",
                                           np.array(REPORT_STRETCHES), direction)
        lines.append(f"  {direction:<15}"
                     + ", ".join(f"{s:g}: {c / s:.4g} MPa" for s, c in zip(REPORT_STRETCHES, cauchy)))
    verdict = "stable" if stability.stable else "UNSTABLE: " + stability.unstable_ranges_text()
    lines.append(f"  stability      {verdict}")
    return "\n".join(lines)


def fit_to_toml(result: FitResult, name: str, d1: float, density: float, source: str) -> str:
    """A complete material TOML file for a fitted law (every value with its unit)."""
    lines = [
        f"# Fitted by 'corneasim material fit': {result.model}, RMSE {result.rmse:.4g} MPa, "
        f"max error {result.max_error:.4g} MPa, stable over stretch 0.1-10.",
        "# Save as a .toml file and give its path as the material (units: MPa, 1/MPa, s, tonne/mm^3).",
        f'name = "{name}"',
        f'description = "{result.model} fitted to {source}"',
        f'source = "{source}"',
        f"density = {density:.6g}          # tonne/mm^3",
        "",
        "[hyperelastic]",
        f'model = "{result.model}"',
    ]
    for key, value in result.constants().items():
        lines.append(f"{key} = {value:.8g}          # {_CONSTANT_UNITS.get(key, 'MPa')}")
    lines.append(f"d1 = {d1:.6g}          # 1/MPa, D1 = 2 / K")
    lines += ["", "[failure]", 'criterion = "none"   # or von-mises, with limit = ... (MPa)']
    return "\n".join(lines) + "\n"
