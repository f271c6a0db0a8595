"""The validated material description read from TOML (presets and user files).

A material file has the top-level keys ``name``, ``description``, ``source``,
``density`` and the tables ``[hyperelastic]``, optional ``[viscoelastic]`` and
optional ``[failure]``. Units: MPa for moduli and stresses, 1/MPa for D1, s for
relaxation times, tonne/mm^3 for density. Validation is strict: unknown keys,
wrong types, non-positive moduli or D1, and Prony lists of unequal length are
:class:`~corneasim.errors.InputError` (see docs/materials.md).
"""

from __future__ import annotations

from typing import Annotated, Literal, Union

import numpy as np
import pydantic
from pydantic import Field

from corneasim.materials._hyperelastic import linear_elastic_to_neo_hooke
from corneasim.materials._kernel_form import FAILURE_CODES, MAX_PRONY_TERMS, KernelMaterial
from corneasim.materials._laws import family_constants, fibre_constants
from corneasim.materials._viscoelastic import normalised_prony_weights
from corneasim.schema import StrictModel

Positive = Annotated[float, Field(gt=0.0)]
D1 = Annotated[float, Field(gt=0.0, description="Compressibility D1 = 2 / K, 1/MPa (> 0).")]


class _Strict(StrictModel):
    model_config = pydantic.ConfigDict(extra="forbid", frozen=True, strict=True)


class NeoHooke(_Strict):
    """W = C10 (I1bar - 3) + (J - 1)^2 / D1."""

    model: Literal["neo-hooke"]
    c10: Positive = Field(description="C10 = mu / 2, MPa (> 0).")
    d1: D1

    def parameters(self) -> np.ndarray:
        """``[C10, D1]``."""
        return np.array([self.c10, self.d1])


class MooneyRivlin(_Strict):
    """W = C10 (I1bar - 3) + C01 (I2bar - 3) + (J - 1)^2 / D1 (needle paper eq. 4)."""

    model: Literal["mooney-rivlin"]
    c10: Positive = Field(description="C10, MPa (> 0).")
    c01: float = Field(description="C01, MPa (any sign; check stability).")
    d1: D1

    def parameters(self) -> np.ndarray:
        """``[C10, C01, D1]``."""
        return np.array([self.c10, self.c01, self.d1])


class Yeoh(_Strict):
    """W = C10 (I1bar - 3) + C20 (I1bar - 3)^2 + C30 (I1bar - 3)^3 + (J - 1)^2 / D1."""

    model: Literal["yeoh"]
    c10: Positive = Field(description="C10, MPa (> 0).")
    c20: float = Field(0.0, description="C20, MPa.")
    c30: float = Field(0.0, description="C30, MPa.")
    d1: D1

    def parameters(self) -> np.ndarray:
        """``[C10, C20, C30, D1]``."""
        return np.array([self.c10, self.c20, self.c30, self.d1])


class HolzapfelGasserOgden(_Strict):
    """Fibre-reinforced stroma: Mooney-Rivlin ground matter plus two dispersed fibre families.

    W = C10 (I1bar - 3) + C01 (I2bar - 3) + sum_i k1/(2 k2) [exp(k2 E_i^2) - 1]
    + (J - 1)^2 / D1, E_i = kappa (I1bar - 3) + (1 - 3 kappa)(I4i_bar - 1) > 0 (``_fibre_law``;
    Gasser, Ogden & Holzapfel 2006, doi:10.1098/rsif.2005.0073). The families lie in the
    lamellar plane at +-fibre_angle from their bisector.
    """

    model: Literal["holzapfel-gasser-ogden"]
    c10: Positive = Field(description="C10 of the ground matter = mu / 2, MPa (> 0).")
    c01: float = Field(0.0, ge=0.0, description="C01 of the ground matter, MPa (>= 0).")
    k1: float = Field(ge=0.0, description="Fibre stiffness k1, MPa (>= 0).")
    k2: float = Field(ge=0.0, description="Fibre exponent k2, dimensionless (>= 0).")
    kappa: float = Field(ge=0.0, le=1.0 / 3.0,
                         description="Dispersion kappa, dimensionless, 0 (aligned) to 1/3 (isotropic).")
    fibre_angle: float = Field(ge=0.0, le=90.0,
                               description="Angle of each family from their bisector, degrees (0 to 90).")
    d1: D1

    def parameters(self) -> np.ndarray:
        """``[C10, C01, k1, k2, kappa, fibre_angle, D1]``."""
        return np.array([self.c10, self.c01, self.k1, self.k2, self.kappa, self.fibre_angle, self.d1])


class LinearElastic(_Strict):
    """Small-strain (E, nu), evaluated as the compressible neo-Hooke law of equal moduli."""

    model: Literal["linear-elastic"]
    youngs_modulus: Positive = Field(description="Young's modulus E, MPa (> 0).")
    poisson_ratio: float = Field(gt=-1.0, lt=0.5, description="Poisson's ratio, -1 < nu < 0.5.")

    def parameters(self) -> np.ndarray:
        """``[C10, D1]`` of the equivalent neo-Hooke law."""
        return np.array(linear_elastic_to_neo_hooke(self.youngs_modulus, self.poisson_ratio))


Hyperelastic = Annotated[Union[NeoHooke, MooneyRivlin, Yeoh, HolzapfelGasserOgden, LinearElastic],
                         Field(discriminator="model")]


class Viscoelastic(_Strict):
    """Prony series in moduli, G(t) = sum E_i exp(-t / tau_i) + E_inf (needle paper eq. 2)."""

    prony_moduli: list[Annotated[float, Field(ge=0.0)]] = Field(description="E_i, MPa (>= 0).")
    long_term_modulus: Positive = Field(description="E_inf, MPa (> 0).")
    relaxation_times: list[Positive] = Field(description="tau_i, s (> 0).")

    @pydantic.model_validator(mode="after")
    def _check(self):
        if len(self.prony_moduli) != len(self.relaxation_times):
            raise ValueError(
                f"prony_moduli and relaxation_times must have equal length "
                f"(got {len(self.prony_moduli)} and {len(self.relaxation_times)})"
            )
        if len(self.prony_moduli) > MAX_PRONY_TERMS:
            raise ValueError(f"at most {MAX_PRONY_TERMS} Prony terms are supported")
        return self

    def weights(self) -> np.ndarray:
        """Normalised weights g_i (dimensionless)."""
        return normalised_prony_weights(self.prony_moduli, self.long_term_modulus)


class Failure(_Strict):
    """Failure criterion and its limit."""

    criterion: Literal["none", "von-mises"] = "none"
    limit: float = Field(0.0, ge=0.0, description="Von Mises stress at failure, MPa.")

    @pydantic.model_validator(mode="after")
    def _check(self):
        if self.criterion != "none" and self.limit <= 0.0:
            raise ValueError(f"limit must be > 0 for criterion {self.criterion!r}")
        return self


class MaterialSpec(_Strict):
    """A complete material: density, hyperelastic law, optional Prony series and failure."""

    name: str
    description: str = ""
    source: str = Field("", description="Where the constants come from.")
    density: Positive = Field(description="Mass density, tonne/mm^3 (water: 1.0e-9).")
    hyperelastic: Hyperelastic
    viscoelastic: Viscoelastic | None = None
    failure: Failure = Failure()

    @property
    def model(self) -> str:
        """Law name for the pointwise functions (``linear-elastic`` maps to ``neo-hooke``)."""
        model = self.hyperelastic.model
        return "neo-hooke" if model == "linear-elastic" else model

    def parameters(self) -> np.ndarray:
        """Parameter array of the law (layout of ``_hyperelastic.py``)."""
        return self.hyperelastic.parameters()

    @property
    def initial_shear_modulus(self) -> float:
        """Instantaneous small-strain shear modulus mu_0, MPa (of the ground matter for a fibre law)."""
        c10, c01, _, _ = family_constants(self.model, self.parameters())
        return float(2.0 * (c10 + c01))

    @property
    def bulk_modulus(self) -> float:
        """Small-strain bulk modulus K = 2 / D1, MPa."""
        return float(2.0 / self.parameters()[-1])

    @property
    def youngs_modulus(self) -> float:
        """Small-strain Young's modulus 9 K mu / (3 K + mu), MPa."""
        mu, k = self.initial_shear_modulus, self.bulk_modulus
        return 9.0 * k * mu / (3.0 * k + mu)

    @property
    def poisson_ratio(self) -> float:
        """Small-strain Poisson's ratio (3K - 2 mu) / (2 (3K + mu))."""
        mu, k = self.initial_shear_modulus, self.bulk_modulus
        return (3.0 * k - 2.0 * mu) / (2.0 * (3.0 * k + mu))

    def kernel_form(self) -> KernelMaterial:
        """The flat record the element kernels read (the family constants of the law and,
        for a fibre-reinforced law, its fibre constants; the fibre directions are the
        mesh's, ``docs/materials.md`` "Fibre-reinforced stroma")."""
        p = self.parameters()
        c10, c01, c20, c30 = family_constants(self.model, p)
        k1, k2, kappa, angle = fibre_constants(self.model, p) or (0.0, 0.0, 0.0, 0.0)
        prony_g, prony_tau = (), ()
        if self.viscoelastic is not None:
            prony_g = tuple(float(g) for g in self.viscoelastic.weights())
            prony_tau = tuple(float(t) for t in self.viscoelastic.relaxation_times)
        return KernelMaterial(
            density=self.density,
            c10=float(c10), c01=float(c01), c20=float(c20), c30=float(c30), d1=float(p[-1]),
            prony_g=prony_g,
            prony_tau=prony_tau,
            failure_criterion=FAILURE_CODES[self.failure.criterion],
            failure_limit=self.failure.limit,
            fibre_k1=float(k1), fibre_k2=float(k2), fibre_kappa=float(kappa), fibre_angle=float(angle),
        )
