"""Amplitudes against their closed forms and against finite differences of themselves."""

import math

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.solver._amplitudes import Constant, Fourier, Linear, SmoothStep, Tabular

AMPLITUDES = [
    Constant(2.5),
    Linear(rate=1.0, start_time=0.1),
    SmoothStep(0.0, 0.5, 0.0, 2.333e-3),
    Tabular((0.0, 1.0, 3.0), (0.0, 2.0, -1.0)),
    Fourier(initial=0.1, cosine=(0.2, 0.0), sine=(1.25, 0.3), circular_frequency=3.508, start_time=0.2),
]


@pytest.mark.parametrize("amplitude", AMPLITUDES, ids=lambda a: type(a).__name__)
def test_rate_is_derivative_of_value(amplitude):
    h = 1e-6
    for t in np.linspace(0.0, 2.9, 37) + 0.0123:
        numeric = (amplitude(t + h) - amplitude(t - h)) / (2 * h)
        assert amplitude.evaluate(t)[1] == pytest.approx(numeric, abs=1e-5)


def test_paper_rotation_history():
    """Trephination paper: N = 1, B1 = theta = 1.25 rad, epsilon = omega = 33.5 r/min."""
    omega = 33.5 * 2 * math.pi / 60
    rotation = Fourier(sine=(1.25,), cosine=(0.0,), circular_frequency=omega)
    t = np.linspace(0, 10, 1001)
    angles = np.array([rotation(ti) for ti in t])
    assert angles.max() == pytest.approx(1.25, rel=1e-3)
    assert rotation(math.pi / (2 * omega)) == pytest.approx(1.25, rel=1e-12)
    assert rotation(2 * math.pi / omega) == pytest.approx(0.0, abs=1e-12)


def test_smooth_step_ends_and_midpoint():
    step = SmoothStep(1.0, 3.0, 0.0, 4.0)
    assert step(0.5) == 0.0 and step(3.5) == 4.0
    assert step(2.0) == pytest.approx(2.0)
    assert step.evaluate(1.0)[1] == 0.0 and step.evaluate(3.0)[1] == 0.0


def test_bad_amplitudes_are_input_errors():
    with pytest.raises(InputError):
        Tabular((0.0, 0.0), (1.0, 2.0))
    with pytest.raises(InputError):
        SmoothStep(1.0, 1.0)
    with pytest.raises(InputError):
        Fourier(cosine=(1.0,), sine=())


@pytest.mark.parametrize("amplitude", AMPLITUDES, ids=lambda a: type(a).__name__)
def test_shifted_amplitude_is_a_time_translation(amplitude):
    from corneasim.solver._amplitudes import shifted

    later = shifted(amplitude, 0.75)
    for t in np.linspace(-1.0, 3.0, 41):
        assert later(t + 0.75) == pytest.approx(amplitude(t), abs=1e-12)


def test_a_long_table_is_numpys_linear_interpolation_at_and_between_its_points():
    rng = np.random.default_rng(3)
    times = np.concatenate([[0.0], np.cumsum(rng.uniform(0.01, 0.2, 300))])
    values = rng.normal(size=times.size)
    table = Tabular(tuple(times), tuple(values))
    for t in np.concatenate([times, rng.uniform(-0.5, times[-1] + 0.5, 500)]):
        assert table(t) == pytest.approx(np.interp(t, times, values), rel=1e-12, abs=1e-12)
