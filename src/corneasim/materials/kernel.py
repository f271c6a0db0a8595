"""What the element kernels evaluate: the material record's slots and the pointwise law.

The solver's element kernels (``corneasim.solver.elements``) import the material from
here and nowhere else in ``materials``:

* the flat record of a :class:`KernelMaterial` (``P_*`` columns of ``kernel_table``) and
  the packed row of the fast kernels (``M_*`` columns of ``packed_constants``);
* the material point, the law at a 3x3 F (``elastic_pk2``, ``elastic_energy``,
  ``isochoric_strain_energy``, ``cauchy_from_pk2``, with ``kinematics``, ``inverse_sym``
  and the ``VOIGT`` tables);
* the pointwise law, scalar ``@njit(inline="always")`` functions that Numba copies into
  the calling loop: the isochoric and volumetric stress of the invariant family
  (``isochoric_pk2``, ``volumetric_factor``) and their energies and derivatives, the fibre
  term (``fibre_pk2``, ``fibre_strain``, ``fibre_energy``, ``fibre_derivatives``,
  ``fibre_tangent_bound``, ``exp_nonnegative``), the Prony update (``prony_factors``,
  ``prony_step``) and the failure measure (``von_mises``, divided by the limit in
  ``limit_ratio``).

A new law provides its functions and slots here (``docs/elements.md``, "Adding a material
law").
"""

from corneasim.materials._failure import limit_ratio
from corneasim.materials._fibre_law import (
    exp_nonnegative, fibre_derivatives, fibre_energy, fibre_pk2, fibre_strain, fibre_tangent_bound)
from corneasim.materials._kernel_form import (
    FAILURE_CODES, FAILURE_NONE, FAILURE_VON_MISES, M_BULK, M_C01, M_C10, M_C20, M_C30,
    M_DISSIPATION, M_FIBRE_COS, M_FIBRE_K1, M_FIBRE_K2, M_FIBRE_KAPPA, M_FIBRE_SIN,
    M_INVERSE_LIMIT, M_LONG_TERM, M_PRONY_A, M_PRONY_B, MAX_PRONY_TERMS, N_CONSTANTS, N_PACKED,
    N_PARAMETERS, P_C01, P_C10, P_C20, P_C30, P_D1, P_DENSITY, P_FAILURE_CRITERION,
    P_FAILURE_LIMIT, P_FIBRE_ANGLE, P_FIBRE_K1, P_FIBRE_K2, P_FIBRE_KAPPA, P_N_PRONY, P_PRONY_G,
    P_PRONY_TAU, KernelMaterial, kernel_table, packed_constants)
from corneasim.materials._law import (
    isochoric_derivatives, isochoric_energy, isochoric_pk2, prony_factors, prony_step,
    volumetric_energy, volumetric_factor, von_mises)
from corneasim.materials._point import (
    POINT_FRAME, VOIGT, VOIGT_PAIRS, cauchy_from_pk2, elastic_energy, elastic_pk2, inverse_sym,
    isochoric_strain_energy, kinematics, symmetric_matrix)

__all__ = [
    "FAILURE_CODES", "FAILURE_NONE", "FAILURE_VON_MISES", "KernelMaterial", "MAX_PRONY_TERMS",
    "M_BULK", "M_C01", "M_C10", "M_C20", "M_C30", "M_DISSIPATION", "M_FIBRE_COS", "M_FIBRE_K1",
    "M_FIBRE_K2", "M_FIBRE_KAPPA", "M_FIBRE_SIN", "M_INVERSE_LIMIT", "M_LONG_TERM", "M_PRONY_A",
    "M_PRONY_B", "N_CONSTANTS", "N_PACKED", "N_PARAMETERS", "POINT_FRAME", "P_C01", "P_C10",
    "P_C20", "P_C30", "P_D1", "P_DENSITY", "P_FAILURE_CRITERION", "P_FAILURE_LIMIT",
    "P_FIBRE_ANGLE", "P_FIBRE_K1", "P_FIBRE_K2", "P_FIBRE_KAPPA", "P_N_PRONY", "P_PRONY_G",
    "P_PRONY_TAU", "VOIGT", "VOIGT_PAIRS", "cauchy_from_pk2", "elastic_energy", "elastic_pk2",
    "exp_nonnegative", "fibre_derivatives", "fibre_energy", "fibre_pk2", "fibre_strain",
    "fibre_tangent_bound", "inverse_sym", "isochoric_derivatives", "isochoric_energy",
    "isochoric_pk2", "isochoric_strain_energy", "kernel_table", "kinematics", "limit_ratio",
    "packed_constants", "prony_factors", "prony_step", "symmetric_matrix", "volumetric_energy",
    "volumetric_factor", "von_mises",
]
