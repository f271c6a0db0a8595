"""The instrument's section by the plane y = 0 (through its axis), for the stress maps.

The needle paper's von Mises maps (its Fig. 10) and the trephination paper's sections (its
Fig. 5) show the instrument where it stands. The section is drawn from the instrument's own
signed distance (``shapes.signed_distance``) on a grid of the plane: the region d < 0 is the
instrument, whatever its shape, with no outline to keep in step with the contact geometry.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.instruments._motion import to_local
from corneasim.instruments._shapes import signed_distance


@njit(cache=True)
def section_distance(shape, pose, x, z, out):
    """Signed distance (mm, negative inside) of the instrument at the points (x, 0, z).

    Parameters
    ----------
    shape : ndarray float64
        Packed shape (``shapes`` module table).
    pose : ndarray (8,) float64
        Instrument pose (``motion.pose_at``).
    x, z : ndarray (n,) float64
        Global coordinates of the points in the plane y = 0, mm.
    out : ndarray (n,) float64
        Out: the signed distances, mm.
    """
    for k in range(x.shape[0]):
        lx, ly, lz = to_local(pose, x[k], 0.0, z[k])
        out[k] = signed_distance(shape, lx, ly, lz)[0]


def instrument_section(instrument, solver_time: float, x_limits, z_limits, n: int = 300):
    """The instrument's signed distance on an n x n grid of the plane y = 0.

    Parameters
    ----------
    instrument : corneasim.contact._instrument_contact.InstrumentContact or None
        The contact hook (its packed shape and motion); None gives None.
    solver_time : float
        Solver time, s (the preload included).
    x_limits, z_limits : (float, float)
        Extent of the grid, mm (for an axisymmetric model x is the radius, mirrored).

    Returns
    -------
    (X, Z, D) : ndarray (n, n) each, or None
        Grid coordinates (mm) and signed distance (mm), ready for ``contourf``.
    """
    if instrument is None:
        return None
    X, Z = np.meshgrid(np.linspace(*x_limits, n), np.linspace(*z_limits, n))
    D = np.empty(X.size)
    section_distance(instrument.shape, instrument.motion.pose(solver_time), X.ravel(), Z.ravel(), D)
    return X, Z, D.reshape(X.shape)
