"""``corneasim compare-meshes trephine``: the Table 1 analogue at coarse size and a very short time (the
table through the CLI's parser and error path in this process, a bad strategy through the entry point)."""

import csv
import json

import numpy as np
import pytest

from cli_helpers import corneasim, corneasim_here

from corneasim.mesh import mesh_3d
from corneasim.mesh._geometry import EyeGeometry
from corneasim.errors import InputError
from corneasim.scenarios._compare import (
    REALIZATION_COLUMNS, compare_meshes, realizations_study, table_row, trephine_area_elements)
from corneasim.studies.designs import REALIZATIONS

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


def test_the_realizations_study_runs_every_strategy_in_every_realization():
    from corneasim.studies.runner import Plan

    spec = realizations_study("trephine", ["mesh.preset=coarse", "solver.end_time=3.6"], ["umbrella", "vertical"])
    assert spec["overrides"] == {"mesh.preset": "coarse", "solver.end_time": 3.6}
    cases = Plan(spec).cases()
    names = [name for name, _, _ in REALIZATIONS]
    assert sorted((case.values["mesh.strategy"], case.realization) for case in cases) == sorted(
        (strategy, name) for strategy in ("umbrella", "vertical") for name in names)
    for strategy in ("umbrella", "vertical"):
        mine = {case.realization: case for case in cases if case.values["mesh.strategy"] == strategy}
        gap = mine["as-given"].values["instrument.start_gap"]
        assert mine["start-gap+1e-7"].values["instrument.start_gap"] == pytest.approx(gap + 1e-7, abs=1e-15)
        assert mine["start-gap-1e-7"].values["instrument.start_gap"] == pytest.approx(gap - 1e-7, abs=1e-15)
        assert mine["fresh-kernels"].fresh_kernels and not mine["as-given"].fresh_kernels
        assert mine["one-thread"].values["solver.threads"] == 1


def _study_table(strategies):
    """A study table as ``corneasim.studies.study`` returns it, with figures made up per case (the
    vertical mesh's last realization failed)."""
    import pandas as pd

    rows = []
    for s, strategy in enumerate(strategies):
        for k, (name, _, _) in enumerate(REALIZATIONS):
            rows.append({"case": f"c{len(rows):04d}", "mesh.strategy": strategy, "realization": name,
                         "run_wall_s": 10.0 + k, "steps": 2050.0, "peak_fz_N": 0.13 + 0.003 * k,
                         "fz_rmse_N": 0.01 * (s + 1) + 1e-4 * k * k, "fz_max_abs_error_N": 0.02,
                         "fc_rmse_N": 0.005, "fz_pearson": 0.85 if k == 0 else 0.95,
                         "fz_magnitude_ratio": 1.0 if k else np.nan,
                         "status": "failed" if strategy == "vertical" and k == len(REALIZATIONS) - 1 else "completed",
                         "error": "", "wall_s": 11.0, "worker": "w"})
    return pd.DataFrame(rows)


def test_the_spread_table_gives_median_and_range_over_the_completed_realizations(tmp_path, monkeypatch):
    import corneasim.studies

    studies = []
    monkeypatch.setattr(corneasim.studies, "study",
                        lambda spec, out, workers, progress: studies.append((spec, out)) or
                        _study_table(spec["parameters"]["mesh.strategy"]), raising=False)
    rows = compare_meshes("trephine", ["mesh.preset=coarse"], tmp_path, ["umbrella", "vertical"], realizations=True)
    assert studies[0][1] == tmp_path / "realizations"
    assert len(rows) == 2 * len(REALIZATIONS)
    table = list(csv.DictReader((tmp_path / "table1.csv").open()))
    assert list(table[0]) == REALIZATION_COLUMNS and len(table) == len(rows)
    assert table[0]["wall_s"] == "10" and table[0]["steps"] == "2050"
    lines = {line.split(" | ")[0].strip("| "): line.split(" | ") for line in
             (tmp_path / "table1.md").read_text().splitlines() if line.startswith("| umbrella") or
             line.startswith("| vertical")}
    header = (tmp_path / "table1.md").read_text().splitlines()[0].strip("| ").split(" | ")
    umbrella = dict(zip(header, (cell.strip("| ") for cell in lines["umbrella"])))
    vertical = dict(zip(header, (cell.strip("| ") for cell in lines["vertical"])))
    n = len(REALIZATIONS)
    assert umbrella["completed"] == f"{n} of {n}" and vertical["completed"] == f"{n - 1} of {n}"
    k = np.arange(n)
    assert umbrella["fz_rmse_N"] == f"{np.median(0.01 + 1e-4 * k * k):.4g} ({0.01:.4g} to {0.01 + 1e-4 * 25:.4g})"
    # the failed realization is left out of the range
    assert vertical["fz_rmse_N"] == f"{np.median(0.02 + 1e-4 * k[:-1] ** 2):.4g} ({0.02:.4g} to {0.02 + 1e-4 * 16:.4g})"
    assert vertical["peak_fz_N"].endswith(f"to {0.13 + 0.003 * (n - 2):.4g})")
    # the trend is classified in every realization, the magnitude in all but the first (no ratio)
    assert umbrella["variation_trend"] == f"similar in {n - 1} of {n}"
    assert umbrella["data_area"] == f"similar in {n - 1} of {n - 1}"


def test_realizations_need_a_results_folder():
    with pytest.raises(InputError, match="out_dir"):
        compare_meshes("trephine", ["mesh.preset=coarse"], realizations=True)
