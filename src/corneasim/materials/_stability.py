"""Drucker stability check of a hyperelastic law over the standard homogeneous tests.

Like the material evaluation of commercial codes (ABAQUS, "Hyperelastic behavior
of rubberlike materials", stability), the incompressible law is checked in
uniaxial, equibiaxial and planar deformation, in tension (stretch 1..10) and in
compression (stretch 0.1..1). Two conditions are reported per test:

* **Drucker**: the incompressible tangent D (Hessian of the energy in the
  logarithmic principal strains, ``_homogeneous.py``) must be positive definite,
  i.e. :math:`d\\tau : d\\varepsilon > 0` for every admissible strain increment;
* **stress sign**: the test's own Cauchy stress must have the sign of the
  deformation (tensile in tension, compressive in compression).

Range boundaries are located to 1e-10 in stretch by root finding between the
points of a fine logarithmic grid. A fibre-reinforced law is checked in its material frame
(loading along the bisector of its fibre families, in the lamellar plane: ``_homogeneous``)
over stretch 0.5..2 by default: its exponential fibre energy leaves the range of float64
long before stretch 10 (k2 E^2 > 709), and tissue tears well below stretch 2; a value that
overflows is not reported as unstable. Its tangent is dominated by the rank-one fibre term
2 Psi''(E) dE dE^T, whose size makes the round-off of the smallest
eigenvalue far larger than the matrix's stiffness, so its Drucker condition is judged
relative to the tangent's size: unstable where
lambda_min(D) < -1e-12 (|D_11| + |D_22|).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from corneasim.materials._homogeneous import (
    MODES, cauchy_stress, drucker_minimum_eigenvalue, energy_derivatives, loaded_strains)
from corneasim.materials._laws import fibre_constants

STRETCH_MIN = 0.1
STRETCH_MAX = 10.0
FIBRE_STRETCH_MIN = 0.5
FIBRE_STRETCH_MAX = 2.0
"""Default stretch range of the check of a fibre-reinforced law (dimensionless)."""
GRID_POINTS = 2000
"""Grid points per side (compression, tension) and test."""


@dataclass(frozen=True)
class TestStability:
    """Unstable stretch ranges of one homogeneous test.

    Attributes
    ----------
    test : str
        ``uniaxial``, ``equibiaxial`` or ``planar``.
    drucker : list of (float, float)
        Stretch intervals where the tangent is not positive definite.
    wrong_sign : list of (float, float)
        Stretch intervals where the test's stress has the wrong sign.
    """

    test: str
    drucker: list[tuple[float, float]] = field(default_factory=list)
    wrong_sign: list[tuple[float, float]] = field(default_factory=list)

    @property
    def stable(self) -> bool:
        """No unstable range."""
        return not self.drucker and not self.wrong_sign


@dataclass(frozen=True)
class StabilityReport:
    """Result of :func:`check_stability` (stretch limits dimensionless)."""

    tests: tuple[TestStability, ...]
    stretch_min: float
    stretch_max: float

    @property
    def stable(self) -> bool:
        """True when every test is stable over the whole stretch range."""
        return all(test.stable for test in self.tests)

    def unstable_ranges_text(self) -> str:
        """One line listing the unstable ranges, e.g. for a warning."""
        parts = []
        for test in self.tests:
            for side, keep in (("tension", lambda r: r[0] >= 1.0), ("compression", lambda r: r[1] <= 1.0)):
                found = [f"{label} at stretch {_format_ranges(selected)}"
                         for label, ranges in (("stress of wrong sign", test.wrong_sign), ("Drucker", test.drucker))
                         if (selected := [r for r in ranges if keep(r)])]
                if found:
                    parts.append(f"{test.test} {side}: " + ", ".join(found))
        return "; ".join(parts) if parts else "none"

    def format(self, name: str = "material") -> str:
        """Readable multi-line report."""
        lines = [
            f"Stability of {name} (incompressible limit, stretch {self.stretch_min:g} to "
            f"{self.stretch_max:g}): {'STABLE' if self.stable else 'UNSTABLE'}"
        ]
        for test in self.tests:
            lines.append(f"  {test.test:<12} Drucker: {_describe(test.drucker)}")
            lines.append(f"  {'':<12} stress sign: {_describe(test.wrong_sign)}")
        return "\n".join(lines)


def _format_ranges(ranges) -> str:
    merged: list[list[float]] = []
    for low, high in ranges:
        if merged and merged[-1][1] == low:
            merged[-1][1] = high
        else:
            merged.append([low, high])
    return ", ".join(f"{low:.4g}-{high:.4g}" for low, high in merged)


def _describe(ranges) -> str:
    if not ranges:
        return "stable"
    sides = []
    for side, keep in (("compression", lambda r: r[1] <= 1.0), ("tension", lambda r: r[0] >= 1.0)):
        selected = [r for r in ranges if keep(r)]
        if selected:
            sides.append(f"{side} unstable at stretch {_format_ranges(selected)}")
    return "; ".join(sides)


def _unstable_runs(function, low: float, high: float, tolerance: float) -> list[tuple[float, float]]:
    """Intervals of [low, high] where ``function < -tolerance``, ends refined by bisection."""
    grid = np.geomspace(low, high, GRID_POINTS)
    bad = function(grid) < -tolerance
    runs = []
    start = None
    for i, flag in enumerate(bad):
        if flag and start is None:
            start = grid[0] if i == 0 else _root(function, grid[i - 1], grid[i], tolerance)
        if not flag and start is not None:
            runs.append((start, _root(function, grid[i - 1], grid[i], tolerance)))
            start = None
    if start is not None:
        runs.append((start, grid[-1]))
    return runs


def _root(function, a: float, b: float, tolerance: float) -> float:
    from scipy.optimize import brentq  # deferred: keeps ``import corneasim.materials`` light

    shifted = lambda x: float(function(np.array([x]))[0]) + tolerance  # noqa: E731
    if not shifted(a) * shifted(b) <= 0.0:
        return 0.5 * (a + b)
    return brentq(shifted, a, b, xtol=1e-12)


def check_stability(
    model: str, parameters, stretch_min: float | None = None, stretch_max: float | None = None
) -> StabilityReport:
    """Drucker and stress-sign stability of a law in the three homogeneous tests.

    Parameters
    ----------
    model : str
        A registered law (``_laws``): ``neo-hooke``, ``mooney-rivlin`` or ``yeoh``.
    parameters : array_like
        Parameter array of the law (``_hyperelastic.py`` layout; MPa, D1 ignored).
    stretch_min, stretch_max : float, optional
        Stretch range checked (dimensionless), ``stretch_min < 1 < stretch_max``; default
        0.1..10, for a fibre-reinforced law 0.5..2.

    Returns
    -------
    StabilityReport
        Unstable ranges per test; interval ends at 1 are reported as exactly 1.
    """
    fibres = fibre_constants(model, parameters) is not None
    if stretch_min is None:
        stretch_min = FIBRE_STRETCH_MIN if fibres else STRETCH_MIN
    if stretch_max is None:
        stretch_max = FIBRE_STRETCH_MAX if fibres else STRETCH_MAX
    scale = max(float(np.max(np.abs(np.asarray(parameters, dtype=float)[:-1]))), 1e-30)
    tolerance = 1e-12 * scale
    sides = ((stretch_min, 1.0 - 1e-9), (1.0 + 1e-9, stretch_max))
    tests = []
    for test in MODES:
        drucker = lambda s, t=test: drucker_minimum_eigenvalue(model, parameters, t, s)  # noqa: E731
        if fibres:
            drucker = lambda s, t=test: _relative_drucker(model, parameters, t, s) * scale  # noqa: E731
        signed = lambda s, t=test: cauchy_stress(model, parameters, t, s) * np.sign(s - 1.0)  # noqa: E731
        ranges = {}
        for key, function in (("drucker", drucker), ("wrong_sign", signed)):
            runs = []
            for low, high in sides:
                with np.errstate(over="ignore", invalid="ignore"):
                    runs += _unstable_runs(function, low, high, tolerance)
            ranges[key] = [(_snap(a), _snap(b)) for a, b in runs]
        tests.append(TestStability(test, **ranges))
    return StabilityReport(tuple(tests), stretch_min, stretch_max)


def _relative_drucker(model: str, parameters, test: str, stretch) -> np.ndarray:
    """Smallest eigenvalue of the tangent divided by |D11| + |D22| (dimensionless)."""
    _, D = energy_derivatives(model, parameters, *loaded_strains(model, parameters, test, stretch))
    D = D / (np.abs(D[0, 0]) + np.abs(D[1, 1]))
    mean = 0.5 * (D[0, 0] + D[1, 1])
    return mean - np.sqrt((0.5 * (D[0, 0] - D[1, 1])) ** 2 + D[0, 1] ** 2)


def _snap(stretch: float) -> float:
    return 1.0 if abs(stretch - 1.0) < 1e-8 else float(stretch)
