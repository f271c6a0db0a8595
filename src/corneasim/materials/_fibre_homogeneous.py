"""Homogeneous tests of a fibre-reinforced law: coaxial derivatives and loading directions.

The two fibre families of ``_fibre_law`` lie in the lamellar plane (e1, e2) at +-angle from
their bisector e1, so the law is orthotropic in the frame (e1, e2, e3). Coaxial stretches
:math:`F = \\mathrm{diag}(e^{e_1}, e^{e_2}, e^{-e_1 - e_2})` then give both families the same

.. math::

    \\bar I_4 = \\cos^2\\!\\theta\\, u_1 + \\sin^2\\!\\theta\\, u_2, \\qquad u_a = e^{2 e_a},

and :func:`coaxial_fibre_derivatives` adds their share
:math:`2\\Psi'(E)\\,\\partial E` to the gradient and
:math:`2[\\Psi''(E)\\,\\partial E\\,\\partial E^T + \\Psi'(E)\\,\\partial^2 E]` to the Hessian
of ``_homogeneous`` (``E = \\kappa(\\bar I_1 - 3) + (1 - 3\\kappa)(\\bar I_4 - 1)``).

:func:`directional_cauchy_stress` loads the material along one of ``DIRECTIONS``, given as
a test frame (n, m, t) of unit vectors in the material frame:

============  ====================================================================
``bisector``  n = e1, the bisector of the families (in the lamellar plane; default)
``along``     n = a01, the first family's direction
``across``    n in the lamellar plane perpendicular to a01
``through``   n = e3, the thickness
============  ====================================================================

In the test frame the uniaxial test holds x1 at stretch lambda with
:math:`F = [[\\lambda, F_{12}, 0], [0, F_{22}, 0], [0, 0, 1/(\\lambda F_{22})]]` (the material
line along n stays along n; the plane (n, m) is a mirror plane of the law, so no
out-of-plane shear arises) and solves F22 and F12 so that :math:`\\sigma_{22} = \\sigma_{33}`
and :math:`\\sigma_{12} = 0`; equibiaxial and planar prescribe diag(lambda, lambda,
lambda^-2) and diag(lambda, 1, 1/lambda). The result is the incompressible
:math:`\\sigma_{11} - \\sigma_{33}` of the compressible law at J = 1.
"""

from __future__ import annotations

import numpy as np

from corneasim.errors import InputError
from corneasim.materials._hyperelastic import cauchy_stress
from corneasim.materials._laws import fibre_constants

DIRECTIONS = ("bisector", "along", "across", "through")
MAX_LOG_STEP = 0.02
"""Largest step in log stretch of the continuation that solves the uniaxial test."""


def coaxial_fibre_derivatives(fibres, u1, u2, u3, dI1, d2I1):
    """Fibre share (both families) of the gradient (2, n) and Hessian (2, 2, n) in (e1, e2), MPa.

    ``fibres`` = (k1 MPa, k2, kappa, angle rad); u_a = exp(2 e_a); dI1, d2I1 the derivatives
    of I1 in (e1, e2) that ``_homogeneous`` computed.
    """
    k1, k2, kappa, angle = fibres
    c2, s2 = np.cos(angle) ** 2, np.sin(angle) ** 2
    E = kappa * (u1 + u2 + u3 - 3.0) + (1.0 - 3.0 * kappa) * (c2 * u1 + s2 * u2 - 1.0)
    active = E > 0.0
    x = np.exp(k2 * np.where(active, E * E, 0.0))
    d1 = np.where(active, k1 * E * x, 0.0)
    d2 = np.where(active, k1 * (1.0 + 2.0 * k2 * E * E) * x, 0.0)
    zero = np.zeros_like(u1)
    b = 1.0 - 3.0 * kappa
    dE = kappa * dI1 + b * np.array([2.0 * c2 * u1, 2.0 * s2 * u2])
    d2E = kappa * d2I1 + b * 4.0 * np.array([[c2 * u1, zero], [zero, s2 * u2]])
    gradient = 2.0 * d1 * dE
    hessian = 2.0 * (d2 * dE[:, None] * dE[None, :] + d1 * d2E)
    return gradient, hessian


def loading_frame(direction: str, angle: float) -> np.ndarray:
    """Rows (n, m, t): the test frame of ``direction`` in material coordinates (angle in rad)."""
    c, s = np.cos(angle), np.sin(angle)
    frames = {
        "bisector": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        "along": [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]],
        "across": [[-s, c, 0.0], [-c, -s, 0.0], [0.0, 0.0, 1.0]],
        "through": [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    }
    if direction not in frames:
        raise ValueError(f"unknown direction {direction!r}; expected one of {', '.join(DIRECTIONS)}")
    return np.array(frames[direction])


class _Overflow(ArithmeticError):
    """The stress is not finite: the fibre energy left the range of float64."""


def _test_stress(model, parameters, R, F_test):
    if not np.all(np.isfinite(F_test)):
        raise _Overflow
    with np.errstate(over="ignore", invalid="ignore"):
        sigma = R @ cauchy_stress(model, parameters, R.T @ F_test @ R) @ R.T
    if not np.all(np.isfinite(sigma)):
        raise _Overflow
    return sigma


def _uniaxial_F(stretch, x):
    return np.array([[stretch, x[1], 0.0], [0.0, np.exp(x[0]), 0.0], [0.0, 0.0, np.exp(-x[0]) / stretch]])


def directional_cauchy_stress(model: str, parameters, mode: str, stretch, direction: str = "bisector"):
    """Incompressible Cauchy stress sigma_11 (MPa) of a test along ``direction`` at ``stretch``.

    Parameters
    ----------
    model : str
        A registered law (fibre-reinforced or not).
    parameters : array_like
        Its parameter array (``_hyperelastic.py`` layout; D1 is irrelevant at J = 1).
    mode : str
        ``uniaxial``, ``equibiaxial`` or ``planar``.
    stretch : array_like
        Stretches lambda > 0 (dimensionless).
    direction : str
        One of ``DIRECTIONS``.
    """
    fibres = fibre_constants(model, parameters)
    R = loading_frame(direction, 0.0 if fibres is None else fibres[3])
    stretch = np.atleast_1d(np.asarray(stretch, dtype=np.float64))
    out = np.empty_like(stretch)
    try:
        with np.errstate(over="ignore", invalid="ignore"):
            _fill(model, parameters, mode, stretch, R, out)
    except _Overflow as overflow:
        raise InputError(f"{mode} test ({direction}) at stretch {overflow.args[0]:g}: the fibre stress leaves "
                         "the range of float64 (exp(k2 E^2) overflows); use stretches closer to 1") from None
    return out


def _fill(model, parameters, mode, stretch, R, out):
    """Write sigma_11 - sigma_33 of each stretch into ``out`` (raises _Overflow)."""
    if mode in ("equibiaxial", "planar"):
        for k, lam in enumerate(stretch):
            lateral = lam if mode == "equibiaxial" else 1.0
            try:
                sigma = _test_stress(model, parameters, R, np.diag([lam, lateral, 1.0 / (lam * lateral)]))
            except _Overflow:
                raise _Overflow(lam) from None
            out[k] = sigma[0, 0] - sigma[2, 2]
        return
    if mode != "uniaxial":
        raise ValueError(f"unknown test {mode!r}; expected uniaxial, equibiaxial or planar")

    def residual(x, lam):
        sigma = _test_stress(model, parameters, R, _uniaxial_F(lam, x))
        return np.array([sigma[1, 1] - sigma[2, 2], sigma[0, 1]])

    for side in (stretch >= 1.0, stretch < 1.0):
        order = np.flatnonzero(side)[np.argsort(np.abs(np.log(stretch[side])))]
        log_now, x = 0.0, np.zeros(2)
        for k in order:
            target = np.log(stretch[k])
            steps = max(1, int(np.ceil(abs(target - log_now) / MAX_LOG_STEP)))
            try:
                for log_stretch in np.linspace(log_now, target, steps + 1)[1:]:
                    x = _newton(residual, x, np.exp(log_stretch))
                sigma = _test_stress(model, parameters, R, _uniaxial_F(stretch[k], x))
            except (_Overflow, np.linalg.LinAlgError):
                raise _Overflow(stretch[k]) from None
            log_now = target
            out[k] = sigma[0, 0] - sigma[2, 2]


def _newton(residual, x, lam, iterations=50, h=1e-7):
    """Damped Newton on the two lateral unknowns, central-difference Jacobian."""
    r = residual(x, lam)
    for _ in range(iterations):
        jacobian = np.empty((2, 2))
        for j in range(2):
            dx = np.zeros(2)
            dx[j] = h
            jacobian[:, j] = (residual(x + dx, lam) - residual(x - dx, lam)) / (2.0 * h)
        step = np.linalg.solve(jacobian, -r)
        size = 1.0
        while True:
            trial = x + size * step
            try:
                r_trial = residual(trial, lam)
            except _Overflow:  # a step too long for float64: shorten it
                r_trial = np.full(2, np.inf)
            if np.linalg.norm(r_trial) < np.linalg.norm(r) or np.linalg.norm(r_trial) == 0.0 or size <= 1e-4:
                break
            size *= 0.5
        if not np.all(np.isfinite(r_trial)):
            raise _Overflow
        x, r = trial, r_trial
        if np.max(np.abs(size * step)) < 1e-15:
            break
    return x
