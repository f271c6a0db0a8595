"""Instrument placement: the clearance to the tissue equals the requested gap."""

import numpy as np
import pytest

from corneasim.tools import Needle, Trephine
from corneasim.tools.placement import clearance, tip_height_for_gap


def dome(radius=7.8, r_max=5.5, n=400):
    """(r, z) points of a spherical cap with its apex at z = 0, mm."""
    r = np.linspace(0.0, r_max, n)
    return np.column_stack([r, np.sqrt(radius ** 2 - r ** 2) - radius])


def test_needle_sits_the_gap_above_the_apex():
    shape = Needle(tip="rounded").pack()
    height = tip_height_for_gap(shape, dome(), 0.01, axisymmetric=True)
    assert clearance(shape, dome(), height, True) == pytest.approx(0.01, abs=1e-9)
    assert height == pytest.approx(0.01, abs=2e-3)


def test_trephine_edge_meets_the_dome_at_its_cutting_radius():
    shape = Trephine().pack()
    points = dome()
    height = tip_height_for_gap(shape, points, 0.0, axisymmetric=True)
    sag = 7.8 - np.sqrt(7.8 ** 2 - 3.75 ** 2)
    assert height == pytest.approx(-sag, abs=0.06)
    xyz = np.column_stack([points[:, 0], np.zeros(len(points)), points[:, 1]])
    assert tip_height_for_gap(shape, xyz, 0.0, axisymmetric=False) == pytest.approx(height, abs=1e-6)
