"""Material laws: hyperelasticity, Prony viscoelasticity, failure criteria, stability, fitting.

Units: MPa (moduli, stresses, energy densities in mJ/mm^3), 1/MPa (D1), s (times),
tonne/mm^3 (density). See docs/materials.md.

* the law itself, inlined by the element kernels and called by everything else: ``_law``;
  named laws (``Law``, ``register_law``, ``LAWS``: the registry of ``_laws``);
* pointwise laws: ``strain_energy``/``cauchy_stress(model, p, F)`` of a registered law and
  (Numba) ``kernel_energy``/``kernel_stress(F, record)``, the exact law of the element kernels
  for a :class:`KernelMaterial` record;
* ``viscoelastic_stress(F, history, dt, record) -> (sigma, history_new)``;
* failure: ``von_mises_stress``, ``failure_ratio``, ``distortion_energy_density``, ``volumetric_energy_density``;
* ``check_stability``, ``fit_hyperelastic``, presets ``load_material``/``list_presets``;
* published ranges of the constants (``published_ranges.toml``): ``published_ranges``,
  ``material_constants``/``scenario_constants``, ``check_constants``, ``check_material``,
  ``out_of_range``.
"""

from corneasim.materials._calibration import (
    calibrate_cornea, calibrate_cornea_in_vivo, in_vivo_uniaxial_curve, published_uniaxial_curve)
from corneasim.materials._failure import (
    distortion_energy_density,
    distortion_energy_limit,
    failure_ratio,
    volumetric_energy_density,
    von_mises_stress,
)
from corneasim.materials._fitting import FIT_MODELS, FitResult, fit_hyperelastic
from corneasim.materials._homogeneous import MODES, cauchy_stress as homogeneous_cauchy_stress
from corneasim.materials._homogeneous import nominal_stress as homogeneous_nominal_stress
from corneasim.materials._hyperelastic import (
    cauchy_stress,
    kernel_energy,
    kernel_stress,
    kernel_stress_split,
    linear_elastic_to_neo_hooke,
    strain_energy,
)
from corneasim.materials._kernel_form import KernelMaterial, kernel_table
from corneasim.materials._laws import LAWS, Law, register_law
from corneasim.materials._ranges import (
    PublishedRange,
    RangeCheck,
    check_constants,
    check_material,
    material_constants,
    out_of_range,
    published_ranges,
    scenario_constants,
)
from corneasim.materials._presets import DEFAULT_MATERIAL, list_presets, load_material, stability_of
from corneasim.materials._spec import MaterialSpec
from corneasim.materials._stability import StabilityReport, check_stability
from corneasim.materials._viscoelastic import (
    HISTORY_SHAPE,
    new_history,
    normalised_prony_weights,
    viscoelastic_stress,
)

__all__ = [
    "DEFAULT_MATERIAL", "FIT_MODELS", "FitResult", "HISTORY_SHAPE", "KernelMaterial", "LAWS", "Law",
    "MODES", "MaterialSpec", "PublishedRange", "RangeCheck", "StabilityReport", "calibrate_cornea",
    "calibrate_cornea_in_vivo", "cauchy_stress", "check_constants", "check_material",
    "check_stability", "distortion_energy_density", "distortion_energy_limit", "failure_ratio",
    "fit_hyperelastic", "homogeneous_cauchy_stress", "homogeneous_nominal_stress",
    "in_vivo_uniaxial_curve", "kernel_energy", "kernel_stress", "kernel_stress_split",
    "kernel_table", "linear_elastic_to_neo_hooke", "list_presets", "load_material",
    "material_constants", "new_history", "normalised_prony_weights", "out_of_range",
    "published_ranges", "published_uniaxial_curve", "register_law", "scenario_constants",
    "stability_of", "strain_energy", "viscoelastic_stress", "volumetric_energy_density",
    "von_mises_stress",
]
