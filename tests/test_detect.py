"""The streaming puncture detector on signals with known drops and sensor noise."""

import numpy as np
import pytest

from corneasim.surrogate import PunctureDetector

RATE = 1000.0       # samples per s
SPEED = 2.0         # mm/s
LATENCY = 10        # samples: 10 ms at 1 kHz


def noisy(force, rng, absolute=0.005, relative=0.004):
    """The sensor: white noise of ``absolute`` N RMS plus ``relative`` of the load."""
    return force + absolute * rng.standard_normal(force.size) + relative * force * rng.standard_normal(force.size)


def signal(n=600, drops=((200, 0.3), (320, 0.2)), exit_at=480):
    """A force rising as depth squared, falling by the given fractions at the given samples,
    and to the shaft's friction (5% of the peak) at ``exit_at``."""
    depth = np.arange(n) / RATE * SPEED
    force = 4.0 * depth**2
    for sample, fraction in drops:
        force[sample:] *= 1.0 - fraction
    force[exit_at:] = 0.05 * force[:exit_at].max()
    return depth, force


def run(detector, depth, force):
    for d, f in zip(depth, force):
        detector.update(f, d)
    return detector


@pytest.mark.parametrize("seed", range(10))
def test_finds_known_drops_within_the_latency(seed):
    depth, force = signal()
    detector = run(PunctureDetector(), depth, noisy(force, np.random.default_rng(seed)))
    found = {p.event: p.sample for p in detector.punctures}
    assert set(found) == {"epithelium", "stroma", "cornea"}
    for event, truth in (("epithelium", 200), ("stroma", 320), ("cornea", 480)):
        assert 0 <= found[event] - truth <= LATENCY


@pytest.mark.parametrize("seed", range(5))
def test_no_alarm_on_pure_noise_or_in_the_contact_stage(seed):
    rng = np.random.default_rng(100 + seed)
    detector = run(PunctureDetector(), np.zeros(5000), noisy(np.zeros(5000), rng))
    assert detector.punctures == [] and detector.drops == []
    depth, force = signal(drops=(), exit_at=600)  # contact stage only: a noisy rise
    detector = run(PunctureDetector(), depth, noisy(force, rng))
    assert detector.punctures == []


def test_a_drop_outside_every_prior_band_is_not_a_puncture():
    depth, force = signal()
    prior = {"epithelium": (0.39, 0.38, 0.41), "stroma": (0.63, 0.62, 0.66)}  # drops at 0.40 and 0.64 mm
    detector = run(PunctureDetector(prior=prior), depth, force)
    assert [p.event for p in detector.punctures] == ["epithelium", "stroma", "cornea"]
    shifted = {"epithelium": (0.2, 0.15, 0.25), "stroma": (0.63, 0.62, 0.66)}
    detector = run(PunctureDetector(prior=shifted), depth, force)
    assert [p.event for p in detector.punctures] == ["stroma", "cornea"]
    assert [round(d.depth_mm, 1) for d in detector.drops] == [0.4, 0.6, 1.0]  # the exit is a drop too


def test_stops_after_the_whole_cornea():
    depth, force = signal()
    detector = PunctureDetector()
    for d, f in zip(depth, force):
        detector.update(f, d)
        if detector.finished:
            break
    assert detector.detected("cornea").sample - 480 <= LATENCY
    assert detector.update(10.0, 2.0) == []


@pytest.mark.parametrize("seed", range(5))
def test_a_one_sample_tear_is_a_drop(seed):
    depth, force = signal(drops=(), exit_at=600)
    force[250] *= 0.85  # a tear that recovers at the next sample: the 4-sample mean moves by 3.75%
    detector = run(PunctureDetector(noise_N=0.0005), depth, noisy(force, np.random.default_rng(seed), 0.0005))
    assert [p.sample for p in detector.punctures] == [250]


def test_a_deep_epithelium_drop_is_not_the_exit():
    depth, force = signal(drops=((200, 0.9), (320, 0.2)))  # the force falls to 10% of its peak at 0.4 mm
    prior = {"epithelium": (0.4, 0.38, 0.41), "stroma": (0.64, 0.62, 0.66), "cornea": (0.96, 0.9, 1.0)}
    found = {p.event: p.sample for p in run(PunctureDetector(prior=prior), depth, force).punctures}
    assert 0 <= found["cornea"] - 480 <= LATENCY  # not at 0.4 mm, where the force is below 25% of its peak
