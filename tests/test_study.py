"""Studies end to end on a 2-worker Dask LocalCluster: the flat-punch example, a few ms of it.

The truths: every row's outputs equal what the case's own results folder says (summary.json,
history.csv read back independently); a resumed study runs only what had not finished; a bad
value fails its case alone; a worker killed in the middle of a case costs nothing but time.
"""

from __future__ import annotations

import json
import os
import signal
import threading
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from corneasim.data import read_table
from corneasim.studies import study as run_study
from corneasim.studies.engine import connect
from corneasim.studies.outputs import check_path

PUNCH = Path(__file__).resolve().parents[1] / "examples" / "flat_punch" / "flat_punch.toml"
AT = np.linspace(0.0, 0.001, 11)


def spec(end_time=0.002, **parameters):
    return {"scenario": str(PUNCH), "overrides": {"solver.end_time": end_time, "solver.field_count": 0},
            "design": {"kind": "grid"},
            "parameters": parameters or {"instrument.motion.insertion.rate": [0.5, 1.0],
                                         "instrument.shape.diameter": [0.8, 1.0]},
            "outputs": {"base": "reactions.base_force_N", "steps": "run.steps",
                        "force": {"curve": "force_N", "x": "depth_mm", "at": {"low": 0.0, "high": 0.001, "steps": 11}}}}


def leaf_paths(tree, prefix=""):
    if isinstance(tree, dict):
        return [p for key, value in tree.items() for p in leaf_paths(value, f"{prefix}{key}.")]
    if isinstance(tree, list) and tree and isinstance(tree[0], dict):
        return [p for i, value in enumerate(tree) for p in leaf_paths(value, f"{prefix}{i}.")]
    return [prefix[:-1]]


@pytest.fixture(scope="module")
def client():
    with connect(workers=2) as engine:
        yield engine


def test_a_four_case_grid_runs_on_two_workers(client, tmp_path):
    table = run_study(spec(), out=tmp_path, client=client)
    assert list(table.columns) == ["case", "instrument.motion.insertion.rate", "instrument.shape.diameter",
                                   "base", "steps", "force", "status", "error", "wall_s", "worker"]
    assert list(table["case"]) == ["c0000", "c0001", "c0002", "c0003"]
    assert (table["status"] == "completed").all() and (table["error"] == "").all()
    assert list(table["instrument.shape.diameter"]) == [0.8, 1.0, 0.8, 1.0]
    assert table["worker"].str.startswith("tcp://").all() and (table["wall_s"] > 0).all()
    for _, row in table.iterrows():
        folder = tmp_path / "cases" / row["case"]
        summary = json.loads((folder / "summary.json").read_text())
        assert row["base"] == summary["reactions"]["base_force_N"]
        assert row["steps"] == summary["run"]["steps"]
        history = read_table(folder / "history.csv")
        np.testing.assert_allclose(row["force"], np.interp(AT, history["depth_mm"], history["force_N"]), rtol=1e-12)
        assert f"rate = {row['instrument.motion.insertion.rate']}" in (folder / "scenario.toml").read_text()
        for path in leaf_paths(summary):  # the output check accepts every entry a real summary has
            check_path(path, "general", "outputs.x")
    back = pd.read_parquet(tmp_path / "results.parquet")
    assert back["base"].tolist() == table["base"].tolist()
    csv = pd.read_csv(tmp_path / "results.csv")
    assert csv["case"].tolist() == table["case"].tolist()
    assert json.loads(csv["force"][0])[-1] == pytest.approx(table["force"][0][-1])
    assert (tmp_path / "study.toml").exists()
    threads = client.run(lambda: os.environ.get("NUMBA_NUM_THREADS"))
    assert set(threads.values()) == {str(max(1, os.cpu_count() // 2))}


def test_a_bad_value_fails_its_case_alone(client, tmp_path):
    """(On the cluster by its scheduler's address, as ``--scheduler`` gives it.)"""
    table = run_study(spec(**{"instrument.start_gap": [0.0005, -1.0]}), out=tmp_path,
                      scheduler=client.scheduler.address)
    failed = table[table["status"] == "failed"]
    assert failed["case"].tolist() == ["c0001"]
    assert "instrument.start_gap" in failed["error"].iloc[0] and "greater than or equal to 0" in failed["error"].iloc[0]
    assert table.loc[0, "status"] == "completed" and np.isfinite(table.loc[0, "base"])
    assert np.isnan(failed["base"].iloc[0])


def test_a_worker_killed_in_a_case_hands_it_to_another(client, tmp_path):
    """The first case to start has its worker process killed (SIGKILL) while it runs."""
    killed = {}

    def kill_first_runner():
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and not killed:
            processing = {w: keys for w, keys in client.processing().items() if keys}
            if processing and any((tmp_path / "cases").glob("c*/scenario.toml")):
                worker = sorted(processing)[0]
                pid = client.run(os.getpid, workers=[worker])[worker]
                os.kill(pid, signal.SIGKILL)
                killed[worker] = pid
            time.sleep(0.02)

    killer = threading.Thread(target=kill_first_runner)
    killer.start()
    table = run_study(spec(end_time=0.005, **{"instrument.motion.insertion.rate": [0.5, 0.6, 0.7]}),
                      out=tmp_path, client=client)
    killer.join()
    assert killed
    assert (table["status"] == "completed").all(), table["error"].tolist()
    assert not set(table["worker"]) & set(killed)


def test_an_interrupted_study_resumes_without_rerunning_finished_cases(client, tmp_path, monkeypatch):
    """Ctrl-C (KeyboardInterrupt) right after the first case's row is written; the same study again."""
    from corneasim.studies.runner import CaseProgress

    rates = {"instrument.motion.insertion.rate": [0.5, 0.6, 0.7, 0.8, 0.9, 1.0]}

    def interrupt(self, status):
        raise KeyboardInterrupt

    monkeypatch.setattr(CaseProgress, "advance", interrupt)
    with pytest.raises(KeyboardInterrupt):
        run_study(spec(**rates), out=tmp_path, client=client)
    monkeypatch.undo()
    first = pd.read_parquet(tmp_path / "results.parquet")
    finished = first[first["status"] == "completed"]
    assert len(finished) == 1
    assert set(first["status"]) == {"completed", "interrupted"} and len(first) == 6
    stamps = {case: (tmp_path / "cases" / case / "summary.json").stat().st_mtime_ns for case in finished["case"]}
    second = run_study(spec(**rates), out=tmp_path, client=client)
    assert (second["status"] == "completed").all() and len(second) == 6
    for case, stamp in stamps.items():
        assert (tmp_path / "cases" / case / "summary.json").stat().st_mtime_ns == stamp
        assert second.set_index("case").loc[case, "wall_s"] == finished.set_index("case").loc[case, "wall_s"]


def test_calibrate_records_every_candidate_and_reports_the_best(client, tmp_path):
    """Two batches of two candidates; the RMSE column is recomputed from each case's history.csv."""
    import tomllib

    from corneasim.studies.calibrate import calibrate

    data = tmp_path / "measured.csv"
    depth = np.linspace(0.0002, 0.001, 9)
    force = 2.0 * np.maximum(depth - 0.0005, 0.0)  # N: a 2 N/mm punch touching at 0.5 um
    data.write_text("depth_mm,force_N\n" + "".join(f"{d:.17g},{f:.17g}\n" for d, f in zip(depth, force)))
    study = spec(**{"instrument.start_gap": {"low": 0.0002, "high": 0.0008}})
    study["design"] = {"kind": "grid"}
    study["calibration"] = {"curve": "force", "dataset": str(data), "x_column": "depth_mm",
                            "y_column": "force_N", "evaluations": 4, "batch": 2}
    result = calibrate(study, tmp_path / "out", client=client)
    table = result.table
    assert len(table) == 4 and (table["status"] == "completed").all()
    for _, row in table.iterrows():
        history = read_table(tmp_path / "out" / "cases" / row["case"] / "history.csv")
        curve = np.interp(AT, history["depth_mm"], history["force_N"])
        expected = np.sqrt(np.mean((np.interp(depth, AT, curve) - force) ** 2))
        assert row["rmse"] == pytest.approx(expected, rel=1e-9)
    best = table.loc[table["rmse"].idxmin()]
    assert result.case == best["case"] and result.rmse == best["rmse"]
    assert tomllib.loads(result.toml)["calibrated"]["instrument.start_gap"] == pytest.approx(
        best["instrument.start_gap"], abs=1e-6)
    assert 0.0002 <= result.values["instrument.start_gap"] <= 0.0008
    assert (tmp_path / "out" / "calibration.png").stat().st_size > 0
