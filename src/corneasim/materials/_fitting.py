"""Least-squares fit of hyperelastic laws to stress-stretch data, constrained to be stable.

Data are nominal (engineering) stress against stretch from uniaxial and,
optionally, equibiaxial tests, evaluated in the incompressible limit
(``_homogeneous.py``). The fit minimises the sum of squared nominal-stress
residuals (MPa) in two stages:

1. bounded least squares (``scipy.optimize.least_squares``) inside a region that is
   Drucker-stable by construction: neo-Hooke C10 > 0; Mooney-Rivlin C10 > 0,
   C01 >= 0; Yeoh C10 > 0, C20, C30 >= 0; Ogden mu_i >= 0, alpha_i > 0 (each term's
   energy is then convex in the logarithmic strains);
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
from corneasim.materials._stability import StabilityReport, check_stability

FIT_MODELS = ("neo-hooke", "mooney-rivlin", "yeoh", "ogden")
_CONSTRAINT_GRID = np.concatenate([np.geomspace(0.1, 0.999, 40), np.geomspace(1.001, 10.0, 40)])


@dataclass(frozen=True)
class FitResult:
    """A fitted law.

    Attributes
    ----------
    model : str
        Law name.
    parameters : numpy.ndarray
        Parameter array without D1 (MPa; Ogden: mu_i in MPa then alpha_i).
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

    def constants(self) -> dict[str, float | list[float]]:
        """The constants by their TOML key (MPa; alpha dimensionless)."""
        p = [float(x) for x in self.parameters]
        if self.model == "neo-hooke":
            return {"c10": p[0]}
        if self.model == "mooney-rivlin":
            return {"c10": p[0], "c01": p[1]}
        if self.model == "yeoh":
            return {"c10": p[0], "c20": p[1], "c30": p[2]}
        n = len(p) // 2
        return {"mu": p[:n], "alpha": p[n:]}


def _start_and_bounds(model: str, n_terms: int, scale: float):
    if model == "neo-hooke":
        return [scale], [1e-9 * scale], [np.inf]
    if model == "mooney-rivlin":
        return [0.5 * scale, 0.1 * scale], [1e-9 * scale, 0.0], [np.inf, np.inf]
    if model == "yeoh":
        return [0.5 * scale, 0.1 * scale, 0.01 * scale], [1e-9 * scale, 0.0, 0.0], [np.inf] * 3
    alphas = list(np.linspace(2.0, 2.0 + 4.0 * (n_terms - 1), n_terms))
    return ([scale / n_terms] * n_terms + alphas, [0.0] * n_terms + [0.1] * n_terms,
            [np.inf] * n_terms + [40.0] * n_terms)


def fit_hyperelastic(
    model: str,
    uniaxial: tuple[np.ndarray, np.ndarray],
    equibiaxial: tuple[np.ndarray, np.ndarray] | None = None,
    ogden_terms: int = 2,
) -> FitResult:
    """Fit a stable incompressible law to nominal stress-stretch data.

    Parameters
    ----------
    model : str
        ``neo-hooke``, ``mooney-rivlin``, ``yeoh`` or ``ogden``.
    uniaxial : (stretch, nominal_stress)
        Uniaxial data: stretch (dimensionless, > 0) and nominal stress (MPa).
    equibiaxial : (stretch, nominal_stress), optional
        Equibiaxial data, same units.
    ogden_terms : int
        Number of Ogden terms (1 to 3).

    Returns
    -------
    FitResult
    """
    from scipy.optimize import least_squares  # deferred: keeps ``import corneasim.materials`` light

    if model not in FIT_MODELS:
        raise InputError(f"--model: unknown law {model!r}; expected one of {', '.join(FIT_MODELS)}")
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
    start, lower, upper = _start_and_bounds(model, ogden_terms, scale)
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

    n_alpha = len(stage1) // 2 if model == "ogden" else 0

    def margins(c):
        law = np.append(c, 1.0)
        values = []
        for test in MODES:
            values.append(drucker_minimum_eigenvalue(model, law, test, _CONSTRAINT_GRID))
            values.append(cauchy_stress(model, law, test, _CONSTRAINT_GRID) * np.sign(_CONSTRAINT_GRID - 1.0))
        return np.concatenate(values)

    bounds = [(lower[0], None)] + [(None, None)] * (len(stage1) - 1)
    if model == "ogden":
        bounds = [(None, None)] * (len(stage1) - n_alpha) + [(-40.0, 40.0)] * n_alpha
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
