"""One study case run in this process (no Dask cluster): its folder and its scenario.

Dask cannot stop a case it cancels (after a Ctrl-C of the study): the earlier attempt runs on
while the resumed study starts the case again, perhaps on another worker. The truths: the new
attempt completes and its folder holds its own run; an attempt that a newer one has overtaken
leaves nothing behind. A study's ``unset`` keys take their defaults in the scenario each case
records.
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest

from corneasim.data import read_table
from corneasim.errors import InputError
from corneasim.scenarios import load_scenario
from corneasim.studies import case
from corneasim.studies.runner import Plan

PUNCH = Path(__file__).resolve().parents[1] / "examples" / "flat_punch" / "flat_punch.toml"
OVERRIDES = ["solver.end_time=0.002", "solver.field_count=0"]
OUTPUTS = {"base": "reactions.base_force_N", "steps": "run.steps"}


def test_an_earlier_attempt_writing_into_the_case_folder_does_not_disturb_a_new_one(tmp_path, monkeypatch):
    folder = tmp_path / "cases" / "c0000"
    run_here = case._run_here

    def earlier_attempt_writes_meanwhile(scenario, overrides, unset, out, plots):
        folder.mkdir(parents=True, exist_ok=True)
        (folder / "history.csv").write_text("time_s,force_N\n0.0,0.0\n")
        (folder / "summary.json").write_text('{"status": "running"}')
        return run_here(scenario, overrides, unset, out, plots)

    monkeypatch.setattr(case, "_run_here", earlier_attempt_writes_meanwhile)
    row = case.run_case(str(PUNCH), OVERRIDES, str(folder), OUTPUTS)
    assert row["status"] == "completed", row["error"]
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["status"] == "completed" and row["steps"] == summary["run"]["steps"] > 1
    assert row["base"] == summary["reactions"]["base_force_N"]
    history = read_table(folder / "history.csv")
    assert len(history["time_s"]) > 1 and np.all(np.diff(history["time_s"]) > 0)
    assert sorted(path.name for path in folder.parent.iterdir()) == ["c0000"]


def test_an_attempt_overtaken_by_a_newer_one_leaves_nothing(tmp_path, monkeypatch):
    folder = tmp_path / "cases" / "c0000"
    run_here = case._run_here

    def newer_attempt_starts_meanwhile(scenario, overrides, unset, out, plots):
        (folder.parent / ".c0000.newest").write_text(".c0000.1-2")
        return run_here(scenario, overrides, unset, out, plots)

    monkeypatch.setattr(case, "_run_here", newer_attempt_starts_meanwhile)
    row = case.run_case(str(PUNCH), OVERRIDES, str(folder), OUTPUTS)
    assert row["status"] == "completed", row["error"]
    assert sorted(path.name for path in folder.parent.iterdir()) == [".c0000.newest"]


def test_a_case_writes_its_plots_and_report_only_when_asked(tmp_path):
    for plots in (False, True):
        folder = tmp_path / f"plots-{plots}" / "c0000"
        row = case.run_case(str(PUNCH), OVERRIDES, str(folder), OUTPUTS, plots=plots)
        assert row["status"] == "completed", row["error"]
        assert (folder / "summary.json").is_file() and (folder / "history.csv").is_file()
        assert (folder / "report.html").is_file() == plots and (folder / "plots").is_dir() == plots


def test_a_study_passes_case_plots_to_its_cases(tmp_path):
    spec = {"scenario": str(PUNCH), "overrides": {"solver.end_time": 0.002}, "design": {"kind": "list", "cases": [{}]},
            "outputs": OUTPUTS}
    for value in (None, True):
        plan = Plan(spec if value is None else {**spec, "case_plots": value})
        function, arguments = plan.job(plan.cases()[0], tmp_path)
        assert function is case.run_case and arguments[-1] is bool(value)


def test_the_attempt_that_takes_the_folder_removes_those_of_earlier_killed_workers(tmp_path):
    """A worker killed mid-case leaves its hidden attempt folder; the next attempt to finish removes
    it, and leaves one started after it alone."""
    cases = tmp_path / "cases"
    killed, later = cases / ".c0000.41-1", cases / f".c0000.42-{2 ** 62}"
    for stale in (killed, later):
        stale.mkdir(parents=True)
        (stale / "history.csv").write_text("time_s\n0.0\n")
    row = case.run_case(str(PUNCH), OVERRIDES, str(cases / "c0000"), OUTPUTS)
    assert row["status"] == "completed", row["error"]
    assert sorted(path.name for path in cases.iterdir()) == [later.name, "c0000"]


def study(**fields) -> dict:
    return {"scenario": str(PUNCH), "overrides": {"solver.end_time": 0.001, "solver.field_count": 0,
                                                  "instrument.contact.damping_ratio": 0.3},
            "parameters": {"instrument.motion.insertion.rate": [0.5]}, "outputs": OUTPUTS, **fields}


def test_a_study_removes_its_unset_keys_from_every_case(tmp_path):
    """The flat punch's damping ratio set to 0.3 by the overrides, then unset: its default (0.05)."""
    default = type(load_scenario(str(PUNCH))[0].instrument.contact).model_fields["damping_ratio"].default
    plan = Plan(study(unset=["instrument.contact.damping_ratio"]))
    [first] = plan.cases()
    assert plan.invalid(first) is None
    function, arguments = plan.job(first, tmp_path)
    row = function(*arguments)
    assert row["status"] == "completed", row["error"]
    recorded = tomllib.loads((tmp_path / "cases" / first.name / "scenario.toml").read_text())
    assert recorded["instrument"]["contact"]["damping_ratio"] == default != 0.3


def test_a_study_refuses_an_unknown_unset_key_and_a_parameter_it_unsets():
    with pytest.raises(InputError, match=r"--unset 'instrument.contact.damping_rate'.*'instrument.contact' has: "):
        Plan(study(unset=["instrument.contact.damping_rate"]))
    with pytest.raises(InputError, match=r"parameters.instrument.motion.insertion.rate: also in unset"):
        Plan(study(unset=["instrument.motion.insertion.rate"]))
