"""The trephine scenario end to end at coarse size, from the CLI: results contract and physics.

The run is short (6 s) and made to cut within it: a 3x faster descent (60 um/s) and an edge
that cuts at a line load of 0.01 N/mm (``instrument.contact.cutting_toughness``), which the
heavily mass-scaled tissue (target step 1e-3 s, for seconds of wall time) reaches at each
first touch (docs/contact.md), so deletions happen in seconds.
The checks use independent truths: the rotation's period 2 pi / 3.508 s (the scenario's
Fourier amplitude, trephination paper eq. 1 with omega = 33.5 r/min), friction opposing the
rotation, the trephine's cutting radius 3.75 mm.
"""

import csv
import json
import math

import meshio
import numpy as np
import pytest

from cli_helpers import corneasim

from corneasim.data import read_table
from corneasim.mesh import mesh_3d
from corneasim.mesh.geometry import EyeGeometry

FAST = [
    "--preset", "coarse",
    "--set", "solver.end_time=6", "--set", "instrument.motion.insertion.rate=0.06",
    "--set", "instrument.contact.cutting_toughness=0.01",
    "--set", "solver.field_count=2", "--set", "solver.checkpoint_every=2000",
    "--set", "solver.target_time_step=1e-3", "--set", "preload.duration=1", "--set", "preload.damping=50",
    "--set", "instrument.start_gap=0.002",
]
OMEGA = 33.5 * 2 * math.pi / 60       # rad/s (33.5 r/min)
CUTTING_RADIUS = 7.5 / 2              # mm


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    out = tmp_path_factory.mktemp("trephine")
    result = corneasim("run", "trephine", *FAST, "--out", str(out), "--no-progress")
    assert result.returncode == 0, result.stderr
    return out


def test_results_folder_has_the_contract_files(results):
    for name in ("scenario.toml", "history.csv", "summary.json", "deletions.csv", "fields/fields.pvd",
                 "plots/forces.png", "plots/stress-0.0s.png", "plots/stress-3.5s.png", "plots/stress-end.png"):
        assert (results / name).is_file(), name
    header = (results / "history.csv").read_text().splitlines()[0].split(",")
    assert header[:9] == ["time_s", "displacement_um", "angle_rad", "fz_N", "fc_N", "torque_Nmm",
                          "kinetic_energy_mJ", "internal_energy_mJ", "deleted_elements"]
    summary = json.loads((results / "summary.json").read_text())
    assert summary["status"] == "completed"
    for key in ("peak_fz_N", "peak_fc_N", "puncture_force_N", "punctures", "fit", "validation", "run"):
        assert key in summary, key
    assert set(summary["fit"]) >= {"a", "b", "c", "rmse_N"} and len(summary["fit"]["a"]) == 2
    for force in ("fz", "fc"):
        assert set(summary["validation"][force]) >= {"rmse_N", "max_abs_error_N", "n_points"}
    for key in ("max_kinetic_to_internal", "time_scaling", "wall_s", "added_mass_fraction"):
        assert key in summary["run"], key


def test_the_fields_show_the_whole_eye(results):
    """The half model (y >= 0, cyclic symmetry about z) is written with its image rotated by pi."""
    frame = meshio.read(sorted((results / "fields").glob("fields_*.vtu"))[-1])
    (cells,) = [block.data for block in frame.cells]
    n = len(frame.points) // 2
    assert cells.shape[0] % 2 == 0 and frame.cell_data["image"][0].sum() == cells.shape[0] // 2
    assert frame.points[:n, 1].min() > -1e-9 and frame.points[n:, 1].max() < 1e-9
    np.testing.assert_allclose(frame.points[n:, :2], -frame.points[:n, :2], atol=1e-12)


def test_history_is_in_physical_time_with_the_paper_motion(results):
    history = read_table(results / "history.csv")
    time = history["time_s"]
    assert time[-1] == pytest.approx(6.0, abs=1e-6)
    np.testing.assert_allclose(history["displacement_um"], 60.0 * time, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(history["angle_rad"], 1.25 * np.sin(OMEGA * time), atol=1e-9)
    np.testing.assert_allclose(history["fc_N"], history["torque_Nmm"] / CUTTING_RADIUS, rtol=1e-12)
    summary = json.loads((results / "summary.json").read_text())
    assert summary["peak_fz_N"] == pytest.approx(history["fz_N"].max(), rel=1e-12)
    assert summary["peak_fc_N"] == pytest.approx(np.abs(history["fc_N"]).max(), rel=1e-12)


def test_fz_pushes_the_trephine_up(results):
    history = read_table(results / "history.csv")
    touching = history["instrument_normal_force_N"] > 0  # nodes or edge in contact
    fz = history["fz_N"][touching]
    assert touching.sum() > 20
    assert fz.mean() > 0 and fz.max() > 0
    assert fz.min() > -0.1 * fz.max()


def test_fc_oscillates_with_the_rotation(results):
    history = read_table(results / "history.csv")
    touching = history["instrument_normal_force_N"] > 0  # nodes or edge in contact
    time, fc = history["time_s"][touching], history["fc_N"][touching]
    angular_velocity = 1.25 * OMEGA * np.cos(OMEGA * time)
    # Friction opposes the rotation: the tissue's torque on the trephine against its angular velocity.
    assert np.corrcoef(fc, angular_velocity)[0, 1] < -0.5
    sign = np.sign(fc)
    crossings = time[1:][sign[1:] * sign[:-1] < 0]
    assert crossings.size >= 4
    # Fc reverses where the rotation does: every half period pi / omega.
    assert np.mean(np.diff(crossings)) == pytest.approx(math.pi / OMEGA, rel=0.15)


def test_elements_are_deleted_under_the_blade_only(results):
    rows = list(csv.DictReader((results / "deletions.csv").open()))
    assert len(rows) > 10
    assert {row["block"] for row in rows} <= {"epithelium", "stroma"}
    mesh = mesh_3d(EyeGeometry(), "umbrella", "coarse")
    elements = np.array([int(row["element"]) for row in rows])
    centres = mesh.points[mesh.cells[elements]].mean(axis=1)
    distance = np.abs(np.hypot(centres[:, 0], centres[:, 1]) - CUTTING_RADIUS)
    # None in the central cornea or towards the limbus (coarse elements near the cut are 0.15-0.25 mm
    # wide radially, so 1 mm is about four of them), most in the elements the edge crosses.
    assert distance.max() < 1.0
    assert np.mean(distance < 0.3) > 0.5


def test_bad_mesh_strategy_is_one_line_exit_2():
    result = corneasim("run", "trephine", "--mesh", "spiral")
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1
    result = corneasim("run", "trephine", "--set", "solver.time_scaling=-1")
    assert result.returncode == 2 and "time_scaling" in result.stderr


@pytest.mark.parametrize("overrides", [[], ["mesh.preset=coarse"], ["mesh.strategy=vertical"],
                                       ["mesh.strategy=horizontal"]])
def test_the_puncture_column_goes_through_the_cornea_under_the_cut(overrides):
    """The column whose deletions define the punctures holds, on every meshing strategy, the
    epithelium and then the stroma under the cutting circle at the symmetry plane, from the
    anterior surface down."""
    from corneasim.scenarios.build import build
    from corneasim.scenarios.postprocess import path_column
    from corneasim.scenarios.registry import load_scenario

    scenario, _, base = load_scenario("trephine", overrides)
    setup = build(scenario, base)
    elements, blocks, spans = path_column(setup)
    mesh = setup.mesh
    corners = mesh.points[mesh.cells[elements]]
    radius = np.hypot(corners[..., 0], corners[..., 1])
    cut = scenario.instrument.shape.cutting_radius
    assert np.all((radius.min(axis=1) <= cut) & (radius.max(axis=1) >= cut))
    assert np.all(np.abs(corners[..., 1]).min(axis=1) <= 1e-9)  # a corner on the plane y = 0
    assert list(blocks) == sorted(blocks)  # "epithelium" first, then "stroma"
    assert (blocks == "epithelium").sum() >= 1 and (blocks == "stroma").sum() >= 2
    anterior = set(mesh.node_sets["anterior_surface"].tolist())
    assert anterior & set(mesh.cells[elements[0]].tolist())  # starts at the anterior surface
    # where the line r = cutting radius, y = 0 crosses each element: it enters the first at the
    # anterior surface, each where the one above left it, and the depths are those of the plane
    # corners (linear interpolation along the element's edges on the plane)
    assert np.all(spans[:, 0] > spans[:, 1])
    np.testing.assert_allclose(spans[1:, 0], spans[:-1, 1], atol=1e-9)
    for element, (top, bottom) in zip(elements, spans):
        z = mesh.points[mesh.cells[element], 2]
        assert z.min() - 1e-12 <= bottom < top <= z.max() + 1e-12


def test_puncture_events_follow_the_cut_front_down_the_column():
    """A depth is cut when one element crossing it there is deleted; the events are the front's
    arrival at the epithelium's last depth, the stroma's first and the cornea's last."""
    from corneasim.scenarios.postprocess import puncture_events

    # epithelium 0 (z 0 to -0.1); stroma 1 and 2 side by side (-0.1 to -0.3), stroma 3 (-0.3 to -0.5)
    elements = np.array([10, 11, 12, 13])
    blocks = np.array(["epithelium", "stroma", "stroma", "stroma"])
    spans = np.array([[0.0, -0.1], [-0.1, -0.3], [-0.1, -0.3], [-0.3, -0.5]])
    column = (elements, blocks, spans)
    deleted = [(2.0, 12, "stroma"), (1.0, 10, "epithelium"), (5.0, 13, "stroma")]
    assert puncture_events(None, deleted, column) == {"epithelium": 1.0, "stroma": 2.0, "cornea": 5.0}
    # a stroma element deleted before the epithelium above it: the front waits for the epithelium
    early = [(0.5, 11, "stroma"), (1.0, 10, "epithelium")]
    assert puncture_events(None, early, column) == {"epithelium": 1.0, "stroma": 1.0}
    # the deepest element still there: no cornea event
    assert "cornea" not in puncture_events(None, deleted[:2], column)
