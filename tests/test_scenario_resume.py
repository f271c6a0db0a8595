"""Ctrl-C during ``corneasim run`` keeps the results and a checkpoint; ``--resume`` finishes the run
with the same history as an uninterrupted run."""

import json
import signal
import subprocess
import time

import numpy as np

from cli_helpers import command

from corneasim.data import read_table

FAST = ["--preset", "coarse", "--speed", "5",
        "--set", "preload.duration=0.02", "--set", "preload.damping=400",
        "--set", "materials.epithelium.failure_limit=0.25", "--set", "materials.stroma.failure_limit=0.12",
        "--set", "solver.field_count=2", "--set", "solver.checkpoint_every=2000", "--no-progress",
        # pinned so that checkpoint step 2000 still falls after the first punctures whatever the
        # scenario's calibrated stroma and mass-scaling step (docs/calibration.md)
        "--set", "materials.stroma.material=cornea-in-vivo", "--set", "materials.stroma.fracture_energy=0.0",
        "--set", "solver.target_time_step=2e-5"]




def test_interrupt_then_resume_equals_uninterrupted_run(tmp_path):
    whole = tmp_path / "whole"
    assert subprocess.run(command("run", "needle", *FAST, "--out", str(whole)), capture_output=True,
                          timeout=600).returncode == 0
    parted = tmp_path / "parted"
    process = subprocess.Popen(command("run", "needle", *FAST, "--out", str(parted)),
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    while not (parted / "checkpoint.npz").exists() and process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    process.send_signal(signal.SIGINT)
    _, stderr = process.communicate(timeout=300)
    if process.returncode == 0:
        return  # the run finished before the signal arrived: nothing to resume on this machine
    assert process.returncode == 130, stderr
    assert "--resume" in stderr and (parted / "summary.json").exists()
    interrupted = json.loads((parted / "summary.json").read_text())
    assert interrupted["status"] == "interrupted"
    assert interrupted["punctures"], "the checkpoint should fall after the first punctures (step 2000)"
    resumed = subprocess.run(command("run", "--resume", str(parted), "--no-progress"), capture_output=True,
                             text=True, timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    a, b = read_table(whole / "history.csv"), read_table(parted / "history.csv")
    assert list(a) == list(b)
    assert a["time_s"].shape == b["time_s"].shape
    for column in ("time_s", "depth_mm", "force_N", "internal_energy_mJ", "deleted_elements"):
        np.testing.assert_allclose(b[column], a[column], rtol=1e-9, atol=1e-12, err_msg=column)
    whole_summary = json.loads((whole / "summary.json").read_text())
    parted_summary = json.loads((parted / "summary.json").read_text())
    assert parted_summary["punctures"] == whole_summary["punctures"]
    assert (parted / "deletions.csv").read_text() == (whole / "deletions.csv").read_text()
