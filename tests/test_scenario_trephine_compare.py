"""``corneasim compare-meshes trephine``: the Table 1 analogue at coarse size and a very short time (the
table through the CLI's parser and error path in this process, a bad strategy through the entry point)."""

import csv
import json

import numpy as np
import pytest

from cli_helpers import corneasim, corneasim_here

from corneasim.mesh import mesh_3d
from corneasim.mesh._geometry import EyeGeometry
from corneasim.scenarios._compare import table_row, trephine_area_elements

SHORT = ["--preset", "coarse", "--set", "solver.end_time=3.6", "--set", "solver.field_count=0",
         "--set", "preload.duration=0.5", "--set", "solver.target_time_step=2e-3"]


@pytest.fixture(scope="module")
def table(tmp_path_factory):
    out = tmp_path_factory.mktemp("compare")
    result = corneasim_here("compare-meshes", "trephine", *SHORT, "--out", str(out), "--no-progress")
    assert result.returncode == 0, result.stderr
    assert "| umbrella |" in result.stdout
    return out, list(csv.DictReader((out / "table1.csv").open()))


def test_one_row_per_strategy_with_its_mesh(table):
    out, rows = table
    assert [row["strategy"] for row in rows] == ["umbrella", "vertical", "horizontal"]
    for row in rows:
        mesh = mesh_3d(EyeGeometry(), row["strategy"], "coarse")
        assert int(row["elements_total"]) == mesh.n_elements
        assert 0 < int(row["elements_trephine_area"]) < mesh.n_elements
        assert row["status"] == "completed" and float(row["wall_s"]) > 0
        # the row is the strategy's summary (the table rounds to 4 digits)
        fz = json.loads((out / row["strategy"] / "summary.json").read_text())["validation"]["fz"]
        assert float(row["fz_rmse_N"]) == pytest.approx(fz["rmse_N"], rel=2e-3, abs=1e-12)
        # two table times inside the run: 0 s, where nothing touches yet (raw error 0), and
        # 3.5 s, so the raw RMSE = max error / sqrt(2) = |Fz(3.5 s) - 0| / sqrt(2)
        assert fz["n_points"] == 2
        assert fz["rmse_raw_N"] == pytest.approx(fz["max_abs_error_raw_N"] / np.sqrt(2), rel=1e-9)
    assert (out / "table1.md").read_text().count("\n|") >= 4


def test_trephine_area_counts_cornea_elements_near_the_cutting_circle():
    mesh = mesh_3d(EyeGeometry(), "umbrella", "coarse")
    centres = mesh.points[mesh.cells].mean(axis=1)
    radius = np.hypot(centres[:, 0], centres[:, 1])
    sclera = mesh.element_block == mesh.block_names.index("sclera")
    expected = np.sum(~sclera & (radius >= 2.75) & (radius <= 4.75))
    assert trephine_area_elements(mesh, 3.75, 1.0) == expected
    assert trephine_area_elements(mesh, 3.75, 100.0) == np.sum(~sclera)


def test_trend_and_magnitude_labels():
    mesh = mesh_3d(EyeGeometry(), "vertical", "coarse")
    summary = {"status": "completed", "validation": {"fz": {"pearson": 0.95, "magnitude_ratio": 0.5}}}
    row = table_row("vertical", mesh, 3.75, summary)
    assert (row["variation_trend"], row["data_area"]) == ("similar", "smaller")
    summary["validation"]["fz"].update(pearson=0.2, magnitude_ratio=2.0)
    row = table_row("vertical", mesh, 3.75, summary)
    assert (row["variation_trend"], row["data_area"]) == ("different", "larger")
    assert table_row("vertical", mesh, 3.75, {"status": "failed"})["variation_trend"] == "n/a"


def test_unknown_strategy_is_one_line_exit_2(tmp_path):
    result = corneasim("compare-meshes", "trephine", "--strategies", "umbrella,spiral", "--out", str(tmp_path))
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1
    assert "spiral" in result.stderr


def test_agreement_of_a_scaled_and_of_a_flat_curve():
    from corneasim.data import load_dataset
    from corneasim.scenarios._trephine import agreement

    data = load_dataset("trephination-force")
    t, fz = data.columns["time_s"], data.columns["experiment_Fz_N"]
    keep = t <= 65.0
    # twice the experiment, sampled at the table times: perfect trend, magnitude 2
    result = agreement(t[keep], 2.0 * fz[keep], data)
    assert result["pearson"] == pytest.approx(1.0) and result["magnitude_ratio"] == pytest.approx(2.0)
    flat = agreement(t[keep], np.full(keep.sum(), 1e-300), data)
    assert flat["pearson"] is None and flat["magnitude_ratio"] == pytest.approx(0.0, abs=1e-12)
