"""Result files: atomic writes, resumable history tables, ParaView time series."""

import json
import xml.etree.ElementTree as ElementTree

import meshio
import numpy as np
import pytest

from corneasim.output._files import HistoryWriter, atomic_write_text, write_json
from corneasim.output._paraview import TimeSeriesWriter


def test_atomic_write_replaces_and_leaves_no_temporary(tmp_path):
    target = tmp_path / "summary.json"
    atomic_write_text(target, "old")
    write_json(target, {"peak_force_N": np.float64(0.5), "bad": float("nan"), "list": np.arange(2)})
    assert json.loads(target.read_text()) == {"peak_force_N": 0.5, "bad": None, "list": [0, 1]}
    assert [p.name for p in tmp_path.iterdir()] == ["summary.json"]


def test_history_resume_drops_rows_after_checkpoint(tmp_path):
    path = tmp_path / "history.csv"
    columns = ["time_s", "force_N"]
    with HistoryWriter(path, columns) as writer:
        for t in (0.0, 0.1, 0.2, 0.3):
            writer.append({"time_s": t, "force_N": 2 * t})
    with HistoryWriter(path, columns, resume=True, resume_time=0.1) as writer:
        writer.append({"time_s": 0.2, "force_N": 0.4})
    rows = path.read_text().splitlines()
    assert rows[0] == "time_s,force_N"
    assert [float(r.split(",")[0]) for r in rows[1:]] == [0.0, 0.1, 0.2]


def test_time_series_round_trip(tmp_path):
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    writer = TimeSeriesWriter(tmp_path, points, np.array([[0, 1, 2, 3]]), "quad")
    for k, t in enumerate((0.0, 0.5)):
        writer.write(t, {"displacement": np.full((4, 2), k * 0.1)}, {"alive": np.array([1 - k])})
    index = ElementTree.parse(tmp_path / "fields.pvd").getroot()
    entries = index.findall("./Collection/DataSet")
    assert [float(e.get("timestep")) for e in entries] == [0.0, 0.5]
    frame = meshio.read(tmp_path / entries[1].get("file"))
    assert frame.point_data["displacement"].shape == (4, 3)
    assert frame.point_data["displacement"][:, :2] == pytest.approx(0.1)
    assert frame.cell_data["alive"][0].tolist() == [0]
    assert not list(tmp_path.glob(".*"))


def test_time_series_resume_keeps_earlier_frames(tmp_path):
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    cells = np.array([[0, 1, 2, 3]])
    writer = TimeSeriesWriter(tmp_path, points, cells, "quad")
    for t in (0.0, 0.5, 1.0):
        writer.write(t, {}, {"alive": np.array([1])})
    resumed = TimeSeriesWriter(tmp_path, points, cells, "quad", resume_time=0.5)
    resumed.write(0.75, {}, {"alive": np.array([1])})
    entries = ElementTree.parse(tmp_path / "fields.pvd").getroot().findall("./Collection/DataSet")
    assert [float(e.get("timestep")) for e in entries] == [0.0, 0.5, 0.75]
    assert len({e.get("file") for e in entries}) == 3


def _voigt(matrix):
    return np.array([matrix[0, 0], matrix[1, 1], matrix[2, 2], matrix[0, 1], matrix[1, 2], matrix[2, 0]])


def _corner_volume(x):
    """det[x1 - x0, x3 - x0, x4 - x0] of a VTK hexahedron (positive when correctly ordered)."""
    return np.linalg.det(np.array([x[1] - x[0], x[3] - x[0], x[4] - x[0]]))


@pytest.mark.parametrize("image, transform", [
    ((-1, -1, 1), np.diag([-1.0, -1.0, 1.0])),  # cyclic symmetry about z: rotation by pi
    ((1, -1, 1), np.diag([1.0, -1.0, 1.0])),  # mirror plane y = 0
])
def test_a_half_model_is_written_whole_with_its_image(tmp_path, image, transform):
    box = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    points = box + np.array([0.5, 0.0, 0.0])  # the half y >= 0, off the axis
    u = np.random.default_rng(2).normal(0.0, 0.02, (8, 3))
    sigma = np.array([[1.0, 0.2, 0.3], [0.2, 2.0, 0.4], [0.3, 0.4, 3.0]])
    writer = TimeSeriesWriter(tmp_path, points, np.arange(8)[None, :], "hexahedron", image=image)
    path = writer.write(0.0, {"displacement": u}, {"cauchy_stress": _voigt(sigma)[None, :],
                                                    "von_mises": np.array([7.0])}, displace=u)
    frame = meshio.read(path)
    (cells,) = [block.data for block in frame.cells]
    assert frame.points.shape == (16, 3) and cells.shape == (2, 8)
    np.testing.assert_allclose(frame.points[8:], (points + u) @ transform.T, atol=1e-12)
    np.testing.assert_allclose(frame.point_data["displacement"][8:], u @ transform.T, atol=1e-12)
    np.testing.assert_allclose(frame.cell_data["cauchy_stress"][0][1], _voigt(transform @ sigma @ transform.T))
    assert frame.cell_data["von_mises"][0].tolist() == [7.0, 7.0]
    assert frame.cell_data["image"][0].tolist() == [0, 1]
    volumes = [_corner_volume(frame.points[cell]) for cell in cells]
    assert volumes[0] > 0 and volumes[1] == pytest.approx(volumes[0], rel=1e-12)
