"""Prescribed rigid motion of an instrument: insertion along its axis and rotation about it.

The instrument axis is the global z-axis through the tip's initial position
``tip_position``; the instrument points down (-z), so the local frame of
:mod:`corneasim.instruments._shapes` is the global frame translated to the current tip and
turned by the rotation angle. With insertion depth d(t) and rotation angle theta(t)
(each an amplitude of :mod:`corneasim.solver._amplitudes`):

.. math::

    c(t) = p_0 - d(t)\\,e_z, \\qquad
    X_{local} = R_z(-\\theta)\\,(x - c), \\qquad
    v_{surface}(x) = -\\dot d\\, e_z + \\dot\\theta\\, e_z \\times (x - c).

The needle paper inserts vertically at a constant 1 or 5 mm/s, the needle held
laterally (only the axial motion is free); the trephination paper lowers the trephine
at 20 um/s while it oscillates about its axis with theta = 1.25 sin(omega t),
omega = 33.5 r/min (its eq. 1 with N = 1, B_1 = theta, epsilon = omega).

The pose is a float64 array of length 8, ``[c_x, c_y, c_z, theta, v_x, v_y, v_z, omega]``:
the current tip point on the axis (mm), the angle (rad), the velocity of that point
(mm/s) and the angular velocity (rad/s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from corneasim.errors import InputError
from corneasim.schema import StrictModel
from corneasim.solver import (
    Amplitude, AmplitudeConfig, Constant, ConstantAmplitude, Fourier, Linear, evaluate_amplitude)
from corneasim.units import RPM_IN_RAD_PER_S

(POSE_X, POSE_Y, POSE_Z, POSE_ANGLE, POSE_VX, POSE_VY, POSE_VZ, POSE_OMEGA) = range(8)
POSE_SIZE = 8
"""Fields of the pose array: the current tip point on the axis (mm), the rotation angle about
the axis (rad), the velocity of the tip point (mm/s) and the angular velocity (rad/s)."""


@njit(cache=True)
def pose_at(motion, t, pose):
    """Fill ``pose`` with the instrument pose at time t.

    Parameters
    ----------
    motion : ndarray, float64
        Packed motion ``[x0, y0, z0, n_insertion, insertion..., rotation...]`` (see :class:`Motion`).
    t : float
        Time, s.
    pose : ndarray, float64, shape (8,)
        Output ``[c_x, c_y, c_z, theta, v_x, v_y, v_z, omega]`` in mm, rad, mm/s, rad/s.
    """
    n_insertion = int(motion[3])
    depth, depth_rate = evaluate_amplitude(motion[4 : 4 + n_insertion], t)
    theta, omega = evaluate_amplitude(motion[4 + n_insertion :], t)
    pose[POSE_X] = motion[0]
    pose[POSE_Y] = motion[1]
    pose[POSE_Z] = motion[2] - depth
    pose[POSE_ANGLE] = theta
    pose[POSE_VX] = 0.0
    pose[POSE_VY] = 0.0
    pose[POSE_VZ] = -depth_rate
    pose[POSE_OMEGA] = omega


@njit(cache=True)
def to_local(pose, x, y, z):
    """Global point (mm) to the instrument-local frame: R_z(-theta) (x - c)."""
    cos_t, sin_t = math.cos(pose[POSE_ANGLE]), math.sin(pose[POSE_ANGLE])
    dx, dy = x - pose[POSE_X], y - pose[POSE_Y]
    return cos_t * dx + sin_t * dy, -sin_t * dx + cos_t * dy, z - pose[POSE_Z]


@njit(cache=True)
def to_global_direction(pose, n_x, n_y, n_z):
    """Instrument-local direction to the global frame: R_z(theta) n."""
    cos_t, sin_t = math.cos(pose[POSE_ANGLE]), math.sin(pose[POSE_ANGLE])
    return cos_t * n_x - sin_t * n_y, sin_t * n_x + cos_t * n_y, n_z


@njit(cache=True)
def surface_velocity(pose, x, y, z):
    """Velocity (mm/s) of the instrument's material point at global x: v_c + omega e_z x (x - c)."""
    omega = pose[POSE_OMEGA]
    return pose[POSE_VX] - omega * (y - pose[POSE_Y]), pose[POSE_VY] + omega * (x - pose[POSE_X]), pose[POSE_VZ]


@dataclass(frozen=True)
class Motion:
    """Insertion and rotation amplitudes plus the tip's initial position.

    Attributes
    ----------
    insertion : Amplitude
        Insertion depth d(t) along the pointing direction (-z), mm.
    rotation : Amplitude
        Rotation angle theta(t) about +z (right-handed), rad.
    tip_position : tuple of float
        Tip position at d = 0, mm: (x, y, z), or (r, z) with r = 0 for the axisymmetric model.
    """

    insertion: Amplitude = Constant(0.0)
    rotation: Amplitude = Constant(0.0)
    tip_position: tuple[float, ...] = (0.0, 0.0, 0.0)

    def __post_init__(self):
        if len(self.tip_position) == 2:
            if self.tip_position[0] != 0.0:
                raise InputError("tip_position: an axisymmetric instrument lies on the axis, r must be 0")
            object.__setattr__(self, "tip_position", (0.0, 0.0, float(self.tip_position[1])))
        elif len(self.tip_position) != 3:
            raise InputError("tip_position: expected (x, y, z) or (r, z) in mm")

    def pack(self) -> np.ndarray:
        """``[x0, y0, z0, n_insertion, insertion..., rotation...]``, read by :func:`pose_at`."""
        insertion = self.insertion.pack()
        head = [*self.tip_position, len(insertion)]
        return np.concatenate([head, insertion, self.rotation.pack()]).astype(np.float64)

    def pose(self, t: float) -> np.ndarray:
        """The pose at time t (s) as an array of length 8 (see the module docstring)."""
        pose = np.empty(POSE_SIZE)
        pose_at(self.pack(), float(t), pose)
        return pose


def needle_insertion(speed: float = 1.0, tip_position=(0.0, 0.0), start_time: float = 0.0) -> Motion:
    """Constant-speed vertical insertion, no rotation (needle paper: 1 or 5 mm/s).

    Parameters
    ----------
    speed : float
        Insertion speed, mm/s.
    tip_position : tuple of float
        Initial tip position, mm ((r, z) axisymmetric or (x, y, z)).
    start_time : float
        Time at which the motion starts, s.
    """
    return Motion(insertion=Linear(rate=speed, start_time=start_time), tip_position=tuple(tip_position))


def trephination(
    vertical_speed: float = 0.020,
    rotation_angle: float = 1.25,
    rotation_speed_rpm: float = 33.5,
    tip_position=(0.0, 0.0, 0.0),
    start_time: float = 0.0,
) -> Motion:
    """Trephination paper motion: descent at constant speed, rotation theta sin(omega t).

    Parameters
    ----------
    vertical_speed : float
        Descent speed, mm/s (paper: 20 um/s = 0.020 mm/s).
    rotation_angle : float
        Amplitude theta of the oscillating rotation, rad (paper: 1.25 rad).
    rotation_speed_rpm : float
        Circular frequency omega of the oscillation, r/min (paper: 33.5 r/min).
    tip_position : tuple of float
        Initial position of the cutting edge's plane on the axis, mm.
    start_time : float
        Time at which both motions start, s.
    """
    rotation = Fourier(
        sine=(rotation_angle,),
        cosine=(0.0,),
        circular_frequency=rotation_speed_rpm * RPM_IN_RAD_PER_S,
        start_time=start_time,
    )
    return Motion(
        insertion=Linear(rate=vertical_speed, start_time=start_time),
        rotation=rotation,
        tip_position=tuple(tip_position),
    )


class MotionConfig(StrictModel):
    """Prescribed instrument motion.

    Attributes
    ----------
    tip_position : list of float
        Tip position at zero insertion, mm: [x, y, z] (3D) or [r, z] with r = 0 (axisymmetric).
    insertion : amplitude table
        Insertion depth along the pointing direction (-z), mm.
    rotation : amplitude table
        Rotation angle about the axis, rad.
    """

    tip_position: list[float] = [0.0, 0.0, 0.0]
    insertion: AmplitudeConfig = ConstantAmplitude()
    rotation: AmplitudeConfig = ConstantAmplitude()

    def build(self) -> Motion:
        """The :class:`Motion` (raises InputError on inconsistent amplitudes)."""
        return Motion(self.insertion.build(), self.rotation.build(), tuple(self.tip_position))
