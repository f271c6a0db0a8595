"""Incompressible homogeneous tests: uniaxial, equibiaxial and planar (pure shear).

For an incompressible isotropic material the energy is a function of two
logarithmic principal strains, :math:`\\hat W(e_1, e_2)` with :math:`e_3 = -e_1 - e_2`.
Its gradient gives the Kirchhoff (= Cauchy, J = 1) stress differences
:math:`\\tau_a - \\tau_3 = \\partial\\hat W/\\partial e_a`, and its Hessian
:math:`D_{ab} = \\partial^2\\hat W/\\partial e_a\\partial e_b` is the incompressible
tangent of :math:`d\\tau : d\\varepsilon`; Drucker stability is D positive definite
(ABAQUS Theory Manual, "Hyperelastic material behavior", stability).

The tests load direction 1 with stretch lambda, direction 3 is traction-free:

===========  ==========================  =====================================
test         (lambda_1, lambda_2)        Cauchy stress sigma_11 = dW/de_1
===========  ==========================  =====================================
uniaxial     (lambda, lambda^-1/2)       direction 2 traction-free too
equibiaxial  (lambda, lambda)            sigma_22 = sigma_11
planar       (lambda, 1)                 direction 2 held at stretch 1
===========  ==========================  =====================================

Nominal (first Piola-Kirchhoff) stress is sigma_11 / lambda. A fibre-reinforced law is
tested in its material frame: direction 1 is the bisector of its two fibre families,
direction 2 the other in-plane axis, direction 3 the thickness (``_fibre_homogeneous``); the
material is orthotropic in that frame, so the coaxial stretches keep the stress coaxial, and
the uniaxial test's lateral strain e2 is solved so that sigma_22 = sigma_33 (Newton on
dW/de2 = 0) instead of the isotropic e2 = -e1/2. Laws are given as
``(model, parameters)`` with the parameter arrays of ``_hyperelastic.py`` (D1 is
ignored here: incompressible limit); the energy derivatives are those of ``_law`` for the
family constants of the registered law (``_laws``).
"""

from __future__ import annotations

import numpy as np

from corneasim.materials._fibre_homogeneous import coaxial_fibre_derivatives
from corneasim.materials._law import isochoric_derivatives
from corneasim.materials._laws import family_constants, fibre_constants

MODES = ("uniaxial", "equibiaxial", "planar")


def log_strains(mode: str, stretch) -> tuple[np.ndarray, np.ndarray]:
    """Logarithmic principal strains (e1, e2) of an incompressible test at ``stretch``."""
    e = np.log(np.asarray(stretch, dtype=np.float64))
    if mode == "uniaxial":
        return e, -0.5 * e
    if mode == "equibiaxial":
        return e, e.copy()
    if mode == "planar":
        return e, np.zeros_like(e)
    raise ValueError(f"unknown test {mode!r}; expected one of {', '.join(MODES)}")


def energy_derivatives(model: str, parameters, e1, e2) -> tuple[np.ndarray, np.ndarray]:
    """Gradient (2, n) and Hessian (2, 2, n) of the incompressible energy in (e1, e2), MPa."""
    c10, c01, c20, c30 = family_constants(model, parameters)
    e1 = np.atleast_1d(np.asarray(e1, dtype=np.float64))
    e2 = np.atleast_1d(np.asarray(e2, dtype=np.float64))
    u1, u2, u3 = np.exp(2.0 * e1), np.exp(2.0 * e2), np.exp(-2.0 * (e1 + e2))
    v1, v2, v3 = 1.0 / u1, 1.0 / u2, 1.0 / u3
    W1, W11 = isochoric_derivatives(u1 + u2 + u3, float(c10), float(c20), float(c30))
    dI1 = np.array([2.0 * (u1 - u3), 2.0 * (u2 - u3)])
    dI2 = np.array([2.0 * (v3 - v1), 2.0 * (v3 - v2)])
    d2I1 = 4.0 * np.array([[u1 + u3, u3], [u3, u2 + u3]])
    d2I2 = 4.0 * np.array([[v1 + v3, v3], [v3, v2 + v3]])
    gradient = W1 * dI1 + c01 * dI2
    hessian = W11 * dI1[:, None] * dI1[None, :] + W1 * d2I1 + c01 * d2I2
    fibres = fibre_constants(model, parameters)
    if fibres is not None:
        fibre_gradient, fibre_hessian = coaxial_fibre_derivatives(fibres, u1, u2, u3, dI1, d2I1)
        gradient, hessian = gradient + fibre_gradient, hessian + fibre_hessian
    return gradient, hessian


def loaded_strains(model: str, parameters, mode: str, stretch) -> tuple[np.ndarray, np.ndarray]:
    """(e1, e2) of a test; for a fibre law in the uniaxial test e2 makes direction 2 traction-free."""
    e1, e2 = log_strains(mode, stretch)
    if mode != "uniaxial" or fibre_constants(model, parameters) is None:
        return e1, e2
    e1, e2 = np.atleast_1d(e1), np.atleast_1d(e2)
    for _ in range(100):
        gradient, hessian = energy_derivatives(model, parameters, e1, e2)
        step = gradient[1] / hessian[1, 1]
        e2 = e2 - step
        if np.all(np.abs(step) <= 1e-15 * (1.0 + np.abs(e1))):
            break
    return e1, e2


def cauchy_stress(model: str, parameters, mode: str, stretch) -> np.ndarray:
    """Incompressible Cauchy stress sigma_11 (MPa) of a homogeneous test at ``stretch``."""
    gradient, _ = energy_derivatives(model, parameters, *loaded_strains(model, parameters, mode, stretch))
    return gradient[0]


def nominal_stress(model: str, parameters, mode: str, stretch) -> np.ndarray:
    """Incompressible nominal stress P_11 = sigma_11 / lambda (MPa, force per reference area)."""
    return cauchy_stress(model, parameters, mode, stretch) / np.asarray(stretch, dtype=np.float64)


def drucker_minimum_eigenvalue(model: str, parameters, mode: str, stretch) -> np.ndarray:
    """Smallest eigenvalue (MPa) of the incompressible tangent D; Drucker-stable where > 0."""
    _, D = energy_derivatives(model, parameters, *loaded_strains(model, parameters, mode, stretch))
    mean = 0.5 * (D[0, 0] + D[1, 1])
    return mean - np.sqrt((0.5 * (D[0, 0] - D[1, 1])) ** 2 + D[0, 1] ** 2)
