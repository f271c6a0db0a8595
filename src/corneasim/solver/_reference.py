"""The stress-free reference of a body measured under load: the backward-displacement fixed point.

A mesh made from a loaded body (an eye at its intraocular pressure) is that body's current
geometry x̂, not its stress-free one. Taken as stress-free it deforms again under the load,
and a law whose fibres carry nothing at zero strain (``holzapfel-gasser-ogden``) bulges until
its fibres are stretched. The stress-free reference X is the geometry that the load takes to
x̂: φ(X) = x̂, with φ(X) = X + u(X) the loaded geometry of a body whose reference is X.

Backward displacement (Bols et al. 2013) finds it by the fixed point

.. math::  X^{k+1} = X^k - (\\varphi(X^k) - \\hat{x}), \\qquad X^0 = \\hat{x},

each φ(X^k) one solve of the loaded body built on X^k; it stops when the largest nodal
distance max_n |φ(X^k) - x̂| is within a tolerance, and X^k is the reference. The update is
x̂ - u(X^k): the displacement under the load, taken back from the measured geometry. It
needs no tangent stiffness, only the forward solve, and converges when the displacement
depends weakly enough on the reference (``docs/solver.md``, "Prestressed reference").

References
----------
Bols, J., Degroote, J., Trachet, B., Verhegghe, B., Segers, P., Vierendeels, J. (2013). Inverse
modelling of image-based patient-specific blood vessels: zero-pressure geometry and in vivo stress
incorporation. ESAIM: M2AN 47, 1059-1075, doi:10.1051/m2an/2012057 (the backward displacement
method, fixed-point form).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from corneasim.solver._checks import SimulationError


@dataclass
class StressFreeReference:
    """The outcome of :func:`backward_displacement`.

    Attributes
    ----------
    points : ndarray (n_nodes, dim), mm
        The last reference X^k whose loaded geometry was solved (the result when converged).
    errors : list of float
        max_n |φ(X^k) - x̂| (mm) of each solved X^k, k = 0, 1, ...
    converged : bool
        The last error is within the tolerance.
    """

    points: np.ndarray
    errors: list[float] = field(default_factory=list)
    converged: bool = False


def backward_displacement(measured: np.ndarray, solve: Callable[[np.ndarray], np.ndarray], tolerance: float,
                          max_iterations: int, start: StressFreeReference | None = None,
                          on_iteration: Callable[[StressFreeReference], None] | None = None
                          ) -> StressFreeReference:
    """Find the reference X whose loaded geometry is ``measured``: X <- X - (solve(X) - measured).

    Parameters
    ----------
    measured : ndarray (n_nodes, dim), mm
        The geometry under the load (x̂).
    solve : callable
        ``solve(X)`` -> the loaded geometry φ(X) (n_nodes, dim), mm, of the body built on X.
    tolerance : float
        Largest nodal distance |φ(X) - x̂| accepted, mm.
    max_iterations : int
        Most solves φ(X^k) to take (the first, of X^0 = x̂, included).
    start : StressFreeReference, optional
        An unfinished iteration to continue (its ``points`` are the next X to solve, its
        ``errors`` those already taken).
    on_iteration : callable, optional
        Called with the state of the iteration after each solve (to save it).

    Returns
    -------
    StressFreeReference
        Converged: ``points`` is X with max |φ(X) - x̂| <= ``tolerance``.

    Raises
    ------
    SimulationError
        When ``max_iterations`` solves leave the error above ``tolerance`` (one line with the
        errors of the first and last solves).
    """
    measured = np.asarray(measured, dtype=float)
    current = start if start is not None else StressFreeReference(measured.copy())
    while not current.converged and len(current.errors) < max_iterations:
        loaded = solve(current.points)
        mismatch = loaded - measured  # (n_nodes, dim) mm
        error = float(np.sqrt((mismatch ** 2).sum(axis=1)).max())
        errors = [*current.errors, error]
        if error <= tolerance:
            current = StressFreeReference(current.points, errors, True)
        else:
            current = StressFreeReference(current.points - mismatch, errors, False)
        if on_iteration is not None:
            on_iteration(current)
    if not current.converged:
        errors = current.errors
        raise SimulationError(f"stress-free reference: not converged in {len(errors)} iterations (largest nodal "
                              f"error {errors[0]:.3g} mm at the first, {errors[-1]:.3g} mm at the last; tolerance "
                              f"{tolerance:.3g} mm)", 0.0)
    return current
