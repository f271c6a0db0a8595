"""SIGTERM and SIGHUP stop a run as Ctrl-C does; a resume repairs a torn row and matches an uninterrupted run
byte for byte; any crash is a failed run with exit 1."""

import json
import os
import signal
import subprocess
import time

import numpy as np
import pytest

from cli_helpers import command

from corneasim.cli.main import main
from corneasim.scenarios._stopping import StopRequest, stop_signals_interrupt

SHORT = ["needle", "--preset", "coarse", "--speed", "5", "--no-progress",
         "--set", "preload.duration=0.02", "--set", "preload.damping=400", "--set", "solver.end_time=0.1",
         "--set", "solver.field_count=2", "--set", "solver.checkpoint_every=200"]


def test_the_first_stop_signal_is_a_flag_and_the_second_stops_at_once():
    request = StopRequest()
    before = signal.getsignal(signal.SIGTERM)
    with request.installed():
        os.kill(os.getpid(), signal.SIGTERM)
        assert request.requested == "SIGTERM" and not request.forced
        with pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGHUP)
        assert request.forced
    assert signal.getsignal(signal.SIGTERM) is before and "SIGTERM" in request.reason()


def test_outside_the_time_loop_sigterm_and_sighup_interrupt_like_ctrl_c():
    previous = {number: signal.getsignal(number) for number in (signal.SIGTERM, signal.SIGHUP)}
    try:
        stop_signals_interrupt()
        for number in previous:
            with pytest.raises(KeyboardInterrupt):
                os.kill(os.getpid(), number)
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)


def test_sigterm_checkpoints_and_a_resume_over_a_torn_row_matches_an_uninterrupted_run(tmp_path):
    whole = tmp_path / "whole"
    for _ in range(2):  # a run that compiled its kernels differs in the last digits from one that loaded them
        finished = subprocess.run(command("run", *SHORT, "--out", str(whole), "--overwrite"), capture_output=True,
                                  text=True, timeout=600)
        assert finished.returncode == 0, finished.stderr
        if not json.loads((whole / "summary.json").read_text())["run"]["platform"]["kernels_compiled_in_run"]:
            break
    parted = tmp_path / "parted"
    process = subprocess.Popen(command("run", *SHORT, "--out", str(parted)), stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    while not (parted / "preload.npz").exists() and process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    process.send_signal(signal.SIGTERM)
    _, stderr = process.communicate(timeout=300)
    if process.returncode == 0:
        pytest.skip("the run ended before SIGTERM arrived")
    assert process.returncode == 130, stderr
    assert f"corneasim run --resume {parted}" in stderr and stderr.count("\n") == 1, stderr
    summary = json.loads((parted / "summary.json").read_text())
    assert summary["status"] == "interrupted" and "SIGTERM" in summary["error"]
    with (parted / "history.csv").open("ab") as handle:
        handle.write(b"0.0")  # what SIGKILL leaves: a row cut inside its first field
    resumed = subprocess.run(command("run", "--resume", str(parted), "--no-progress"), capture_output=True,
                             text=True, timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    for name in ("history.csv", "deletions.csv"):
        assert (parted / name).read_bytes() == (whole / name).read_bytes(), name
    assert b"\r" not in (parted / "history.csv").read_bytes()
    summaries = [json.loads((folder / "summary.json").read_text()) for folder in (whole, parted)]
    assert summaries[1]["status"] == "completed"
    assert summaries[1]["run"]["preload"] == summaries[0]["run"]["preload"] is not None


def test_a_crash_inside_the_run_is_a_failed_run_exit_1(tmp_path, monkeypatch, capsys):
    import corneasim.scenarios._runner as runner

    def crashing_run(*arguments, **options):
        raise np.linalg.LinAlgError("Array must not contain infs or NaNs.")
        yield  # a generator, as the solver's run

    monkeypatch.setattr(runner, "run", crashing_run)
    out = tmp_path / "out"
    with pytest.raises(SystemExit) as exit_:
        main(["run", "needle", "--preset", "coarse", "--no-progress", "--set", "preload.duration=0.001",
              "--out", str(out)])
    err = capsys.readouterr().err
    assert exit_.value.code == 1 and err.count("\n") == 1 and "LinAlgError" in err, err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "failed" and summary["error"].startswith("LinAlgError: Array must not")
