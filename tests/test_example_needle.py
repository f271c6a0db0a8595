"""The Python API and ``examples/needle_insertion.py`` at coarse size."""

import runpy
from pathlib import Path

import numpy as np

import corneasim

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "needle_insertion.py"
FAST = ["mesh.preset=coarse", "preload.duration=0.02", "preload.damping=400",
        "materials.epithelium.failure_limit=0.25", "materials.stroma.failure_limit=0.12"]


def test_run_scenario_returns_arrays_and_writes_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = corneasim.run_scenario("needle", FAST + ["instrument.motion.insertion.rate=5", "solver.end_time=0.1"])
    assert list(tmp_path.iterdir()) == []
    history = result.history
    assert isinstance(history["force_N"], np.ndarray)
    assert history["depth_mm"][-1] == np.float64(history["depth_mm"][-1])
    assert abs(history["depth_mm"][-1] - 0.5) < 1e-3
    assert result.summary["peak_force_N"] == history["force_N"].max()
    assert result.summary["status"] == "completed"


def test_example_script_runs(monkeypatch, capsys):
    module = runpy.run_path(str(EXAMPLE))
    monkeypatch.setattr(corneasim, "run_scenario",
                        lambda name, overrides, **kw: _fast(name, overrides))
    results = module["main"]("coarse")
    assert set(results) == {1.0, 5.0}
    assert "5 mm/s" in capsys.readouterr().out


def _fast(name, overrides):
    """The example's call with its depth cut to 0.1 mm and the preload shortened (test time)."""
    speed = float(next(o for o in overrides if o.startswith("instrument.motion.insertion.rate=")).split("=")[1])
    return _ORIGINAL(name, [o for o in overrides if not o.startswith("solver.end_time")]
                     + FAST + [f"solver.end_time={0.1 / speed}"])


_ORIGINAL = corneasim.run_scenario
