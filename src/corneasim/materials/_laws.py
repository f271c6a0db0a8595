"""The registry of named hyperelastic laws: their constants and their place in the family.

Every named law is a member of the strain-energy family that ``_law`` evaluates (and with
it every element kernel): a :class:`Law` says which constants the law has, in the order of
its parameter array, and which family constants (C10, C01, C20, C30, MPa) they are. The
curve code (``_homogeneous``, hence fitting and the stability check), the pointwise
``strain_energy``/``cauchy_stress`` of ``_hyperelastic`` and ``MaterialSpec.kernel_form``
look a law up here by name, so a new member is one module that calls :func:`register_law`
(``docs/elements.md``, "Adding a material law"). A fibre-reinforced law (Holzapfel-Gasser-
Ogden with dispersion, ``_fibre_law``) is a member of the family for its ground matrix plus
the fibre term its ``fibres`` map gives.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from corneasim.errors import InputError


@dataclass(frozen=True)
class Law:
    """A named hyperelastic law.

    Attributes
    ----------
    name : str
        The ``model`` key of the law, e.g. ``"neo-hooke"``.
    keys : tuple of str
        Names of its constants (MPa unless the law's table class says otherwise) in the
        order of its parameter array; the array ends with D1 (1/MPa), which is not listed.
    family : callable
        ``family(parameters) -> (c10, c01, c20, c30)``, MPa: the family member it is.
    fit_start : tuple of float
        Start of a least-squares fit, in units of the data's stiffness scale (one per key);
        the first constant is kept > 0 and the others >= 0 in the first fitting stage.
    fibres : callable or None
        ``fibres(parameters) -> (k1, k2, kappa, angle)`` of a fibre-reinforced law: k1 in
        MPa, k2 and kappa dimensionless, angle in radians of the two in-plane families from
        their bisector e1 (``_fibre_law``); None for an isotropic law.
    """

    name: str
    keys: tuple[str, ...]
    family: Callable[[np.ndarray], tuple[float, float, float, float]]
    fit_start: tuple[float, ...]
    fibres: Callable[[np.ndarray], tuple[float, float, float, float]] | None = None


LAWS: dict[str, Law] = {}
"""Law name -> :class:`Law`, in the order of registration."""


def register_law(law: Law) -> Law:
    """Make ``law`` known by its name (a later registration of the same name replaces it)."""
    if len(law.fit_start) != len(law.keys):
        raise ValueError(f"law {law.name!r}: one fit_start value per key expected")
    LAWS[law.name] = law
    return law


def get_law(name: str) -> Law:
    """The registered law ``name``; an unknown name is an InputError."""
    try:
        return LAWS[name]
    except KeyError:
        raise InputError(f"unknown hyperelastic law {name!r}; expected one of "
                         f"{', '.join(LAWS)}") from None


def family_constants(name: str, parameters) -> tuple[float, float, float, float]:
    """(C10, C01, C20, C30), MPa, of law ``name`` with its parameter array."""
    return get_law(name).family(np.asarray(parameters, dtype=np.float64))


def fibre_constants(name: str, parameters) -> tuple[float, float, float, float] | None:
    """(k1 MPa, k2, kappa, angle rad) of a fibre-reinforced law ``name``; None without fibres."""
    law = get_law(name)
    if law.fibres is None:
        return None
    return tuple(float(x) for x in law.fibres(np.asarray(parameters, dtype=np.float64)))


register_law(Law("neo-hooke", ("c10",), lambda p: (p[0], 0.0, 0.0, 0.0), (1.0,)))
register_law(Law("mooney-rivlin", ("c10", "c01"), lambda p: (p[0], p[1], 0.0, 0.0), (0.5, 0.1)))
register_law(Law("yeoh", ("c10", "c20", "c30"), lambda p: (p[0], 0.0, p[1], p[2]),
                 (0.5, 0.1, 0.01)))
register_law(Law("holzapfel-gasser-ogden", ("c10", "c01", "k1", "k2", "kappa", "fibre_angle"),
                 lambda p: (p[0], p[1], 0.0, 0.0), (0.5, 0.0, 0.5, 0.0, 0.0, 0.0),
                 fibres=lambda p: (p[2], p[3], p[4], np.deg2rad(p[5]))))
