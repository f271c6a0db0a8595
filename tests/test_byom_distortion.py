"""The distortion check: warns and records where and when an element's corner Jacobian ratio drops.

Truth: one axisymmetric quad (1 <= r <= 2, 0 <= z <= 1 mm) whose corner (2, 1) is moved by
s (-0.6, -0.6) mm, all other nodes held, has the corner Jacobian ratios 1 - 1.2 s (that
corner) and 1 - 0.6 s (its neighbours): the smallest is 1 - 1.2 s, below 0.1 from s = 0.75,
-0.2 (folded) at s = 1.
"""

import numpy as np
import pytest

import corneasim
from corneasim.mesh import Mesh, write_mesh

from byom_helpers import SUBSTRATE


def _scenario(tmp_path):
    mesh = Mesh(np.array([[1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0]]), np.array([[0, 1, 2, 3]]), "quad",
                np.zeros(1, dtype=np.int64), ["solid"], axisymmetric=True,
                node_sets={"held": np.array([0, 1, 3]), "corner": np.array([2])})
    write_mesh(mesh, tmp_path / "quad.inp")
    moves = "\n".join(f"""[[constraints]]
node_set = "corner"
prescribed = "displacement"
component = "{c}"
value = -0.6
amplitude = {{ type = "tabular", times = [0.0, 1.0e-3], values = [0.0, 1.0] }}""" for c in "rz")
    path = tmp_path / "fold.toml"
    path.write_text(f"""
name = "fold"
[mesh]
file = "quad.inp"
[materials]
solid = {{ material = "{SUBSTRATE.as_posix()}" }}
[[constraints]]
node_set = "held"
fixed = "rz"
{moves}
[solver]
end_time = 1.0e-3
time_step = 1.0e-6
history_every = 10
field_count = 0
""")
    return path


def test_folding_element_is_reported_with_place_and_time(tmp_path):
    result = corneasim.run_scenario(_scenario(tmp_path))
    history, summary = result.history, result.summary
    s = history["time_s"] / 1.0e-3
    np.testing.assert_allclose(history["min_corner_jacobian_ratio"], 1.0 - 1.2 * s, atol=1e-9)
    report = summary["distortion"]
    assert report["threshold"] == 0.1
    first, worst = report["first"], report["worst"]
    assert first["element"] == 0 and first["block"] == "solid"
    assert 0.75e-3 <= first["time_s"] <= 0.75e-3 + 10.5e-6  # the first history row past s = 0.75
    assert first["corner_jacobian_ratio"] < 0.1
    assert worst["corner_jacobian_ratio"] == pytest.approx(-0.2, abs=1e-9)
    assert worst["time_s"] == pytest.approx(1.0e-3)
    lines = [w for w in summary["run"]["warnings"] if w.startswith("elements folded")]
    assert len(lines) == 1 and "element 0 (block 'solid')" in lines[0] and "\n" not in lines[0]


def test_no_report_when_off_or_undistorted(tmp_path):
    path = _scenario(tmp_path)
    off = corneasim.run_scenario(path, ["solver.distortion_warning=0"])
    assert "distortion" not in off.summary and "min_corner_jacobian_ratio" not in off.history
    mild = corneasim.run_scenario(path, ["constraints[1].value=-0.1", "constraints[2].value=-0.1"])
    assert mild.summary["distortion"]["first"] is None
    assert not any("elements" in w for w in mild.summary["run"]["warnings"])


def test_records_survive_a_checkpoint(tmp_path):
    from corneasim.solver import DistortionCheck

    mesh = Mesh(np.array([[1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0]]), np.array([[0, 1, 2, 3]]), "quad",
                np.zeros(1, dtype=np.int64), ["solid"], axisymmetric=True)
    check = DistortionCheck(mesh, 0.1)
    check.first, check.worst, check.below = (1e-3, 0, 0.05), (2e-3, 0, -0.2), 1
    again = DistortionCheck(mesh, 0.1)
    again.restore(check.checkpoint())
    assert (again.first, again.worst, again.below) == (check.first, check.worst, check.below)
    empty = DistortionCheck(mesh, 0.1)
    empty.restore(DistortionCheck(mesh, 0.1).checkpoint())
    assert empty.first is None and empty.worst is None
