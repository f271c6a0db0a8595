"""``examples/robot_force_reference.py`` at tiny size: the robot stops at the whole-cornea puncture."""

import runpy
from pathlib import Path

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "robot_force_reference.py"


def test_robot_stops_within_10_ms_of_the_whole_cornea_puncture(tmp_path):
    module = runpy.run_path(str(EXAMPLE))
    result = module["main"](tiny=True, out=tmp_path / "robot.png")
    assert (tmp_path / "robot.png").stat().st_size > 0
    assert [d.event for d in result["detections"]] == ["epithelium", "stroma", "cornea"]
    lag = result["stop_depth"] - result["truth"]["cornea"]          # mm
    assert 0.0 <= lag <= 0.010 * result["rate"]                   # within 10 ms of insertion
    assert result["inside_band"] >= 0.9
