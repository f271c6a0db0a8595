"""The trephine scenario end to end at coarse size, from the CLI (run in this process through its parser
and error path): results contract and physics.

The run is short (6 s) and made to cut within it: a 3x faster descent (60 um/s) and an edge
that cuts at a line load of 0.006 N/mm (``instrument.contact.cutting_toughness``, F_z of about
0.07 N on the half model's 11.8 mm of edge), which the heavily mass-scaled tissue (target
step 1e-3 s, for seconds of wall time) reaches within the first second (docs/contact.md), so
deletions happen in seconds.
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

from cli_helpers import corneasim, corneasim_here

from corneasim.data import read_table
from corneasim.mesh import mesh_3d
from corneasim.mesh._geometry import EyeGeometry

FAST = [
    "--preset", "coarse",
    "--set", "solver.end_time=6", "--set", "instrument.motion.insertion.rate=0.06",
    "--set", "instrument.contact.cutting_toughness=0.006",
    "--set", "solver.field_count=2", "--set", "solver.checkpoint_every=2000",
    "--set", "solver.target_time_step=1e-3", "--set", "preload.duration=1", "--set", "preload.damping=50",
    "--set", "instrument.start_gap=0.002",
]
OMEGA = 33.5 * 2 * math.pi / 60       # rad/s (33.5 r/min)
CUTTING_RADIUS = 7.5 / 2              # mm


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    out = tmp_path_factory.mktemp("trephine")
    result = corneasim_here("run", "trephine", *FAST, "--out", str(out), "--no-progress")
    assert result.returncode == 0, result.stderr
    return out


def test_results_folder_has_the_contract_files(results):
    for name in ("scenario.toml", "history.csv", "summary.json", "deletions.csv", "fields/fields.pvd",
                 "plots/forces.png", "plots/stress-0.0s.png", "plots/stress-3.5s.png", "plots/stress-end.png"):
        assert (results / name).is_file(), name
    header = (results / "history.csv").read_text().splitlines()[0].split(",")
    assert header[:9] == ["time_s", "displacement_mm", "angle_rad", "fz_N", "fc_N", "torque_Nmm",
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
    np.testing.assert_allclose(history["displacement_mm"], 0.06 * time, rtol=1e-9, atol=1e-9)
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
    result = corneasim_here("run", "trephine", "--set", "solver.time_scaling=-1")
    assert result.returncode == 2 and "time_scaling" in result.stderr


@pytest.mark.parametrize("overrides", [[], ["mesh.preset=coarse"], ["mesh.strategy=vertical"],
                                       ["mesh.strategy=horizontal"]])
def test_the_cut_section_spans_the_cornea_about_the_cutting_radius(overrides):
    """The section whose deleted elements define the trephine's punctures holds, on every
    meshing strategy, cornea elements with a face on the plane y = 0 about the cutting radius,
    from the anterior surface through the epithelium-stroma interface to the posterior one."""
    from corneasim.scenarios._build import build
    from corneasim.scenarios._punctures import SECTION_BAND, cut_section
    from corneasim.scenarios._registry import load_scenario

    scenario, _, base = load_scenario("trephine", overrides)
    setup = build(scenario, base)
    section = cut_section(setup)
    mesh = setup.mesh
    corners = mesh.points[mesh.cells[section.elements]]
    assert np.all((np.abs(corners[..., 1]) <= 1e-9).sum(axis=1) >= 3)
    centre = corners.mean(axis=1)
    assert np.all(np.abs(np.hypot(centre[:, 0], centre[:, 1]) - scenario.instrument.shape.cutting_radius)
                  <= SECTION_BAND)
    for mark in (section.top, section.interface, section.stroma, section.bottom):
        assert mark.any()
    for i, others in enumerate(section.neighbours):
        assert all(i in section.neighbours[j] for j in others)


def test_trephine_punctures_follow_a_path_of_deleted_elements_from_the_surface():
    """An event is the first time deleted elements, each sharing an edge with the next, join
    the anterior surface to the interface (epithelium), the stroma, the posterior surface."""
    from corneasim.scenarios._build import build
    from corneasim.scenarios._punctures import cut_section, section_events
    from corneasim.scenarios._registry import load_scenario

    scenario, _, base = load_scenario("trephine", ["mesh.preset=coarse"])
    section = cut_section(build(scenario, base))
    elements = section.elements
    stroma = section.stroma
    everything = {int(e): 1.0 for e in elements}
    assert section_events(section, everything) == {"epithelium": 1.0, "stroma": 1.0, "cornea": 1.0}
    layered = {int(e): (2.0 if s else 1.0) for e, s in zip(elements, stroma)}
    assert section_events(section, layered) == {"epithelium": 1.0, "stroma": 2.0, "cornea": 2.0}
    # the stroma cut but not the epithelium above it: nothing reaches down from the surface
    assert section_events(section, {int(e): 1.0 for e in elements[stroma]}) == {}
    # everything but the posterior row: through the epithelium and into the stroma, not out
    assert section_events(section, {int(e): 1.0 for e, b in zip(elements, section.bottom) if not b}) == \
        {"epithelium": 1.0, "stroma": 1.0}
