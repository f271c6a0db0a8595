"""The plain (non-terminal) progress lines measure the stage from its first frame."""

from types import SimpleNamespace

from corneasim.output._progress import track


def test_plain_progress_counts_from_the_stage_start(capsys, monkeypatch):
    clock = iter(range(0, 1000, 10))
    monkeypatch.setattr("corneasim.output._progress.wallclock.monotonic", lambda: float(next(clock)))
    frames = [SimpleNamespace(time=t) for t in (0.5, 0.6, 0.75, 1.0)]
    assert list(track(frames, end_time=1.0, description="stage", plain_interval=1.0)) == frames
    lines = capsys.readouterr().err.splitlines()
    assert lines[0].startswith("stage:  20.0% of the stage")
    assert lines[0].endswith("about 40 s left")
