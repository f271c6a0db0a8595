"""A trephine study (F_z and F_c against time) through the same surrogate: two channels, one event."""

import json

import numpy as np

from corneasim.surrogate import build_surrogate

SPEED = "instrument.motion.insertion.rate"


def law(time, speed):
    """F_z rises until the cut-through at 0.5 / speed s, then falls to about a tenth; F_c grows linearly (N)."""
    through = 0.5 / speed
    fz = np.where(time < through, 0.3 * speed * time / 0.05, 1.5 * speed)
    fc = 0.02 + 0.1 * speed * time
    return fz, fc, through


def write_study(folder, speeds):
    folder.mkdir()
    (folder / "study.toml").write_text(f'scenario = "trephine"\n[parameters]\n"{SPEED}" = {list(speeds)}\n'
                                       '[outputs]\npeak = "peak_force_N"\n')
    rows = [f"case,{SPEED},status,error,wall_s,worker"]
    time = np.linspace(0.0, 60.0, 301)
    for n, speed in enumerate(speeds):
        case = folder / "cases" / f"c{n:04d}"
        case.mkdir(parents=True)
        fz, fc, through = law(time, speed)
        (case / "scenario.toml").write_text('kind = "trephine"\n')
        np.savetxt(case / "history.csv", np.c_[time, fz, fc], delimiter=",", header="time_s,fz_N,fc_N", comments="")
        (case / "summary.json").write_text(json.dumps({"punctures": [{"event": "cornea", "time_s": through}]}))
        rows.append(f"c{n:04d},{speed!r},completed,,0.0,test")
    (folder / "results.csv").write_text("\n".join(rows) + "\n")
    return folder


def test_trephine_channels_and_cut_through(tmp_path):
    study = write_study(tmp_path / "study", [0.01, 0.0125, 0.015, 0.0175, 0.02, 0.0225, 0.025, 0.0275, 0.03])
    model = build_surrogate(study, hold_out=0.0)
    assert model.channels == ["fz_N", "fc_N"] and model.events == ["cornea"]
    assert model.metadata["abscissa"] == {"name": "time_s", "unit": "s", "max": 60.0}
    time = np.linspace(0.0, 60.0, 121)
    fz, fc, through = law(time, 0.021)
    centre, low, high = model.punctures(rate=0.021)["cornea"]
    assert abs(centre - through) < 0.02 * through and low <= through <= high
    for channel, truth in (("fz_N", fz), ("fc_N", fc)):
        mean, lower, upper = model.predict(time, channel, rate=0.021)
        assert np.sqrt(np.mean((mean - truth) ** 2)) < 0.05 * truth.max()
        assert np.mean((truth >= lower) & (truth <= upper)) >= 0.9
