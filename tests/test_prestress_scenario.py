"""``preload.stress_free_reference`` on the needle's coarse eye with the fibre (HGO) stroma.

The eye's mesh is its geometry under the IOP. Taken as stress-free, the soft-matrix HGO
stroma bulges under the IOP until its fibres carry it (the apex rises by a tenth of a
millimetre or more); built on the stress-free reference, the preloaded eye is the mesh's
own: the apex after the preload lies within 5 um of the mesh's apex.
"""

import json
from pathlib import Path

import numpy as np
import pytest

from cli_helpers import corneasim_here

import corneasim
from corneasim.mesh import mesh_axisymmetric
from corneasim.scenarios._prestress import REFERENCE_FILE, preloaded_points
from corneasim.scenarios._preload_reuse import PRELOAD_FILE
from corneasim.scenarios._registry import load_scenario
from corneasim.scenarios._runner import simulate

STROMA = Path(__file__).resolve().parents[1] / "validation" / "materials" / "needle-cut-stroma.toml"
EYE = ["mesh.preset=coarse", f"materials.stroma.material={STROMA}", "solver.end_time=0.002",
       "solver.field_count=0", "preload.stress_free_reference=true"]
# the preload shortened to 0.1 s: the eye is far from settled (apex at 0.011 of its 0.153 mm), but
# the reference makes the preload's end the mesh, settled or not
QUICK = [*EYE, "preload.duration=0.1", "preload.damping=140"]
# settled: 0.25 s at 60 1/s leaves the apex 1.5% short of its equilibrium rise (0.153 mm)
SETTLED = [*EYE, "preload.duration=0.25", "preload.damping=60", "preload.reference_tolerance=0.002"]


def apex_node(points):
    """The highest node on the axis."""
    on_axis = np.flatnonzero(points[:, 0] <= 1e-9)
    return int(on_axis[np.argmax(points[on_axis, 1])])


def check_apex(folder, overrides, rise):
    """The preloaded apex within 5 um of the mesh's; the stress-free apex more than ``rise`` (mm) below it."""
    scenario, _, _ = load_scenario("needle", overrides)
    measured = mesh_axisymmetric(scenario.mesh.geometry, "coarse").points
    with np.load(folder / REFERENCE_FILE) as saved, np.load(folder / PRELOAD_FILE) as settled:
        reference, displacement = saved["points"], settled["u"]
    top = apex_node(measured)
    assert apex_node(reference) == top
    assert measured[top, 1] - reference[top, 1] > rise
    assert np.linalg.norm(reference[top] + displacement[top] - measured[top]) < 5e-3


@pytest.fixture(scope="module")
def prestressed(tmp_path_factory):
    folder = tmp_path_factory.mktemp("prestressed")
    return folder, corneasim.run_scenario("needle", QUICK, out_dir=folder)


def test_the_preloaded_eye_is_the_mesh(prestressed):
    folder, result = prestressed
    report = result.summary["stress_free_reference"]
    assert report["errors_mm"][0] > 0.1  # the mesh as stress-free: the IOP moves it by as much
    assert report["errors_mm"][-1] <= 1e-3 and report["iterations"] <= 6
    assert report["loaded_error_mm"] == report["errors_mm"][-1]  # the run's preload is the last solve's
    check_apex(folder, QUICK, 0.005)


@pytest.mark.slow
def test_the_settled_hgo_apex_is_the_measured_apex(tmp_path):
    result = corneasim.run_scenario("needle", SETTLED, out_dir=tmp_path)
    assert result.summary["stress_free_reference"]["loaded_error_mm"] <= 2e-3
    check_apex(tmp_path, SETTLED, 0.1)


def test_a_resumed_run_takes_the_saved_reference(prestressed, monkeypatch):
    folder, result = prestressed
    (folder / "checkpoint.npz").unlink(missing_ok=True)  # resumed from the start: the preload again
    # (the first run started from its last solve's preload; this one settles its own on the saved reference)

    def no_solve(*arguments, **options):
        raise AssertionError("the reference was solved again")

    monkeypatch.setattr("corneasim.scenarios._prestress.settle", no_solve)
    scenario, _, base_dir = load_scenario("needle", QUICK)
    again = simulate(scenario, out_dir=folder, base_dir=base_dir, resume=True, progress=False)
    assert again.summary["stress_free_reference"] == result.summary["stress_free_reference"]
    np.testing.assert_array_equal(again.history["force_N"], result.history["force_N"])


def test_a_run_from_its_preload_takes_its_reference(prestressed, monkeypatch):
    folder, result = prestressed
    monkeypatch.setattr("corneasim.scenarios._prestress.settle", lambda *a, **k: pytest.fail("solved"))
    reused = corneasim.run_scenario("needle", QUICK, preload_from=folder)
    np.testing.assert_array_equal(reused.history["force_N"], result.history["force_N"])
    assert reused.summary["stress_free_reference"]["errors_mm"] == result.summary["stress_free_reference"]["errors_mm"]


def test_a_run_from_a_preload_without_its_reference_is_refused(prestressed, tmp_path):
    folder, _ = prestressed
    (tmp_path / PRELOAD_FILE).write_bytes((folder / PRELOAD_FILE).read_bytes())
    sets = [item for override in QUICK for item in ("--set", override)]
    result = corneasim_here("run", "needle", *sets, "--preload-from", str(tmp_path), "--no-progress")
    assert result.returncode == 2
    assert len(result.stderr.strip().splitlines()) == 1 and "no converged stress-free reference" in result.stderr


def test_a_reference_that_does_not_converge_fails_the_run_with_its_reason(tmp_path):
    out = tmp_path / "run"
    sets = [item for override in [*QUICK, "preload.reference_iterations=1"] for item in ("--set", override)]
    result = corneasim_here("run", "needle", *sets, "--out", str(out), "--no-progress")
    assert result.returncode == 1, result.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "failed"
    assert summary["error"].startswith("stress-free reference: not converged in 1 iterations")
    assert (out / REFERENCE_FILE).is_file()  # the iteration so far, for a resumed run


@pytest.mark.parametrize("override, key", [("preload.reference_tolerance=-1", "reference_tolerance"),
                                           ("preload.reference_iterations=0", "reference_iterations")])
def test_bad_reference_settings_are_one_line_exit_2(override, key, tmp_path):
    result = corneasim_here("run", "needle", "--set", override, "--out", str(tmp_path / "x"), "--no-progress")
    assert result.returncode == 2
    assert len(result.stderr.strip().splitlines()) == 1 and key in result.stderr, result.stderr


def test_axis_nodes_stay_on_the_axis_of_an_axisymmetric_mesh():
    """A penalty that holds the axis nodes leaves them a round-off radial displacement, which the
    iteration X <- X - (x - x_mesh) would take to a negative radius."""
    from test_solver_meshes import sphere_quarter_quad

    mesh = sphere_quarter_quad(1.0, 2.0, 2, 4)
    displacement = np.full(mesh.points.shape, 1e-8)
    points = preloaded_points(mesh, displacement)
    on_axis = mesh.points[:, 0] == 0.0
    assert on_axis.sum() == 3 and np.all(points[on_axis, 0] == 0.0)
    np.testing.assert_array_equal(points[~on_axis], mesh.points[~on_axis] + 1e-8)
    np.testing.assert_array_equal(points[:, 1], mesh.points[:, 1] + 1e-8)
