"""N-term Gaussian-sum curve model and its least-squares fit.

Both papers summarise a simulated force curve by a sum of Gaussians (the
``gaussN`` model of curve-fitting toolboxes): the needle insertion force by three
terms (needle paper, eq. 16) and the trephine's linear cutting force by two
(trephination paper, eq. 14). This module evaluates such a sum and fits one to
sampled data, so simulated curves can be summarised the same way.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from corneasim.errors import InputError


def gaussian_sum(x, a, b, c) -> np.ndarray:
    r"""Evaluate :math:`f(x) = \sum_{i=1}^{N} a_i \exp(-((x - b_i)/c_i)^2)`.

    Parameters
    ----------
    x : array_like
        Abscissae, any shape (unit of ``b`` and ``c``: mm for depth, s for time).
    a, b, c : array_like, shape (N,)
        Amplitudes (unit of ``f``, e.g. N), centres and widths (unit of ``x``; ``c > 0``).

    Returns
    -------
    numpy.ndarray
        ``f(x)``, same shape as ``x``.

    Notes
    -----
    Needle paper eq. 16 (N = 3, x = depth in mm, F in N); trephination paper
    eq. 14 (N = 2, x = time in s, g in N). The width ``c`` is :math:`\sqrt{2}`
    times the standard deviation of a normal density.

    Examples
    --------
    >>> float(gaussian_sum(0.61, [0.46], [0.61], [0.15]))
    0.46
    """
    x = np.asarray(x, dtype=np.float64)
    a, b, c = (np.asarray(v, dtype=np.float64).reshape(-1) for v in (a, b, c))
    z = (x[..., None] - b) / c  # (..., N)
    return np.sum(a * np.exp(-(z * z)), axis=-1)


@dataclass(frozen=True)
class GaussianFit:
    """A fitted Gaussian sum; terms sorted by centre ``b``.

    Attributes
    ----------
    a, b, c : numpy.ndarray, shape (N,)
        Amplitudes (unit of y), centres and widths (unit of x).
    rmse : float
        Root-mean-square residual over the fitted samples (unit of y).
    """

    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    rmse: float

    def __call__(self, x) -> np.ndarray:
        """Evaluate the fitted sum at ``x`` (see :func:`gaussian_sum`)."""
        return gaussian_sum(x, self.a, self.b, self.c)

    @property
    def n_terms(self) -> int:
        """Number of Gaussian terms."""
        return len(self.a)


def fit_gaussian_sum(
    x, y, n_terms: int, *, nonnegative: bool = False, initial=None, n_starts: int = 8, seed: int = 0,
    min_width: float | None = None,
) -> GaussianFit:
    r"""Least-squares fit of an ``n_terms`` Gaussian sum to samples ``(x, y)``.

    Parameters
    ----------
    x, y : array_like, shape (n,)
        Samples (any order); ``n >= 3 * n_terms`` and finite.
    n_terms : int
        Number of Gaussian terms N (>= 1).
    nonnegative : bool, optional
        Constrain the amplitudes to :math:`a_i \ge 0` (a sum of bumps, as a
        force curve usually is); default False (free amplitudes).
    initial : tuple of three array_like of shape (N,), optional
        Starting ``(a, b, c)``; only its centres and widths are used (the
        amplitudes are solved for), tried before the automatic starts.
    n_starts : int, optional
        Number of automatic starts (default 8, at least 2). The search stops
        early once a start fits to rounding level (RMSE below 1e-12 max|y|).
    seed : int, optional
        Seed of the random starts (the fit is deterministic for a given seed).
    min_width : float, optional
        Smallest width :math:`c_i` allowed (unit of x; at most the x-range); default: the
        smallest sample spacing. A curve judged at a table's abscissae is best fitted with
        widths no smaller than the table's spacing: a narrower term only lands on or misses
        a table point.

    Returns
    -------
    GaussianFit
        The lowest-cost solution over all starts, terms sorted by centre.

    Raises
    ------
    corneasim.errors.InputError
        ``x`` and ``y`` of different lengths, non-finite values, too few
        samples, ``x`` without spread, or ``n_terms < 1``.

    Notes
    -----
    Minimises :math:`\sum_k (f(x_k) - y_k)^2`. The amplitudes enter linearly,
    so they are eliminated (variable projection, Golub & Pereyra 1973,
    doi:10.1137/0710036): for given centres and widths, :math:`a` is the
    linear least-squares solution of :math:`\Phi a = y` with
    :math:`\Phi_{ki} = \exp(-((x_k - b_i)/c_i)^2)`, and
    ``scipy.optimize.least_squares`` (trust-region reflective, with Kaufman's
    Jacobian: ``_projected_jacobian``) moves only :math:`(b, c)` within the bounds
    :math:`b_i \in [x_{min} - L, x_{max} + L]`, :math:`c_i \in [h, 10 L]`
    (L the x-range, h the smallest sample spacing: a narrower term is not
    resolved by the samples; or ``min_width`` if larger). Centres may lie
    outside the data, as in eq. 16 (b = 0.86 mm on [0, 0.7] mm). The amplitudes
    are bounded by :math:`|a_i| \le 10 \max|y|` (and :math:`a_i \ge 0` if
    ``nonnegative``), solved by bounded-variable least squares when the plain
    solution violates a bound: without this bound a narrow term centred just
    outside the data can take an astronomically large amplitude to bend the
    last samples, a degenerate fit.

    A Gaussian sum has many local minima, so several starts are tried:

    1. greedy peeling: a term at the largest remaining residual, width from the
       half-maximum crossing around it, subtracted, repeated N times;
    2. centres spread evenly over the data range, widths L/N;
    3. random centres in the bounds and widths in [L/(4N), 2L/N] (``seed``).

    References
    ----------
    Needle paper eq. 16; trephination paper eq. 14.
    """
    x, y = _validated_samples(x, y, n_terms)
    order = np.argsort(x)
    x, y = x[order], y[order]
    span = float(x[-1] - x[0])
    spacing = float(np.min(np.diff(np.unique(x))))
    narrowest = spacing if min_width is None else min(max(spacing, float(min_width)), span)
    lower = np.concatenate([np.full(n_terms, x[0] - span), np.full(n_terms, narrowest)])
    upper = np.concatenate([np.full(n_terms, x[-1] + span), np.full(n_terms, 10.0 * span)])

    starts = []
    if initial is not None:
        starts.append(np.concatenate([np.asarray(v, dtype=np.float64).reshape(n_terms) for v in initial[1:]]))
    starts += _automatic_starts(x, y, n_terms, max(2, n_starts), lower, upper, seed)

    y_scale = max(float(np.max(np.abs(y))), np.finfo(np.float64).tiny)
    amplitude_bounds = (0.0 if nonnegative else -10.0 * y_scale, 10.0 * y_scale)
    exact_cost = 0.5 * y.size * (1e-12 * y_scale) ** 2
    from scipy.optimize import least_squares  # deferred: a 0.1-0.3 s import that only the summary needs

    best = None
    for start in starts:
        result = least_squares(
            _projected_residual, np.clip(start, lower, upper), jac=_projected_jacobian,
            args=(x, y, n_terms, amplitude_bounds),
            bounds=(lower, upper), method="trf", x_scale="jac",
            xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=100 * n_terms,
        )
        if best is None or result.cost < best.cost:
            best = result
        if best.cost <= exact_cost:
            break
    b, c = best.x[:n_terms], best.x[n_terms:]
    a = _amplitudes(_basis(x, b, c), y, amplitude_bounds)
    keep = np.argsort(b)
    rmse = float(np.sqrt(np.mean((gaussian_sum(x, a, b, c) - y) ** 2)))
    return GaussianFit(a=a[keep], b=b[keep], c=c[keep], rmse=rmse)


def _basis(x, b, c):
    """Gaussian basis matrix, shape (n_samples, n_terms)."""
    z = (x[:, None] - b) / c
    return np.exp(-(z * z))


def _amplitudes(basis, y, bounds):
    """Least-squares amplitudes for a fixed basis within ``bounds = (low, high)``."""
    a = np.linalg.lstsq(basis, y, rcond=None)[0]
    if np.all((a >= bounds[0]) & (a <= bounds[1])):
        return a
    from scipy.optimize import lsq_linear  # deferred, as in fit_gaussian_sum

    return lsq_linear(basis, y, bounds=bounds, method="bvls").x


def _projected_residual(p, x, y, n_terms, amplitude_bounds):
    """Residual with the amplitudes eliminated; ``p = [b, c]``."""
    basis = _basis(x, p[:n_terms], p[n_terms:])
    return basis @ _amplitudes(basis, y, amplitude_bounds) - y


def _projected_jacobian(p, x, y, n_terms, amplitude_bounds):
    """Kaufman's Jacobian of the projected residual, (n_samples, 2 n_terms).

    With r = Phi a - y and a the least-squares amplitudes, column j is
    (I - Phi Phi^+) (dPhi/dp_j) a (Kaufman 1975, doi:10.1007/BF01932995), the standard
    variable-projection approximation (the term through da/dp is dropped). Each centre b_i and
    width c_i moves only column i of Phi: dphi_i/db_i = phi_i 2 z / c_i and
    dphi_i/dc_i = phi_i 2 z^2 / c_i with z = (x - b_i) / c_i. One residual evaluation instead
    of 2 n_terms finite differences per iteration.
    """
    b, c = p[:n_terms], p[n_terms:]
    z = (x[:, None] - b) / c
    basis = np.exp(-(z * z))
    a = _amplitudes(basis, y, amplitude_bounds)
    derivative = np.concatenate([basis * (2.0 * z / c) * a, basis * (2.0 * z * z / c) * a], axis=1)
    q, _ = np.linalg.qr(basis)
    return derivative - q @ (q.T @ derivative)


def _automatic_starts(x, y, n_terms, n_starts, lower, upper, seed):
    """Starting vectors ``[b, c]``, see :func:`fit_gaussian_sum` Notes."""
    span = float(x[-1] - x[0])
    peeled = _peeling_guess(x, y, n_terms)
    centres = x[0] + span * (np.arange(n_terms) + 0.5) / n_terms
    starts = [peeled, np.concatenate([centres, np.full(n_terms, span / n_terms)])]
    rng = np.random.default_rng(seed)
    for _ in range(n_starts - 2):
        random_centres = rng.uniform(lower[:n_terms], upper[:n_terms])
        random_widths = rng.uniform(0.25, 2.0, n_terms) * span / n_terms
        starts.append(np.concatenate([random_centres, random_widths]))
    return starts


def _peeling_guess(x, y, n_terms):
    """Greedy ``[b, c]``: put each term at the largest remaining residual, then subtract it."""
    span = float(x[-1] - x[0])
    residual = y.copy()
    b, c = np.zeros(n_terms), np.zeros(n_terms)
    for term in range(n_terms):
        peak = int(np.argmax(np.abs(residual)))
        height = residual[peak]
        below_half = np.abs(residual) < 0.5 * abs(height)
        left = np.nonzero(below_half[:peak])[0]
        right = np.nonzero(below_half[peak:])[0]
        widths = []
        if left.size:
            widths.append(x[peak] - x[left[-1]])
        if right.size:
            widths.append(x[peak + right[0]] - x[peak])
        # a Gaussian is at half its maximum at |x - b| = c sqrt(ln 2)
        width = (min(widths) if widths else span / n_terms) / np.sqrt(np.log(2.0))
        b[term], c[term] = x[peak], max(width, 1e-2 * span)
        residual = residual - height * np.exp(-(((x - b[term]) / c[term]) ** 2))
    return np.concatenate([b, c])


def _validated_samples(x, y, n_terms):
    """Finite float arrays of equal length with enough samples, or InputError."""
    x = np.asarray(x, dtype=np.float64).reshape(-1)
    y = np.asarray(y, dtype=np.float64).reshape(-1)
    if not isinstance(n_terms, (int, np.integer)) or n_terms < 1:
        raise InputError(f"n_terms: expected an integer >= 1, got {n_terms!r}")
    if x.size != y.size:
        raise InputError(f"Gaussian fit: x has {x.size} samples but y has {y.size}")
    if x.size < 3 * n_terms:
        raise InputError(f"Gaussian fit: {x.size} samples, expected at least {3 * n_terms} for {n_terms} terms")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise InputError("Gaussian fit: x and y must be finite numbers")
    if np.ptp(x) <= 0.0:
        raise InputError("Gaussian fit: x has no spread (all abscissae equal)")
    return x, y
