"""A results folder belongs to one run: locked while in use, an earlier run refused or cleared, bad paths one line."""

import signal
import subprocess
import sys
import time

import pytest

from corneasim.errors import InputError
from corneasim.output._results_folder import LOCK_NAME, ResultsFolder, run_files


def _earlier_run(folder):
    folder.mkdir(parents=True, exist_ok=True)
    for name in ("scenario.toml", "history.csv", "summary.json", "checkpoint.npz"):
        (folder / name).write_text("earlier")
    for name in ("fields/fields.pvd", "fields/fields_0003.vtu", "plots/force.png", "fields/.fields_0004.vtu.tmp"):
        (folder / name).parent.mkdir(exist_ok=True)
        (folder / name).write_text("earlier")


def test_a_second_claim_of_a_folder_in_use_is_refused_until_it_is_released(tmp_path):
    first = ResultsFolder.claim(tmp_path / "run")
    with pytest.raises(InputError, match="in use by another run") as caught:
        ResultsFolder.claim(tmp_path / "run", resume=True)
    assert "\n" not in str(caught.value)
    first.release()
    ResultsFolder.claim(tmp_path / "run", resume=True).release()


def test_the_lock_goes_with_a_killed_process(tmp_path):
    code = ("import sys, time; from corneasim.output._results_folder import ResultsFolder; "
            "held = ResultsFolder.claim(sys.argv[1]); print('locked', flush=True); time.sleep(60)")
    holder = subprocess.Popen([sys.executable, "-c", code, str(tmp_path)], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "locked"
        with pytest.raises(InputError, match=rf"in use by another run \(process {holder.pid}\)"):
            ResultsFolder.claim(tmp_path, resume=True)
    finally:
        holder.send_signal(signal.SIGKILL)
        holder.wait(timeout=30)
    deadline = time.monotonic() + 10
    while True:  # the kernel drops the lock when the process is gone
        try:
            ResultsFolder.claim(tmp_path, resume=True).release()
            break
        except InputError:
            assert time.monotonic() < deadline
            time.sleep(0.05)


def test_a_folder_of_an_earlier_run_is_refused_naming_overwrite(tmp_path):
    _earlier_run(tmp_path / "run")
    with pytest.raises(InputError, match="--overwrite"):
        ResultsFolder.claim(tmp_path / "run")
    assert (tmp_path / "run" / "summary.json").read_text() == "earlier"  # nothing touched
    ResultsFolder.claim(tmp_path / "run", resume=True).release()  # a resumed run keeps them


def test_overwrite_clears_only_what_a_run_writes(tmp_path):
    folder = tmp_path / "run"
    _earlier_run(folder)
    (folder / "notes.md").write_text("mine")
    (folder / "plots" / "sketch.txt").write_text("mine")
    ResultsFolder.claim(folder, overwrite=True).release()
    assert run_files(folder) == []
    assert (folder / "notes.md").read_text() == "mine" and (folder / "plots" / "sketch.txt").read_text() == "mine"
    assert (folder / LOCK_NAME).exists()


def test_a_folder_with_only_foreign_files_or_nothing_is_accepted(tmp_path):
    (tmp_path / "mine.txt").write_text("mine")
    ResultsFolder.claim(tmp_path).release()
    ResultsFolder.claim(tmp_path / "new" / "deeper").release()
    assert (tmp_path / "new" / "deeper").is_dir()


def test_paths_that_cannot_be_a_results_folder_are_one_line(tmp_path):
    (tmp_path / "afile").write_text("x")
    for path, expected in ((tmp_path / "afile", "is a file"), (tmp_path / "afile" / "sub" / "run", "is a file")):
        with pytest.raises(InputError, match=expected) as caught:
            ResultsFolder.claim(path)
        assert "\n" not in str(caught.value)
    assert (tmp_path / "afile").read_text() == "x"
