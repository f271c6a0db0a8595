"""Error of a simulated curve against an experimental table.

The papers judge their simulations by the force curves of Tables 2 (needle
insertion force against depth, trephine force against time). A simulation
produces a densely sampled curve; the table has a few abscissae. The simulated
curve is interpolated linearly at the table's abscissae and the differences
summarised by their RMSE and maximum absolute value.
"""

from __future__ import annotations

import numpy as np

from corneasim.errors import InputError


def compare_to_experiment(sim_x, sim_y, exp_x, exp_y) -> dict:
    r"""RMSE and maximum absolute error of a simulated curve at the table's abscissae.

    Parameters
    ----------
    sim_x : array_like, shape (n,)
        Abscissae of the simulated curve, strictly increasing (e.g. depth in mm
        or time in s), ``n >= 2``.
    sim_y : array_like, shape (n,)
        Simulated values (e.g. force in N).
    exp_x : array_like, shape (m,)
        Abscissae of the experimental table (same unit as ``sim_x``), any order.
    exp_y : array_like, shape (m,)
        Experimental values (same unit as ``sim_y``).

    Returns
    -------
    dict
        ``rmse`` and ``max_abs_error`` (unit of y), ``n_points`` (table points
        compared), ``n_outside`` (table points outside the simulated range, not
        compared), ``x_max_error`` (abscissa of the largest error).

    Raises
    ------
    corneasim.errors.InputError
        Mismatched lengths, non-finite values, ``sim_x`` not strictly
        increasing, or no table point inside the simulated range.

    Notes
    -----
    With :math:`\hat y_k` the simulated curve linearly interpolated at the
    table abscissa :math:`x_k`, over the :math:`m'` table points with
    :math:`x_k \in [\min x_{sim}, \max x_{sim}]`:

    .. math::

        \mathrm{RMSE} = \sqrt{\frac{1}{m'} \sum_k (\hat y_k - y_k)^2}, \qquad
        e_{max} = \max_k |\hat y_k - y_k|.

    The range is widened by 1e-9 of its length at both ends, so that round-off in
    the simulated end point (a depth of 0.69999999 mm for the table's 0.70) does not
    drop a table point; interpolation clamps there. Table points outside the range
    are **excluded and counted** in ``n_outside``, never extrapolated: a
    simulation that stopped early (or started late) is compared only where it
    exists, and the caller sees how much of the table was left out. (The trephination paper's Table 2 runs to
    100 s while its simulation lasted 70 s.)

    Examples
    --------
    >>> result = compare_to_experiment([0, 1, 2], [0, 1, 2], [0.5, 1.5, 3.0], [0.5, 1.0, 9.0])
    >>> result["rmse"], result["max_abs_error"], result["n_points"], result["n_outside"]
    (0.3535533905932738, 0.5, 2, 1)
    """
    sim_x, sim_y = _pair(sim_x, sim_y, "simulation")
    exp_x, exp_y = _pair(exp_x, exp_y, "experiment")
    if sim_x.size < 2:
        raise InputError("simulation: expected at least 2 samples to interpolate")
    if np.any(np.diff(sim_x) <= 0.0):
        raise InputError("simulation: abscissae must be strictly increasing")
    slack = 1e-9 * (sim_x[-1] - sim_x[0])  # round-off of the simulated end points
    inside = (exp_x >= sim_x[0] - slack) & (exp_x <= sim_x[-1] + slack)
    if not np.any(inside):
        raise InputError(
            f"experiment: no table abscissa inside the simulated range [{sim_x[0]:g}, {sim_x[-1]:g}]"
        )
    error = np.interp(exp_x[inside], sim_x, sim_y) - exp_y[inside]  # (m',)
    worst = int(np.argmax(np.abs(error)))
    return {
        "rmse": float(np.sqrt(np.mean(error * error))),
        "max_abs_error": float(abs(error[worst])),
        "n_points": int(inside.sum()),
        "n_outside": int((~inside).sum()),
        "x_max_error": float(exp_x[inside][worst]),
    }


def _pair(x, y, label):
    """Finite 1-D float arrays of equal length, or InputError."""
    x = np.asarray(x, dtype=np.float64).reshape(-1)
    y = np.asarray(y, dtype=np.float64).reshape(-1)
    if x.size != y.size:
        raise InputError(f"{label}: {x.size} abscissae but {y.size} values")
    if x.size == 0:
        raise InputError(f"{label}: no samples")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise InputError(f"{label}: values must be finite numbers")
    return x, y
