"""The flat material record that element kernels evaluate.

Element kernels support one straight-line strain-energy family that covers every
law the papers use, so a single vectorised kernel serves all blocks:

.. math::

    W = C_{10}(\\bar I_1 - 3) + C_{01}(\\bar I_2 - 3) + C_{20}(\\bar I_1 - 3)^2
        + C_{30}(\\bar I_1 - 3)^3 + \\frac{1}{D_1}(J - 1)^2

neo-Hookean (only C10), Mooney-Rivlin (C10, C01), Yeoh (C10, C20, C30) and the
sclera's compressible neo-Hookean are members. The hyperelastic constants give the
*instantaneous* response; a Prony series with normalised weights g_i (sum < 1) and
times tau_i relaxes the isochoric (deviatoric) second Piola-Kirchhoff stress so
that the long-term deviatoric response is (1 - sum g_i) times the instantaneous one:

.. math::

    S = S_{vol} + (1 - \\textstyle\\sum_i g_i)\\,\\bar S_0 + \\sum_i h_i, \\qquad
    h_i^{n+1} = e^{-\\Delta t/\\tau_i} h_i^n
        + g_i \\frac{1 - e^{-\\Delta t/\\tau_i}}{\\Delta t/\\tau_i}(\\bar S_0^{n+1} - \\bar S_0^n)

(exact for a stress history linear within each step; Simo & Hughes 1998, ch. 10;
Taylor et al. 2009, doi:10.1002/cnm.1146).

A fibre-reinforced material adds the two dispersed fibre families of ``_fibre_law``
(Holzapfel-Gasser-Ogden with dispersion, constants k1, k2, kappa and the angle of the
families from their bisector) to the isochoric energy. Their isochoric stress is part of
the instantaneous isochoric stress :math:`\\bar S_0` above, so the same Prony series
relaxes matrix and fibres alike (a single relaxation spectrum of the stroma, as the
needle paper fits it). The directions are per element (``elements.prepare``,
``fibre_frame``): a unit vector m (the bisector) and a unit vector n orthogonal to it in
the lamellar plane, the families along cos(angle) m +- sin(angle) n.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MAX_PRONY_TERMS = 4
"""Largest number of Prony terms a kernel material carries."""

FAILURE_NONE = 0
FAILURE_VON_MISES = 1
FAILURE_CODES = {"none": FAILURE_NONE, "von-mises": FAILURE_VON_MISES}

# Layout of the flat record (one row per material in a (n_materials, N_PARAMETERS) array).
P_DENSITY = 0
P_C10 = 1
P_C01 = 2
P_C20 = 3
P_C30 = 4
P_D1 = 5
P_N_PRONY = 6
P_PRONY_G = 7
P_PRONY_TAU = P_PRONY_G + MAX_PRONY_TERMS
P_FAILURE_CRITERION = P_PRONY_TAU + MAX_PRONY_TERMS
P_FAILURE_LIMIT = P_FAILURE_CRITERION + 1
P_FIBRE_K1 = P_FAILURE_LIMIT + 1  # MPa; 0: no fibres
P_FIBRE_K2 = P_FIBRE_K1 + 1  # dimensionless
P_FIBRE_KAPPA = P_FIBRE_K2 + 1  # dimensionless, 0 .. 1/3
P_FIBRE_ANGLE = P_FIBRE_KAPPA + 1  # rad, of each family from the bisector m
N_PARAMETERS = P_FIBRE_ANGLE + 1

# Layout of the packed row the fast kernels gather per material (``packed_constants``):
# the constants, the Prony factors of the current step (``M_PRONY_A``, ``M_PRONY_B``), the
# fibre constants (``M_FIBRE_*``).
M_C10, M_C01, M_C20, M_C30 = 0, 1, 2, 3  # strain-energy constants, MPa
M_BULK = 4  # K = 2 / D1, MPa
M_LONG_TERM = 5  # g_inf = 1 - sum g_i, the long-term fraction of the isochoric stress
M_DISSIPATION = 6  # 1 / (2 g_i mu_0 tau_i), 1/(MPa s), one per Prony term
M_INVERSE_LIMIT = M_DISSIPATION + MAX_PRONY_TERMS  # 1 / von Mises limit, 1/MPa (0: no criterion)
N_CONSTANTS = M_INVERSE_LIMIT + 1
M_PRONY_A = N_CONSTANTS  # a_i = exp(-dt / tau_i) of the step, one per Prony term
M_PRONY_B = M_PRONY_A + MAX_PRONY_TERMS  # b_i = g_i (1 - a_i) / (dt / tau_i)
# the fibre constants last, so that a kernel can keep them apart from the isotropic rows
M_FIBRE_K1 = M_PRONY_B + MAX_PRONY_TERMS  # MPa
M_FIBRE_K2, M_FIBRE_KAPPA = M_FIBRE_K1 + 1, M_FIBRE_K1 + 2  # dimensionless
M_FIBRE_COS, M_FIBRE_SIN = M_FIBRE_K1 + 3, M_FIBRE_K1 + 4  # of the family angle
N_PACKED = M_FIBRE_SIN + 1


@dataclass(frozen=True)
class KernelMaterial:
    """Material constants in the form the element kernels read.

    Attributes
    ----------
    density : float
        Mass density, tonne/mm^3 (cornea about 1.062e-9).
    c10, c01, c20, c30 : float
        Strain-energy constants, MPa.
    d1 : float
        Compressibility, 1/MPa; bulk modulus K = 2 / D1. Must be > 0.
    prony_g : tuple of float
        Normalised relaxation weights g_i (dimensionless, each >= 0, sum < 1).
    prony_tau : tuple of float
        Relaxation times tau_i, s (> 0), same length as ``prony_g``.
    failure_criterion : int
        ``FAILURE_NONE`` or ``FAILURE_VON_MISES``.
    failure_limit : float
        Limit of the von Mises stress, MPa.
    fibre_k1 : float
        Fibre stiffness k1, MPa (0: an isotropic material).
    fibre_k2 : float
        Fibre exponent k2, dimensionless (>= 0).
    fibre_kappa : float
        Fibre dispersion kappa, dimensionless, 0 (aligned) to 1/3 (isotropic).
    fibre_angle : float
        Angle of each family from the bisector m of the element's fibre frame, rad.
    """

    density: float
    c10: float
    c01: float = 0.0
    c20: float = 0.0
    c30: float = 0.0
    d1: float = 1.0
    prony_g: tuple[float, ...] = ()
    prony_tau: tuple[float, ...] = ()
    failure_criterion: int = FAILURE_NONE
    failure_limit: float = 0.0
    fibre_k1: float = 0.0
    fibre_k2: float = 0.0
    fibre_kappa: float = 0.0
    fibre_angle: float = 0.0

    @property
    def initial_shear_modulus(self) -> float:
        """Instantaneous small-strain shear modulus mu_0 = 2 (C10 + C01), MPa."""
        return 2.0 * (self.c10 + self.c01)

    @property
    def bulk_modulus(self) -> float:
        """Small-strain bulk modulus K = 2 / D1, MPa."""
        return 2.0 / self.d1

    @property
    def has_fibres(self) -> bool:
        """Whether the material has fibre families (k1 > 0)."""
        return self.fibre_k1 > 0.0

    @property
    def dilatational_modulus(self) -> float:
        """Instantaneous P-wave modulus K + 4/3 |mu_0| + 8 k1, MPa (for the stable time step;
        8 k1 is the bound of the two fibre families at rest, ``elements._time_step``)."""
        return self.bulk_modulus + 4.0 / 3.0 * abs(self.initial_shear_modulus) + 8.0 * self.fibre_k1

    @property
    def wave_speed(self) -> float:
        """Instantaneous dilatational wave speed sqrt((K + 4/3 mu_0) / rho), mm/s."""
        return float(np.sqrt(self.dilatational_modulus / self.density))

    def as_array(self) -> np.ndarray:
        """The flat record, shape (N_PARAMETERS,), float64, in the ``P_*`` layout."""
        if len(self.prony_g) != len(self.prony_tau) or len(self.prony_g) > MAX_PRONY_TERMS:
            raise ValueError("prony_g and prony_tau must have equal length <= MAX_PRONY_TERMS")
        record = np.zeros(N_PARAMETERS)
        record[P_DENSITY] = self.density
        record[P_C10], record[P_C01], record[P_C20], record[P_C30] = self.c10, self.c01, self.c20, self.c30
        record[P_D1] = self.d1
        n = len(self.prony_g)
        record[P_N_PRONY] = n
        record[P_PRONY_G : P_PRONY_G + n] = self.prony_g
        record[P_PRONY_TAU : P_PRONY_TAU + n] = self.prony_tau
        record[P_PRONY_TAU + n : P_PRONY_TAU + MAX_PRONY_TERMS] = 1.0
        record[P_FAILURE_CRITERION] = self.failure_criterion
        record[P_FAILURE_LIMIT] = self.failure_limit
        record[P_FIBRE_K1], record[P_FIBRE_K2] = self.fibre_k1, self.fibre_k2
        record[P_FIBRE_KAPPA], record[P_FIBRE_ANGLE] = self.fibre_kappa, self.fibre_angle
        return record


def kernel_table(materials: list[KernelMaterial]) -> np.ndarray:
    """Stack kernel materials into a (n_materials, N_PARAMETERS) float64 table."""
    return np.stack([material.as_array() for material in materials])


def packed_constants(table: np.ndarray) -> np.ndarray:
    """The fast kernels' rows (n_materials, N_PACKED) of a kernel table, Prony factors zero.

    The constants are those of the ``M_*`` layout; the kernels multiply by 1 / limit (0
    without a criterion) and by the dissipation factors, so no division or branch is left
    in their vector loops.
    """
    out = np.zeros((table.shape[0], N_PACKED))
    for m, row in enumerate(table):
        n = int(row[P_N_PRONY])
        g = row[P_PRONY_G:P_PRONY_G + n]
        tau = row[P_PRONY_TAU:P_PRONY_TAU + n]
        mu0 = 2.0 * (row[P_C10] + row[P_C01])
        out[m, M_C10], out[m, M_C01] = row[P_C10], row[P_C01]
        out[m, M_C20], out[m, M_C30] = row[P_C20], row[P_C30]
        out[m, M_BULK] = 2.0 / row[P_D1]
        out[m, M_LONG_TERM] = 1.0 - g.sum()
        for i in range(n):
            if g[i] > 0.0 and mu0 != 0.0:
                out[m, M_DISSIPATION + i] = 1.0 / (2.0 * g[i] * mu0 * tau[i])
        limit = row[P_FAILURE_LIMIT]
        if row[P_FAILURE_CRITERION] == FAILURE_VON_MISES and limit > 0.0:
            out[m, M_INVERSE_LIMIT] = 1.0 / limit
        out[m, M_FIBRE_K1], out[m, M_FIBRE_K2] = row[P_FIBRE_K1], row[P_FIBRE_K2]
        out[m, M_FIBRE_KAPPA] = row[P_FIBRE_KAPPA]
        out[m, M_FIBRE_COS], out[m, M_FIBRE_SIN] = np.cos(row[P_FIBRE_ANGLE]), np.sin(row[P_FIBRE_ANGLE])
    return out
