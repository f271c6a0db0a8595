"""A robot inserting a needle under a force reference, stopped at the whole-cornea puncture.

A controller samples the needle's force at 1 kHz. Before the insertion it asks the surrogate
(``corneasim surrogate build``) for the expected force curve with its 95% band and for the
expected puncture depths at this insertion's inputs (rate, needle, cornea). At every sample it

1. compares the measured force with the band at the current depth (a force above the band
   warns of a stiffer eye or a blunt needle; below it, of an early tear);
2. feeds the sample to the causal :class:`~corneasim.surrogate.PunctureDetector`, whose prior
   is the surrogate's puncture bands;
3. stops the robot as soon as the whole cornea is punctured.

The "measured" force is a simulated one: a case's force history (an FE run of the study, not
used to fit the surrogate) plus the needle paper's Instron noise (0.4% of load and 0.5 mN),
fed sample by sample. The plot shows force, band and detections against depth.

Run it: ``python examples/robot_force_reference.py --study DIR`` (DIR: the folder of
``python validation/surrogate.py --out DIR``), or ``--tiny`` for a synthetic study with a
closed-form force law (a few seconds, no finite elements).
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np

from corneasim.surrogate import PunctureDetector, build_surrogate, load, synthetic
from corneasim.surrogate._study import read_study

SAMPLE_RATE = 1000.0       # Hz, the controller's loop
NOISE_N, NOISE_RELATIVE = 0.0005, 0.004   # N RMS and fraction of the load (Instron 5848, +-0.4%)


def insertion(model, case, seed: int = 0) -> dict:
    """Insert at the case's rate, sample by sample; stop at the whole-cornea puncture.

    Returns the depths (mm), measured forces (N), the band at each depth, the detections and
    the stop depth.
    """
    inputs = dict(zip(model.inputs, case.inputs))
    rate = inputs["instrument.motion.insertion.rate"]                      # mm/s
    maximum = min(model.metadata["abscissa"]["max"], case.abscissa[-1])
    depths = np.arange(0.0, maximum, rate / SAMPLE_RATE)                  # mm, one per sample
    mean, lower, upper = model.force(depths, **inputs)                     # the reference, once
    rng = np.random.default_rng(seed)
    detector = PunctureDetector(noise_N=NOISE_N, relative_noise=NOISE_RELATIVE, prior=model.punctures(**inputs))
    measured, outside = [], 0
    for k, depth in enumerate(depths):
        true_force = np.interp(depth, case.abscissa, case.forces["force_N"])
        force = true_force + NOISE_N * rng.standard_normal() + NOISE_RELATIVE * true_force * rng.standard_normal()
        measured.append(force)
        outside += not lower[k] <= force <= upper[k]
        detector.update(force, depth)
        if detector.finished:                                                # stop the robot
            break
    count = len(measured)
    return {"depth": depths[:count], "force": np.array(measured), "mean": mean[:count], "lower": lower[:count],
            "upper": upper[:count], "detections": detector.punctures, "stop_depth": depths[count - 1],
            "inside_band": 1.0 - outside / count, "truth": case.events, "rate": rate}


def plot(result: dict, path: Path) -> None:
    """Force, band and detections against depth."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(7, 4))
    axes.fill_between(result["depth"], result["lower"], result["upper"], color="tab:blue", alpha=0.25,
                      label="surrogate 95% band")
    axes.plot(result["depth"], result["mean"], color="tab:blue", label="surrogate mean")
    axes.plot(result["depth"], result["force"], color="black", lw=0.6, label="measured (simulated + noise)")
    for detection in result["detections"]:
        axes.axvline(detection.depth_mm, color="tab:red", ls="--", lw=0.8)
        axes.annotate(detection.event, (detection.depth_mm, axes.get_ylim()[1] * 0.95), rotation=90,
                      ha="right", va="top", fontsize=8, color="tab:red")
    axes.set_xlabel("depth (mm)")
    axes.set_ylabel("force (N)")
    axes.legend(loc="upper left", fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


def main(study: Path | None = None, tiny: bool = False, out: Path = Path("robot_force_reference.png")) -> dict:
    """Run the insertion on the first held-out case of ``study`` (or of a synthetic study)."""
    with tempfile.TemporaryDirectory() as scratch:
        if tiny:
            study = synthetic.write_study(Path(scratch) / "study", count=10, samples=300)
            model = build_surrogate(study, hold_out=0.2)
        else:
            model = load(study / "surrogate.npz")
        case = next(c for c in read_study(study).cases if c.name == model.metadata["held_out_cases"][0])
    result = insertion(model, case)
    plot(result, out)
    for detection in result["detections"]:
        lag = detection.depth_mm - result["truth"].get(detection.event, np.nan)
        print(f"{detection.event} detected at {detection.depth_mm:.3f} mm "
              f"({1000 * lag / result['rate']:+.1f} ms from the case's puncture)")
    print(f"robot stopped at {result['stop_depth']:.3f} mm; measured force inside the surrogate's band "
          f"at {100 * result['inside_band']:.0f}% of the samples; plot: {out}")
    return result


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description="A robot insertion stopped at the whole-cornea puncture.")
    parser.add_argument("--study", type=Path, help="folder of validation/surrogate.py (surrogate.npz and cases)")
    parser.add_argument("--tiny", action="store_true", help="a synthetic study instead (seconds, no FE)")
    parser.add_argument("--out", type=Path, default=Path("robot_force_reference.png"), help="plot file")
    arguments = parser.parse_args()
    if not arguments.tiny and arguments.study is None:
        parser.error("give --study DIR or --tiny")
    main(arguments.study, arguments.tiny, arguments.out)
