"""Instrument motion: pose against the amplitudes, surface velocity against finite differences."""

import math

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.solver._amplitudes import Linear, SmoothStep
from corneasim.instruments._motion import Motion, needle_insertion, surface_velocity, to_global_direction, to_local, trephination

OMEGA = 33.5 * 2 * math.pi / 60


def test_trephination_pose_follows_the_paper():
    motion = trephination(tip_position=(0.1, -0.2, 1.0))
    for t in np.linspace(0.01, 70.0, 57):
        cx, cy, cz, theta, vx, vy, vz, omega = motion.pose(t)
        assert (cx, cy) == (0.1, -0.2)
        assert cz == pytest.approx(1.0 - 0.020 * t, abs=1e-14)
        assert vz == pytest.approx(-0.020)
        assert theta == pytest.approx(1.25 * math.sin(OMEGA * t), abs=1e-12)
        assert omega == pytest.approx(1.25 * OMEGA * math.cos(OMEGA * t), abs=1e-12)
    assert motion.pose(math.pi / (2 * OMEGA))[3] == pytest.approx(1.25, rel=1e-12)


def test_needle_moves_only_along_its_axis():
    motion = needle_insertion(speed=5.0, tip_position=(0.0, 0.6))
    pose = motion.pose(0.1)
    assert pose.tolist() == pytest.approx([0.0, 0.0, 0.1, 0.0, 0.0, 0.0, -5.0, 0.0])


def test_surface_velocity_is_time_derivative_of_material_point():
    motion = Motion(insertion=SmoothStep(0.0, 2.0, 0.0, 1.5), rotation=Linear(rate=0.8), tip_position=(0.3, 0.1, 2.0))
    local = np.array([0.7, -0.4, 0.25])

    def material_point(t):
        cx, cy, cz, theta = motion.pose(t)[:4]
        rotated = to_global_direction(np.array([0, 0, 0, theta, 0, 0, 0, 0.0]), *local)
        return np.array([cx, cy, cz]) + np.array(rotated)

    t, h = 0.77, 1e-6
    numeric = (material_point(t + h) - material_point(t - h)) / (2 * h)
    pose = motion.pose(t)
    assert np.array(surface_velocity(pose, *material_point(t))) == pytest.approx(numeric, abs=1e-7)
    assert np.array(to_local(pose, *material_point(t))) == pytest.approx(local, abs=1e-12)


def test_bad_tip_position():
    with pytest.raises(InputError, match="tip_position"):
        Motion(tip_position=(0.2, 1.0))
    with pytest.raises(InputError, match="tip_position"):
        Motion(tip_position=(1.0,))
