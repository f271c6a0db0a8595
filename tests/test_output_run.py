"""The field files and the report of a short needle run with deletions: the nodes the deleted elements
release stay where they last belonged, the series starts at t = 0, every frame names the blocks; every
history column and summary key carries a unit of the mm, s, N, MPa, mJ system; report.html is whole."""

import base64
import io
import json
import re
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import matplotlib.image
import meshio
import numpy as np
import pytest

import corneasim
from corneasim.output import OrphanNodes

FAST = ["mesh.preset=coarse", "instrument.motion.insertion.rate=5.0", "solver.end_time=0.1",
        "preload.duration=0.02", "preload.damping=400", "solver.field_count=3",
        "materials.epithelium.failure_limit=0.25", "materials.stroma.failure_limit=0.12",
        "materials.stroma.material=cornea-in-vivo", "materials.stroma.fracture_energy=0.0"]

UNITS = ("s", "mm", "mm2", "N", "Nmm", "MPa", "mJ", "mJ_per_s", "rad", "per_s")
COUNTS = {"step", "deleted_elements", "softening_elements", "instrument_contact_nodes", "energy_balance_error",
          "min_corner_jacobian_ratio"}


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    out = tmp_path_factory.mktemp("run")
    corneasim.run_scenario("needle", FAST, out_dir=out)
    return out


def _frames(results):
    entries = ElementTree.parse(results / "fields" / "fields.pvd").getroot().findall("./Collection/DataSet")
    return [(float(e.get("timestep")), meshio.read(results / "fields" / e.get("file"))) for e in entries]


def test_released_nodes_stay_inside_the_model(results):
    """Each released node is written at a position it had while attached: inside the box of the
    model at the start of the procedure, give or take 0.05 mm of deformation (a free node would
    fly on at its release velocity, several mm in this run)."""
    frames = _frames(results)
    first, last = frames[0][1], frames[-1][1]
    start = first.points + first.point_data["displacement"]
    low, high = start.min(axis=0) - 0.05, start.max(axis=0) + 0.05
    released = last.point_data["node_active"] == 0
    assert released.any(), "the run should release nodes (all their elements deleted)"
    position = last.points + last.point_data["displacement"]
    assert np.all((position[released] >= low) & (position[released] <= high))


def test_series_starts_at_zero_and_names_the_blocks(results):
    frames = _frames(results)
    assert frames[0][0] == pytest.approx(0.0, abs=1e-12) and len(frames) >= 3
    for _, frame in frames:
        names = {name: int(value[0]) for name, value in frame.field_data.items()}
        assert names == {"epithelium": 0, "stroma": 1, "sclera": 2}
        blocks = frame.cell_data["block"][0]
        assert set(np.unique(blocks)) == set(names.values())


def test_history_and_summary_carry_units(results):
    header = (results / "history.csv").read_text().splitlines()[0].split(",")
    for column in header:
        assert column in COUNTS or any(column.endswith("_" + unit) for unit in UNITS), column

    def keys(value):
        if isinstance(value, dict):
            for key, item in value.items():
                yield key
                yield from keys(item)
        elif isinstance(value, list):
            for item in value:
                yield from keys(item)

    summary = json.loads((results / "summary.json").read_text())
    assert not [key for key in keys(summary) if re.search(r"_(um|kPa|ms|deg)$", key)]


def test_the_run_writes_a_whole_report(results):
    text = (results / "report.html").read_text()
    sources = re.findall(r'<img [^>]*src="([^"]*)"', text)
    assert len(sources) >= 3  # the force plot, the energies, the stress maps
    for source in sources:
        assert source.startswith("data:image/png;base64,")
        matplotlib.image.imread(io.BytesIO(base64.b64decode(source.split(",", 1)[1], validate=True)))
    assert "Validation" in text and "Energies" in text and "Stress maps" in text


def test_a_run_without_plots_writes_the_data_files_only(tmp_path):
    from cli_helpers import corneasim_here

    punch = Path(__file__).resolve().parents[1] / "examples" / "flat_punch" / "flat_punch.toml"
    result = corneasim_here("run", punch, "--set", "solver.end_time=0.002", "--set", "solver.field_count=2",
                            "--no-plots", "--no-progress", "--out", tmp_path / "run")
    assert result.returncode == 0, result.stderr
    written = {path.name for path in (tmp_path / "run").iterdir()}
    assert {"summary.json", "history.csv", "scenario.toml", "fields"} <= written
    assert not written & {"plots", "report.html"}
    assert json.loads((tmp_path / "run" / "summary.json").read_text())["status"] == "completed"


def test_a_released_node_is_frozen_where_its_last_element_was_deleted():
    # two quads sharing the edge 1-2: deleting element 0 releases nodes 0 and 3 only
    cells = np.array([[0, 1, 2, 3], [1, 4, 5, 2]])
    orphans = OrphanNodes(cells, 6, 2)
    orphans.deleted([0], [1.0])
    u_release = np.arange(12.0).reshape(6, 2)
    v = np.full((6, 2), 4.0)
    u = u_release + v * (1.5 - 1.0)  # free flight at constant velocity from t = 1 to 1.5
    node_active = np.array([0, 1, 1, 0, 1, 1], dtype=np.uint8)
    orphans.update(1.5, u, v, node_active)
    written = orphans.apply(u + v * 2.0)  # a later frame: the free nodes have flown on
    np.testing.assert_allclose(written[[0, 3]], u_release[[0, 3]], rtol=0, atol=1e-12)
    np.testing.assert_allclose(written[[1, 2, 4, 5]], (u + v * 2.0)[[1, 2, 4, 5]])
