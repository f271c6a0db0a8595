"""Amplitudes: time functions that scale prescribed motions, loads and pressures, and their tables.

Each amplitude packs into a flat float64 array (its first entry the kind) that
:func:`evaluate` reads inside Numba kernels, so the time loop can run many steps
without returning to Python. The Python classes only build and document the
arrays; their ``value`` and ``rate`` call the same compiled evaluator. The scenario file's
amplitude tables (:data:`AmplitudeConfig`, validated) ``build()`` them.

======  ============  ===================================================
kind    class         packed array
======  ============  ===================================================
0       Constant      [0, value]
1       Linear        [1, rate, start_time]
2       SmoothStep    [2, t0, t1, a0, a1]
3       Tabular       [3, n, t_1..t_n, a_1..a_n]
4       Fourier       [4, N, A0, omega, t0, A_1..A_N, B_1..B_N]
======  ============  ===================================================
"""

from __future__ import annotations

import abc
import math
from dataclasses import dataclass, replace
from typing import Annotated, Literal, Union

import numpy as np
import pydantic
from numba import njit

from corneasim.errors import InputError
from corneasim.schema import StrictModel

CONSTANT, LINEAR, SMOOTH_STEP, TABULAR, FOURIER = 0, 1, 2, 3, 4


@njit(cache=True)
def evaluate(packed, t):
    """Value a(t) and rate da/dt of a packed amplitude.

    Parameters
    ----------
    packed : ndarray, float64
        Packed amplitude (see the module table).
    t : float
        Time, s.

    Returns
    -------
    (float, float)
        a(t) in the amplitude's unit, and da/dt in that unit per second.
    """
    kind = int(packed[0])
    if kind == CONSTANT:
        return packed[1], 0.0
    if kind == LINEAR:
        rate, start = packed[1], packed[2]
        if t <= start:
            return 0.0, 0.0
        return rate * (t - start), rate
    if kind == SMOOTH_STEP:
        t0, t1, a0, a1 = packed[1], packed[2], packed[3], packed[4]
        if t <= t0:
            return a0, 0.0
        if t >= t1:
            return a1, 0.0
        xi = (t - t0) / (t1 - t0)
        shape = xi * xi * xi * (10.0 - 15.0 * xi + 6.0 * xi * xi)
        slope = 30.0 * xi * xi * (1.0 - xi) * (1.0 - xi) / (t1 - t0)
        return a0 + (a1 - a0) * shape, (a1 - a0) * slope
    if kind == TABULAR:
        n = int(packed[1])
        times = packed[2 : 2 + n]
        values = packed[2 + n : 2 + 2 * n]
        if t <= times[0]:
            return values[0], 0.0
        if t >= times[n - 1]:
            return values[n - 1], 0.0
        # bisection keeping times[k] <= t < times[high]: np.searchsorted would compile
        # kernels of its own, about half a second of a first run
        k, high = 0, n - 1
        while high - k > 1:
            middle = (k + high) // 2
            if times[middle] <= t:
                k = middle
            else:
                high = middle
        slope = (values[k + 1] - values[k]) / (times[k + 1] - times[k])
        return values[k] + slope * (t - times[k]), slope
    # FOURIER
    n_terms = int(packed[1])
    a0, omega, t0 = packed[2], packed[3], packed[4]
    if t <= t0:
        return a0, 0.0
    value, rate = a0, 0.0
    for n in range(1, n_terms + 1):
        cosine, sine = packed[4 + n], packed[4 + n_terms + n]
        phase = n * omega * (t - t0)
        value += cosine * math.cos(phase) + sine * math.sin(phase)
        rate += n * omega * (sine * math.cos(phase) - cosine * math.sin(phase))
    return value, rate


class Amplitude(abc.ABC):
    """Base class: a packed array plus Python-side evaluation through the same kernel."""

    @abc.abstractmethod
    def pack(self) -> np.ndarray:
        """The packed float64 array read by :func:`evaluate`."""

    def __call__(self, t: float) -> float:
        """a(t)."""
        return evaluate(self.pack(), float(t))[0]

    def evaluate(self, t: float) -> tuple[float, float]:
        """(a(t), da/dt), the rate per second."""
        value, rate = evaluate(self.pack(), float(t))
        return float(value), float(rate)


@dataclass(frozen=True)
class Constant(Amplitude):
    """a(t) = value."""

    value: float = 1.0

    def pack(self) -> np.ndarray:
        return np.array([CONSTANT, self.value], dtype=np.float64)


@dataclass(frozen=True)
class Linear(Amplitude):
    """a(t) = rate (t - start_time) after start_time, 0 before: constant velocity.

    ``rate`` is in the amplitude's unit per second (mm/s for a displacement).
    """

    rate: float
    start_time: float = 0.0

    def pack(self) -> np.ndarray:
        return np.array([LINEAR, self.rate, self.start_time], dtype=np.float64)


@dataclass(frozen=True)
class SmoothStep(Amplitude):
    """Quintic smooth step from a0 at t0 to a1 at t1, zero slope and curvature at both ends.

    a = a0 + (a1 - a0) xi^3 (10 - 15 xi + 6 xi^2), xi = (t - t0) / (t1 - t0); times in s.
    """

    t0: float
    t1: float
    a0: float = 0.0
    a1: float = 1.0

    def __post_init__(self):
        if not self.t1 > self.t0:
            raise InputError(f"smooth step: t1 ({self.t1} s) must be greater than t0 ({self.t0} s)")

    def pack(self) -> np.ndarray:
        return np.array([SMOOTH_STEP, self.t0, self.t1, self.a0, self.a1], dtype=np.float64)


@dataclass(frozen=True)
class Tabular(Amplitude):
    """Piecewise-linear through (times [s], values); constant outside the table."""

    times: tuple[float, ...]
    values: tuple[float, ...]

    def __post_init__(self):
        if len(self.times) != len(self.values) or len(self.times) < 2:
            raise InputError("tabular amplitude: times and values need equal length >= 2")
        if np.any(np.diff(self.times) <= 0):
            raise InputError("tabular amplitude: times must increase strictly")

    def pack(self) -> np.ndarray:
        n = len(self.times)
        return np.concatenate([[TABULAR, n], self.times, self.values]).astype(np.float64)


@dataclass(frozen=True)
class Fourier(Amplitude):
    """Fourier series (trephination paper eq. 1, with the missing n restored in the sine term).

    a(t) = A0 + sum_n [A_n cos(n omega (t - t0)) + B_n sin(n omega (t - t0))] for t >= t0,
    a(t) = A0 before t0; ``circular_frequency`` omega in rad/s, ``start_time`` t0 in s.
    The paper's rotation: N = 1, B_1 = 1.25 rad, omega = 33.5 r/min = 3.508 rad/s.
    """

    initial: float = 0.0
    cosine: tuple[float, ...] = ()
    sine: tuple[float, ...] = ()
    circular_frequency: float = 1.0
    start_time: float = 0.0

    def __post_init__(self):
        if len(self.cosine) != len(self.sine):
            raise InputError("fourier amplitude: cosine and sine coefficient lists need equal length")
        if self.circular_frequency <= 0:
            raise InputError("fourier amplitude: circular_frequency must be > 0 rad/s")

    def pack(self) -> np.ndarray:
        head = [FOURIER, len(self.cosine), self.initial, self.circular_frequency, self.start_time]
        return np.concatenate([head, self.cosine, self.sine]).astype(np.float64)


def shifted(amplitude: Amplitude, delay: float) -> Amplitude:
    """The same amplitude started ``delay`` seconds later: b(t) = a(t - delay).

    Used to hold a procedure's motion until a preload stage has finished.
    """
    if delay == 0.0 or isinstance(amplitude, Constant):
        return amplitude
    if isinstance(amplitude, (Linear, Fourier)):
        return replace(amplitude, start_time=amplitude.start_time + delay)
    if isinstance(amplitude, SmoothStep):
        return replace(amplitude, t0=amplitude.t0 + delay, t1=amplitude.t1 + delay)
    if isinstance(amplitude, Tabular):
        return replace(amplitude, times=tuple(t + delay for t in amplitude.times))
    raise TypeError(f"cannot shift a {type(amplitude).__name__} amplitude")


class ConstantAmplitude(StrictModel):
    """a(t) = value (in the driven quantity's unit: mm for insertion, rad for rotation)."""

    type: Literal["constant"] = "constant"
    value: float = 0.0

    def build(self) -> Amplitude:
        return Constant(self.value)


class LinearAmplitude(StrictModel):
    """Constant velocity: a = rate (t - start_time); rate in mm/s or rad/s, start_time in s."""

    type: Literal["linear"] = "linear"
    rate: float
    start_time: float = 0.0

    def build(self) -> Amplitude:
        return Linear(self.rate, self.start_time)


class SmoothStepAmplitude(StrictModel):
    """Quintic step from a0 at t0 to a1 at t1 (times in s, values in mm or rad)."""

    type: Literal["smooth-step"] = "smooth-step"
    t0: float
    t1: float
    a0: float = 0.0
    a1: float = 1.0

    def build(self) -> Amplitude:
        return SmoothStep(self.t0, self.t1, self.a0, self.a1)


class TabularAmplitude(StrictModel):
    """Piecewise linear through (times in s, values in mm or rad)."""

    type: Literal["tabular"] = "tabular"
    times: list[float]
    values: list[float]

    def build(self) -> Amplitude:
        return Tabular(tuple(self.times), tuple(self.values))


class FourierAmplitude(StrictModel):
    """Trephination paper eq. 1: initial A0, cosine A_n, sine B_n, circular_frequency in rad/s, start_time in s."""

    type: Literal["fourier"] = "fourier"
    initial: float = 0.0
    cosine: list[float] = []
    sine: list[float] = []
    circular_frequency: float
    start_time: float = 0.0

    def build(self) -> Amplitude:
        return Fourier(self.initial, tuple(self.cosine), tuple(self.sine), self.circular_frequency, self.start_time)


AmplitudeConfig = Annotated[
    Union[ConstantAmplitude, LinearAmplitude, SmoothStepAmplitude, TabularAmplitude, FourierAmplitude],
    pydantic.Field(discriminator="type"),
]
