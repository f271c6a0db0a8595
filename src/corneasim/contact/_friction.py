"""Friction laws of the instrument-tissue contact: regularised Coulomb and the needle paper's law.

A law packs into ``[kind, mu, beta, F_c, b, v_valid, mu_limit]`` for the contact kernel,
which regularises stick by a tangential penalty spring k_t = beta k_n (elastic slip of
at most mu_eff p, p the penetration) and caps the friction at mu_eff f_n
(:mod:`corneasim.contact._node`).

* ``none``: frictionless.
* ``coulomb``: mu_eff = mu, a constant coefficient.
* ``karnopp``: the needle paper's lumped law (its eq. 3, after Xuan et al.): the total
  friction force on the needle F(v) = F_c + b v, F_c = 0.371 N, b = 0.1171 N s/mm,
  stated valid for v >= 0.84 mm/s. It becomes a contact traction through an effective
  coefficient mu_eff = min(F(s) / N, mu_limit), N the total normal contact force of the
  step, so each sliding node carries f_t = mu_eff f_n (the total friction F(v) is
  shared over the nodes in proportion to their normal force, and is F(v) exactly when
  every node slides at the needle speed v; s is each node's tangential speed relative to
  the instrument). mu_limit caps the friction where the normal force is still small
  (first touch), so there is no friction without contact pressure.

The paper prints the law as f = -0.371 sgn(v) + 0.1171 v. Read literally, its viscous
part pushes the needle forward (negative damping) and the friction would vanish at
3.17 mm/s, contradicting the paper's statement that a faster insertion meets more
friction. Both parts are taken here as resisting: f = -sgn(v)(0.371 + 0.1171 |v|).
"""

from __future__ import annotations

import warnings
from typing import Annotated, Literal

import numpy as np
import pydantic
from numba import njit

from corneasim.schema import StrictModel

NONE, COULOMB, KARNOPP = 0, 1, 2
LAWS = {"none": NONE, "coulomb": COULOMB, "karnopp": KARNOPP}

KARNOPP_COULOMB_FORCE = 0.371
"""F_c of the needle paper's eq. 3, N."""
KARNOPP_VISCOUS_COEFFICIENT = 0.1171
"""b of the needle paper's eq. 3, N s/mm."""
KARNOPP_MINIMUM_SPEED = 0.84
"""Lowest speed for which the needle paper states eq. 3 valid, mm/s."""


class FrictionValidityWarning(UserWarning):
    """A friction law used outside the range its source states it valid for."""


@njit(cache=True)
def needle_friction_force(speed, coulomb_force, viscous_coefficient):
    """Total friction force resisting a needle moving at ``speed`` (needle paper eq. 3).

    .. math:: f(\\dot x) = -\\operatorname{sgn}(\\dot x)\\,(F_c + b\\,|\\dot x|)

    Parameters
    ----------
    speed : float
        Needle velocity relative to the tissue, mm/s (signed).
    coulomb_force, viscous_coefficient : float
        F_c in N and b in N s/mm (paper: 0.371 N and 0.1171 N s/mm).

    Returns
    -------
    float
        The friction force on the needle along its motion, N (opposite in sign to ``speed``).
    """
    if speed == 0.0:
        return 0.0
    magnitude = coulomb_force + viscous_coefficient * abs(speed)
    return -magnitude if speed > 0.0 else magnitude


@njit(cache=True)
def effective_coefficient(friction, slip_speed, normal_total):
    """Friction coefficient mu_eff for a node sliding at ``slip_speed`` (mm/s).

    Coulomb: mu. Karnopp: min(F(s) / N, mu_limit) with N = ``normal_total`` (N).
    """
    kind = int(friction[0])
    if kind == COULOMB:
        return friction[1]
    if kind == KARNOPP:
        if normal_total <= 0.0:
            return 0.0
        lumped = -needle_friction_force(slip_speed, friction[3], friction[4])
        return min(lumped / normal_total, friction[6])
    return 0.0


class Friction(StrictModel):
    """Friction law of a contact pair.

    Attributes
    ----------
    law : str
        ``none``, ``coulomb`` or ``karnopp``.
    coefficient : float
        Coulomb coefficient mu, dimensionless (the papers give none; 0.1 is an assumption).
    tangential_stiffness_ratio : float
        beta = k_t / k_n of the tangential (stick) penalty spring, 0 < beta <= 1, dimensionless.
    coulomb_force : float
        F_c of the lumped law, N.
    viscous_coefficient : float
        b of the lumped law, N s/mm.
    minimum_valid_speed : float
        Speed below which the lumped law is extrapolated (with a warning), mm/s.
    coefficient_limit : float
        Largest effective coefficient the lumped law may give, dimensionless.
    """

    law: Literal["none", "coulomb", "karnopp"] = "coulomb"
    coefficient: Annotated[float, pydantic.Field(ge=0.0)] = 0.1
    tangential_stiffness_ratio: Annotated[float, pydantic.Field(gt=0.0, le=1.0)] = 1.0
    coulomb_force: Annotated[float, pydantic.Field(ge=0.0)] = KARNOPP_COULOMB_FORCE
    viscous_coefficient: Annotated[float, pydantic.Field(ge=0.0)] = KARNOPP_VISCOUS_COEFFICIENT
    minimum_valid_speed: Annotated[float, pydantic.Field(ge=0.0)] = KARNOPP_MINIMUM_SPEED
    coefficient_limit: Annotated[float, pydantic.Field(ge=0.0)] = 1.0

    def pack(self) -> np.ndarray:
        """``[kind, mu, beta, F_c, b, v_valid, mu_limit]`` for the contact kernel."""
        return np.array(
            [
                LAWS[self.law],
                self.coefficient,
                self.tangential_stiffness_ratio,
                self.coulomb_force,
                self.viscous_coefficient,
                self.minimum_valid_speed,
                self.coefficient_limit,
            ],
            dtype=np.float64,
        )

    def check_speed(self, speed: float) -> bool:
        """Warn (:class:`FrictionValidityWarning`) if the lumped law is used below its valid speed.

        Parameters
        ----------
        speed : float
            Instrument speed relative to the tissue, mm/s.

        Returns
        -------
        bool
            True when the law is used within its stated range (or is not the lumped law).
        """
        if self.law != "karnopp" or abs(speed) >= self.minimum_valid_speed:
            return True
        warnings.warn(
            f"friction: the needle paper's law (eq. 3) is stated valid for speeds >= "
            f"{self.minimum_valid_speed} mm/s; {abs(speed):.4g} mm/s extrapolates it",
            FrictionValidityWarning,
            stacklevel=2,
        )
        return False
