"""Puncture events that some cases of a study lack (a whole cornea not punctured by the run's
end): left out of the model by default and said so, or modelled on request without those cases."""

import numpy as np
import pytest

from cli_helpers import corneasim_here

from corneasim.errors import InputError
from corneasim.surrogate import build_surrogate, synthetic

DEPTH = 0.82
"""Insertion depth of the study, mm: inside the law's whole-cornea punctures (0.71-0.91 mm)."""
COUNT = 16


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    return synthetic.write_study(tmp_path_factory.mktemp("study"), count=COUNT, samples=250, depth=DEPTH)


def lacking_cornea(study):
    """The cases whose law puts the whole cornea's puncture past the insertion depth."""
    import pandas as pd

    table = pd.read_csv(study / "results.csv")
    return sorted(row.case for row in table.itertuples()
                  if synthetic.punctures(row[2], row[3])["cornea"] > DEPTH)


def test_the_study_has_cases_on_both_sides_of_the_depth(study):
    assert 3 <= len(lacking_cornea(study)) <= COUNT - 6


def test_by_default_an_event_some_cases_lack_is_named_and_not_modelled(study):
    model = build_surrogate(study, hold_out=0.0)
    meta = model.metadata
    assert meta["events"] == ["epithelium", "stroma"]
    assert meta["partial_events"] == {"cornea": lacking_cornea(study)}
    assert meta["left_out_cases"] == []
    assert len(meta["training_cases"]) == COUNT


def test_asked_for_the_event_is_modelled_without_the_cases_that_lack_it(study):
    model = build_surrogate(study, hold_out=0.0, events=["cornea", "epithelium", "stroma"])
    meta = model.metadata
    assert meta["events"] == ["epithelium", "stroma", "cornea"]
    lacking = lacking_cornea(study)
    assert [item["case"] for item in meta["left_out_cases"]] == lacking
    assert all(item["reason"] == f"no cornea puncture by depth_mm {DEPTH:.4g}" for item in meta["left_out_cases"])
    assert sorted(meta["training_cases"]) == sorted(set(f"c{n:04d}" for n in range(COUNT)) - set(lacking))
    rate, diameter = 2.0, 0.17  # the law's whole cornea at 0.754 mm, inside the depth
    centre, low, high = model.punctures(rate=rate, diameter=diameter)["cornea"]
    truth = synthetic.punctures(rate, diameter)["cornea"]
    assert abs(centre - truth) < 0.01 and low <= truth <= high


def test_an_unknown_event_is_one_line(study):
    with pytest.raises(InputError, match="events: unknown event 'lens'; expected some of epithelium, stroma, cornea"):
        build_surrogate(study, events=["epithelium", "lens"])


def test_an_event_no_case_has_leaves_too_few_cases(tmp_path):
    shallow = synthetic.write_study(tmp_path / "shallow", count=6, samples=100, depth=0.5)
    with pytest.raises(InputError, match="0 completed case"):
        build_surrogate(shallow, events=["cornea"])


def test_the_command_line_says_what_is_left_out(study, tmp_path):
    default = corneasim_here("surrogate", "build", str(study), "--out", str(tmp_path / "a.npz"), "--hold-out", "0")
    assert default.returncode == 0, default.stderr
    lacking = lacking_cornea(study)
    assert (f"not modelled: cornea, missing from {len(lacking)} case(s) ({', '.join(lacking[:3])}, ...); "
            "--events epithelium,stroma,cornea models it without them") in default.stdout
    asked = corneasim_here("surrogate", "build", str(study), "--out", str(tmp_path / "b.npz"), "--hold-out", "0",
                           "--events", "epithelium,stroma,cornea")
    assert asked.returncode == 0, asked.stderr
    assert asked.stdout.count("left out: ") == len(lacking)
    assert f"left out: {lacking[0]} (no cornea puncture by depth_mm {DEPTH:.4g})" in asked.stdout
    assert "punctures: epithelium, stroma, cornea" in asked.stdout
    checked = corneasim_here("surrogate", "check", str(tmp_path / "b.npz"))
    assert checked.stdout.count("left out: ") == len(lacking)
    bad = corneasim_here("surrogate", "build", str(study), "--out", str(tmp_path / "c.npz"), "--events", "lens")
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "unknown event 'lens'" in bad.stderr
    assert not (tmp_path / "c.npz").exists()
    assert np.load(tmp_path / "b.npz")["event_reference"].shape == (3,)
