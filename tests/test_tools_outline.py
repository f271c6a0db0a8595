"""The instrument's section in the plane y = 0 drawn on the stress maps."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from corneasim.solver._amplitudes import Fourier, Linear
from corneasim.instruments._kinds import Needle, Trephine
from corneasim.instruments._motion import Motion
from corneasim.instruments._outline import instrument_section, section_distance


def test_rounded_needle_section_against_its_geometry():
    """Beside the shaft the distance is |x| - R, below the tip it is the height above the
    hemispherical tip, at the tip's moved position (tip at z0 - v t)."""
    needle = Needle(tip="rounded", diameter=0.2)
    motion = Motion(insertion=Linear(rate=1.0), tip_position=(0.0, 0.0, 0.5))
    pose = motion.pose(0.3)  # tip at z = 0.2
    x = np.array([0.25, -0.25, 0.0, 0.05])
    z = np.array([0.6, 0.6, 0.15, 0.6])
    out = np.empty(4)
    section_distance(needle.pack(), pose, x, z, out)
    assert out == pytest.approx([0.15, 0.15, 0.05, -0.05], abs=1e-12)


def test_trephine_blade_is_cut_twice_by_the_plane_through_its_axis():
    """The ring's wall appears at x = +-3.75 mm whatever the rotation angle."""
    trephine = Trephine(diameter=7.5, wall_thickness=0.1, bevel_side="outer")
    rotation = Fourier(cosine=(0.0,), sine=(1.25,), circular_frequency=3.5)
    motion = Motion(insertion=Linear(rate=0.02), rotation=rotation,
                    tip_position=(0.0, 0.0, 1.0))
    hook = SimpleNamespace(shape=trephine.pack(), motion=motion)
    X, Z, D = instrument_section(hook, 10.0, (-5.0, 5.0), (0.5, 2.5), n=401)
    inside = D < 0.0
    assert inside.any()
    columns = np.unique(np.round(np.abs(X[inside]), 1))
    assert set(columns) <= {3.7, 3.8}
    tip = 1.0 - 0.02 * 10.0  # the edge has come down 0.2 mm: nothing below it, the wedge just above
    assert tip <= Z[inside].min() <= tip + 0.02
    assert instrument_section(None, 10.0, (-5.0, 5.0), (0.5, 2.5)) is None
    assert math.isfinite(D.max())
