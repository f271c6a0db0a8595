"""Statistics of the streaming puncture detector on noisy force signals.

Two families of signals, sampled at 1 kHz and fed one sample at a time:

* **FE**: the held-out cases of the study of ``validation/surrogate.py`` (run it first; its
  folder holds ``surrogate.npz``): each case's force against time, the detector's prior the
  surrogate's puncture bands at the case's inputs, the truth the case's puncture events;
* **law**: the closed-form law of :mod:`corneasim.surrogate.synthetic` at random inputs, with
  its exact puncture depths, no prior.

Each signal gets 100 noise realizations per sensor: the needle paper's Instron (+-0.4% of
load, taken as 0.4% RMS, plus 0.5 mN) and a noisier 5 mN RMS sensor. Printed per layer: the
fraction detected within 10 ms of the truth, the latencies (median, 95th percentile, max) and
the false alarms (a puncture reported before the epithelium's, in the contact stage).

Run: ``python validation/detector.py [--out DIR] [--realizations N]``
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from corneasim.surrogate import PunctureDetector, load, synthetic
from corneasim.surrogate._study import read_study

SAMPLE_RATE = 1000.0
"""Hz."""
LATENCY = 0.010
"""s: the largest latency that counts as a detection."""
SENSORS = {"Instron (0.4% of load)": (0.0005, 0.004), "5 mN RMS": (0.005, 0.0)}
"""Sensor -> (absolute noise N RMS, relative noise RMS fraction of the load)."""
LAYERS = ("epithelium", "stroma", "cornea")


def detect(time, depth, force, sensor, rng, prior=None) -> dict:
    """Feed one noisy realization of ``force`` (N, at ``time`` s and ``depth`` mm) to a detector.

    Returns the detection time of each layer reported (s).
    """
    absolute, relative = sensor
    noisy = force + absolute * rng.standard_normal(force.size) + relative * force * rng.standard_normal(force.size)
    detector = PunctureDetector(noise_N=absolute, relative_noise=relative, prior=prior)
    for d, f in zip(depth, noisy):
        detector.update(f, d)
        if detector.finished:
            break
    return {p.event: time[p.sample] for p in detector.punctures}


def statistics(signals, sensor, realizations: int, seed: int) -> dict:
    """Detection rate, latencies and false alarms over ``signals``: (time, depth, force, truth times, prior)."""
    rng = np.random.default_rng(seed)
    latencies = {layer: [] for layer in LAYERS}
    detected = {layer: 0 for layer in LAYERS}
    false_alarms = trials = 0
    for time, depth, force, truth, prior in signals:
        for _ in range(realizations):
            found = detect(time, depth, force, sensor, rng, prior)
            trials += 1
            false_alarms += any(t < truth["epithelium"] - LATENCY for t in found.values())
            for layer in LAYERS:
                if layer in found:
                    latency = found[layer] - truth[layer]
                    latencies[layer].append(latency)
                    detected[layer] += abs(latency) <= LATENCY
    return {"trials": trials, "false_alarms": false_alarms,
            "detected": {layer: detected[layer] / trials for layer in LAYERS},
            "latencies": {layer: np.array(latencies[layer]) for layer in LAYERS}}


def fe_signals(out: Path) -> list:
    """The held-out FE cases at 1 kHz: (time s, depth mm, force N, true event times s, surrogate prior mm)."""
    model = load(out / "surrogate.npz")
    training = read_study(out)
    signals = []
    for case in training.cases:
        if case.name not in model.metadata["held_out_cases"]:
            continue
        inputs = dict(zip(model.inputs, case.inputs))
        rate = inputs["instrument.motion.insertion.rate"]
        depth = np.arange(0.0, case.abscissa[-1], rate / SAMPLE_RATE)
        force = np.interp(depth, case.abscissa, case.forces["force_N"])
        signals.append((depth / rate, depth, force, {e: a / rate for e, a in case.events.items()},
                        model.punctures(**inputs)))
    return signals


def law_signals(count: int, seed: int) -> list:
    """The synthetic law at ``count`` random inputs, 1 kHz, no prior."""
    rng = np.random.default_rng(seed)
    signals = []
    for _ in range(count):
        rate, diameter = (rng.uniform(*synthetic.RANGES[synthetic.RATE]),
                          rng.uniform(*synthetic.RANGES[synthetic.DIAMETER]))
        depth = np.arange(0.0, synthetic.DEPTH, rate / SAMPLE_RATE)
        truth = {e: a / rate for e, a in synthetic.punctures(rate, diameter).items()}
        signals.append((depth / rate, depth, synthetic.needle_force(depth, rate, diameter), truth, None))
    return signals


def report(label: str, result: dict) -> None:
    print(f"{label}: {result['trials']} realizations, false alarms in the contact stage {result['false_alarms']}")
    for layer in LAYERS:
        lat = 1000.0 * result["latencies"][layer]
        spread = (f"latency median {np.median(lat):.1f} ms, 95th percentile {np.percentile(lat, 95):.1f} ms, "
                  f"range {lat.min():.1f} to {lat.max():.1f} ms") if lat.size else "never reported"
        print(f"  {layer}: detected within 10 ms in {100 * result['detected'][layer]:.1f}% ({spread})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/validation-surrogate"),
                        help="folder of validation/surrogate.py's study and surrogate")
    parser.add_argument("--realizations", type=int, default=100, help="noise realizations per signal")
    arguments = parser.parse_args()
    families = {"law (10 inputs, no prior)": law_signals(10, seed=1)}
    if (arguments.out / "surrogate.npz").is_file():
        families["FE held-out cases (surrogate prior)"] = fe_signals(arguments.out)
    else:
        print(f"no {arguments.out / 'surrogate.npz'}: run validation/surrogate.py first for the FE signals")
    for family, signals in families.items():
        for k, (sensor, noise) in enumerate(SENSORS.items()):
            report(f"{family}, {sensor}", statistics(signals, noise, arguments.realizations, seed=k))


if __name__ == "__main__":
    main()
