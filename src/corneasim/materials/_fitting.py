"""Least-squares fit of hyperelastic laws to stress-stretch data, constrained to be stable.

Data are nominal (engineering) stress against stretch from uniaxial and,
optionally, equibiaxial tests, evaluated in the incompressible limit
(``_homogeneous.py``). The fit minimises the sum of squared nominal-stress
residuals (MPa) in two stages:

1. bounded least squares (``scipy.optimize.least_squares``) inside a region that is
   Drucker-stable by construction: neo-Hooke C10 > 0; Mooney-Rivlin C10 > 0,
   C01 >= 0; Yeoh C10 > 0, C20, C30 >= 0 (the first constant of a registered law > 0,
   the others >= 0: each term's energy is then convex in the logarithmic strains);
2. for the laws with more than one constant, SLSQP from that optimum with the
   sign restrictions lifted (C10 > 0 kept) and the stability of the three tests
   on a grid over stretch 0.1-10 as inequality constraints.

The result of stage 2 is kept only if :func:`check_stability` confirms it is
stable and it lowers the residual; otherwise stage 1 is returned.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from corneasim.errors import InputError
from corneasim.materials._homogeneous import MODES, cauchy_stress, drucker_minimum_eigenvalue, nominal_stress
from corneasim.materials._laws import LAWS, get_law
from corneasim.materials._stability import StabilityReport, check_stability

FIT_MODELS = tuple(name for name, law in LAWS.items() if law.fibres is None)
"""The laws ``fit_hyperelastic`` fits: every registered isotropic law (``_laws``); a fibre law
needs data along several directions, which the fit does not take."""
_CONSTRAINT_GRID = np.concatenate([np.geomspace(0.1, 0.999, 40), np.geomspace(1.001, 10.0, 40)])


@dataclass(frozen=True)
class FitResult:
    """A fitted law.

    Attributes
    ----------
    model : str
        Law name.
    parameters : numpy.ndarray
        Parameter array without D1, MPa.
    rmse : float
        Root-mean-square nominal-stress residual over all data points, MPa.
    max_error : float
        Largest absolute residual, MPa.
    stability : StabilityReport
        Stability of the fitted law (stable by construction).
    """

    model: str
    parameters: np.ndarray
    rmse: float
    max_error: float
    stability: StabilityReport

    def constants(self) -> dict[str, float]:
        """The constants by their TOML key, MPa."""
        return dict(zip(get_law(self.model).keys, (float(x) for x in self.parameters)))


def _start_and_bounds(model: str, scale: float):
    start = get_law(model).fit_start
    lower = [1e-9 * scale] + [0.0] * (len(start) - 1)
    return [value * scale for value in start], lower, [np.inf] * len(start)


def fit_hyperelastic(
    model: str,
    uniaxial: tuple[np.ndarray, np.ndarray],
    equibiaxial: tuple[np.ndarray, np.ndarray] | None = None,
) -> FitResult:
    """Fit a stable incompressible law to nominal stress-stretch data.

    Parameters
    ----------
    model : str
        A registered law (``FIT_MODELS``): ``neo-hooke``, ``mooney-rivlin`` or ``yeoh``.
    uniaxial : (stretch, nominal_stress)
        Uniaxial data: stretch (dimensionless, > 0) and nominal stress (MPa).
    equibiaxial : (stretch, nominal_stress), optional
        Equibiaxial data, same units.

    Returns
    -------
    FitResult
    """
    from scipy.optimize import least_squares  # deferred: keeps ``import corneasim.materials`` light

    if model not in LAWS or LAWS[model].fibres is not None:
        fitted = ", ".join(name for name, law in LAWS.items() if law.fibres is None)
        raise InputError(f"--model: law {model!r} cannot be fitted; expected one of {fitted}")
    data = [("uniaxial", *map(np.asarray, uniaxial))]
    if equibiaxial is not None:
        data.append(("equibiaxial", *map(np.asarray, equibiaxial)))
    for test, stretch, _ in data:
        if np.any(stretch <= 0.0):
            raise InputError(f"{test} data: stretch must be > 0")
    n_points = sum(stretch.size for _, stretch, _ in data)

    def residuals(c):
        law = np.append(c, 1.0)
        return np.concatenate([nominal_stress(model, law, test, s) - y for test, s, y in data])

    def loss(c):
        return float(np.sum(residuals(c) ** 2))

    slope_data = [np.abs(y) / np.maximum(np.abs(s - 1.0), 1e-3) for _, s, y in data]
    scale = max(float(np.median(np.concatenate(slope_data))) / 6.0, 1e-6)
    start, lower, upper = _start_and_bounds(model, scale)
    stage1 = least_squares(residuals, start, bounds=(lower, upper), x_scale="jac").x
    best = stage1
    if len(start) > 1:
        best = _relax_signs(model, stage1, lower, loss)
    stability = check_stability(model, np.append(best, 1.0))
    r = residuals(best)
    return FitResult(model, best, float(np.sqrt(np.sum(r**2) / n_points)), float(np.max(np.abs(r))), stability)


def _relax_signs(model, stage1, lower, loss):
    """SLSQP without the sign restrictions, stability on a grid as constraints."""
    from scipy.optimize import minimize

    def margins(c):
        law = np.append(c, 1.0)
        values = []
        for test in MODES:
            values.append(drucker_minimum_eigenvalue(model, law, test, _CONSTRAINT_GRID))
            values.append(cauchy_stress(model, law, test, _CONSTRAINT_GRID) * np.sign(_CONSTRAINT_GRID - 1.0))
        return np.concatenate(values)

    bounds = [(lower[0], None)] + [(None, None)] * (len(stage1) - 1)
    try:
        result = minimize(loss, stage1, method="SLSQP", bounds=bounds,
                          constraints=[{"type": "ineq", "fun": margins}], options={"maxiter": 200})
    except (ValueError, FloatingPointError):
        return stage1
    if not result.success or loss(result.x) >= loss(stage1):
        return stage1
    if not check_stability(model, np.append(result.x, 1.0)).stable:
        return stage1
    return result.x
