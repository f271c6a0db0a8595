"""Force-drop detection: synthetic drops at known positions, none in pure noise."""

import numpy as np
import pytest

from corneasim.analysis import detect_force_drops, noise_level
from corneasim.errors import InputError


def noisy_ramp_with_drops(rng, drop_depths, drop_sizes, noise=0.002, n=4000, ramp=(0.6, 0.7)):
    depth = np.linspace(0.0, ramp[1], n)  # mm
    force = ramp[0] * depth  # N
    for position, size in zip(drop_depths, drop_sizes):
        force = force - size * (depth > position)
    return depth, force + rng.normal(0.0, noise, n)


def test_noise_level_of_white_noise_is_sqrt2_sigma():
    rng = np.random.default_rng(0)
    sigma = 0.003
    samples = 0.5 * np.linspace(0, 1, 200_000) + rng.normal(0.0, sigma, 200_000)
    assert noise_level(samples) == pytest.approx(np.sqrt(2.0) * sigma, rel=0.02)


def test_finds_sudden_drops_at_known_positions():
    rng = np.random.default_rng(1)
    positions, sizes = [0.12, 0.4, 0.57], [0.05, 0.08, 0.2]  # mm, N
    depth, force = noisy_ramp_with_drops(rng, positions, sizes)
    events = detect_force_drops(force, depth)
    assert len(events) == 3
    # peak and trough are noisy extremes: they sit within a few noise/slope = 0.0033 mm of the step
    tolerance = 3 * 0.002 / 0.6
    for event, position, size in zip(events, positions, sizes):
        assert position - tolerance <= event.x <= position
        assert position < event.end_x <= position + tolerance
        assert event.drop == pytest.approx(size, abs=0.015)  # noise (s = 2 mN) at peak and trough
        earlier_drops = sum(s for p, s in zip(positions, sizes) if p < position)
        assert event.force == pytest.approx(0.6 * position - earlier_drops, abs=0.01)


def test_a_gradual_noisy_drop_is_one_event():
    rng = np.random.default_rng(2)
    x = np.arange(3000.0)
    force = np.where(x < 1000, x * 1e-4, np.where(x < 1050, 0.1 - (x - 1000) * 1e-3, 0.05 + (x - 1050) * 1e-4))
    events = detect_force_drops(force + rng.normal(0.0, 5e-4, x.size))
    assert len(events) == 1
    # the noise (5e-4) equals 5 samples of the ramp (1e-4 per sample): peak and trough move by up to ~20
    assert abs(events[0].index - 1000) <= 20 and abs(events[0].end_index - 1050) <= 20
    assert events[0].drop == pytest.approx(0.05, abs=0.004)


@pytest.mark.parametrize("seed", range(5))
def test_none_in_pure_noise_or_noisy_ramp(seed):
    rng = np.random.default_rng(100 + seed)
    assert detect_force_drops(rng.normal(0.0, 0.01, 50_000)) == []
    depth, force = noisy_ramp_with_drops(rng, [], [], n=20_000)
    assert detect_force_drops(force, depth) == []


def test_min_drop_applies_to_a_clean_signal():
    force = np.concatenate([np.linspace(0, 0.1, 50), np.linspace(0.09995, 0.2, 50)])  # 0.05 mN dip
    assert detect_force_drops(force) == []
    assert len(detect_force_drops(force, min_drop=1e-5)) == 1


def test_drop_below_the_noise_threshold_is_ignored():
    rng = np.random.default_rng(3)
    depth, force = noisy_ramp_with_drops(rng, [0.3], [0.008])  # 4 noise sigmas only
    assert detect_force_drops(force, depth) == []


@pytest.mark.parametrize(
    "kwargs, fragment",
    [
        (dict(force=[0, 1, 2], x=[0, 1]), "3 force samples but 2 abscissae"),
        (dict(force=[0, np.nan]), "finite"),
        (dict(force=[0, 1], noise_factor=-1.0), ">= 0"),
    ],
)
def test_bad_input(kwargs, fragment):
    with pytest.raises(InputError, match=fragment):
        detect_force_drops(**kwargs)
