"""One-point axisymmetric quad and hexahedron kernels for the explicit solver.

Contract with the integrator: ``docs/dev/solver-api.md``; theory and choices:
``docs/elements.md``.
"""

from corneasim.solver.elements._api import (
    ElementSet, element_jacobians, element_stress, eval_internal_forces,
    lumped_masses, new_history, prepare, stable_time_steps, stored_energy)
from corneasim.solver.elements._fast import FORCE_KERNELS

__all__ = [
    "FORCE_KERNELS", "ElementSet", "element_jacobians", "element_stress", "eval_internal_forces",
    "lumped_masses", "new_history", "prepare", "stable_time_steps", "stored_energy",
]
