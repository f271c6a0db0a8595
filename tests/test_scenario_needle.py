"""The needle scenario end to end at coarse size: the results folder contract, from the CLI."""

import csv
import json
import xml.etree.ElementTree as ElementTree

import numpy as np
import pytest

from cli_helpers import corneasim, corneasim_here

from corneasim.data import read_table

FAST = [
    "--preset", "coarse", "--speed", "5",
    "--set", "preload.duration=0.02", "--set", "preload.damping=400",
    "--set", "materials.epithelium.failure_limit=1.0", "--set", "materials.stroma.failure_limit=2.0",
    "--set", "solver.field_count=3", "--set", "solver.checkpoint_every=500",
]


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    out = tmp_path_factory.mktemp("needle")
    result = corneasim("run", "needle", *FAST, "--out", str(out), "--no-progress")
    assert result.returncode == 0, result.stderr
    return out


def test_results_folder_has_the_contract_files(results):
    for name in ("scenario.toml", "history.csv", "summary.json", "deletions.csv", "fields/fields.pvd",
                 "plots/force.png", "plots/stress-end.png", "checkpoint.npz"):
        assert (results / name).is_file(), name
    header = (results / "history.csv").read_text().splitlines()[0].split(",")
    assert header[:6] == ["time_s", "depth_mm", "force_N", "kinetic_energy_mJ", "internal_energy_mJ",
                          "deleted_elements"]
    frames = ElementTree.parse(results / "fields" / "fields.pvd").getroot().findall("./Collection/DataSet")
    assert len(frames) >= 3 and all((results / "fields" / f.get("file")).is_file() for f in frames)


def test_summary_is_consistent_with_history(results):
    summary = json.loads((results / "summary.json").read_text())
    history = read_table(results / "history.csv")
    assert summary["status"] == "completed"
    assert summary["peak_force_N"] == pytest.approx(history["force_N"].max(), rel=1e-12)
    assert history["depth_mm"][-1] == pytest.approx(0.7, abs=1e-3)
    assert summary["run"]["steps"] == int(history["step"][-1])
    assert summary["run"]["elements"] > 0 and summary["run"]["wall_s"] > 0
    for key in ("max_kinetic_to_internal", "added_mass_fraction", "energy_balance_error", "element_steps_per_s"):
        assert key in summary["run"]
    assert set(summary["validation"]) >= {"dataset", "rmse_N", "max_abs_error_N"}
    assert set(summary["fit"]) >= {"a", "b", "c", "rmse_N"}
    # the history starts where the procedure does (the preload's last row), so the validation
    # uses all 15 depths of the table, 0 to 0.70 mm
    assert history["time_s"][0] == pytest.approx(0.0, abs=1e-12) and history["depth_mm"][0] <= 1e-12
    assert summary["validation"]["n_points"] == 15
    # no fitted term narrower than the table's 0.05 mm spacing
    assert min(summary["fit"]["c"]) >= 0.05 - 1e-12


def test_summary_records_the_platform(results):
    """The run's platform (what decides its speed and its round-off) is in summary.json: a coarse
    model runs on one thread, compiled by this numba for this machine's CPU."""
    import os

    import numba

    platform = json.loads((results / "summary.json").read_text())["run"]["platform"]
    assert platform["numba"] == numba.__version__ and platform["logical_cpus"] == os.cpu_count()
    assert platform["numba_threads"] == 1  # 985 elements: below the parallel threshold
    assert platform["threading_layer"] in ("omp", "tbb", "workqueue")
    assert platform["processor"] and platform["compiled_for"]
    assert platform["environment"]["OMP_WAIT_POLICY"] == os.environ.get("OMP_WAIT_POLICY", "PASSIVE")
    # compiled by this run or loaded from the cache, depending on what ran before: only the quad kernel can appear
    assert set(platform["kernels_compiled_in_run"]) <= {"corneasim.solver.elements._fast_quad.quad_internal_forces"}


def test_needle_pushes_and_cuts_along_the_axis(results):
    history = read_table(results / "history.csv")
    force = history["force_N"]
    assert force.max() > 0 and force.mean() > 0
    # Single contact nodes sliding on the cone can pull back briefly (friction up to the normal force).
    assert force.min() > -0.5 * force.max()
    summary = json.loads((results / "summary.json").read_text())
    events = [p["event"] for p in summary["punctures"]]
    assert events == ["epithelium", "stroma", "cornea"][: len(events)] and events
    with (results / "deletions.csv").open() as handle:
        deletions = list(csv.DictReader(handle))
    from corneasim.scenarios._build import make_mesh
    from corneasim.scenarios._registry import load_scenario

    scenario, _, _ = load_scenario(str(results / "scenario.toml"))
    mesh = make_mesh(scenario, results)
    deleted = np.array([int(row["element"]) for row in deletions])
    assert deleted.size > 0
    nearest_axis = mesh.points[mesh.cells[deleted], 0].min(axis=1)
    assert np.all(nearest_axis < 0.25), "elements deleted away from the needle path"


def test_bad_scenario_input_exits_2_with_one_line(tmp_path):
    """The first case through the real entry point in a process of its own, the others through
    the same parser and error path in this one."""
    result = corneasim("run", "needle", "--set", "solver.end_tim=1", "--out", str(tmp_path / "x"))
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1, result.stderr
    for arguments in (["run", "needle", "--set", "materials.stroma.material=rubber"],
                      ["run", "needle", "--set", "materials.stroma.fracture_energy=-0.1"],
                      ["run", "no-such-scenario"],
                      ["run", "needle", "--speed", "-1"],
                      ["run", "needle", "--depth", "0"],
                      ["run", "trephine", "--depth", "1.0"],
                      ["run", "needle", "--depth", "1.0", "--set", "instrument.motion.insertion.rate=0"],
                      ["run", str(_bad_toml(tmp_path))]):
        result = corneasim_here(*arguments, "--out", str(tmp_path / "x"))
        assert result.returncode == 2, (arguments, result.stderr)
        assert len(result.stderr.strip().splitlines()) == 1, result.stderr


def _bad_toml(folder):
    """A scenario file with a TOML syntax error (unterminated string)."""
    path = folder / "broken.toml"
    path.write_text('kind = "needle\nname = "x"\n')
    return path


def test_procedure_damping_does_work_only_when_asked():
    """solver.damping (1/s) acts after the preload: the damping work grows during the procedure."""
    import corneasim

    # the target step is pinned: the damping force alpha M v scales with the mass-scaled M
    quick = ["mesh.preset=coarse", "preload.duration=0.02", "preload.damping=400", "solver.end_time=0.01",
             "instrument.motion.insertion.rate=5", "solver.field_count=0", "solver.target_time_step=2e-5"]
    grown = {}
    for damping in (0.0, 50.0):
        history = corneasim.run_scenario("needle", [*quick, f"solver.damping={damping}"]).history
        work = history["damping_energy_mJ"]  # the history holds the procedure's rows only
        grown[damping] = work[-1] - work[0]
    # without it only the contact's normal damping adds a trace
    assert grown[50.0] > 100 * grown[0.0] > 0.0


def test_a_run_is_the_same_on_one_and_two_threads():
    """The whole run, deletions included, is bitwise the same on 1 and 2 threads: the element
    forces are summed in one order whatever the thread count (``solver/elements/_reduce.py``),
    and the other kernels are serial or element by element."""
    import numba

    import corneasim

    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("one thread only")
    quick = ["mesh.preset=coarse", "preload.duration=0.02", "preload.damping=400", "solver.end_time=0.05",
             "instrument.motion.insertion.rate=5", "solver.field_count=0",
             "materials.epithelium.failure_limit=1.0", "materials.stroma.failure_limit=2.0"]
    runs = [corneasim.run_scenario("needle", [*quick, f"solver.threads={threads}"]) for threads in (1, 2)]
    one, two = (run.history for run in runs)
    assert one["deleted_elements"][-1] > 0
    assert one.keys() == two.keys()
    for column in one:
        np.testing.assert_array_equal(one[column], two[column], err_msg=column)


def test_writing_plots_leaves_the_users_matplotlib_alone(tmp_path):
    """A run that writes plots from Python neither switches the matplotlib backend of the
    calling program (a notebook's, say) nor loads pyplot, and a run without a results
    folder does not import matplotlib at all."""
    import subprocess
    import sys

    script = f"""
import sys
import corneasim
quick = ["mesh.preset=coarse", "preload.duration=0.01", "solver.end_time=0.004", "solver.field_count=2"]
corneasim.run_scenario("needle", quick)
assert "matplotlib" not in sys.modules
import matplotlib
matplotlib.use("svg")
corneasim.run_scenario("needle", quick, out_dir={str(tmp_path / "run")!r})
assert matplotlib.get_backend() == "svg", matplotlib.get_backend()
assert "matplotlib.pyplot" not in sys.modules
"""
    completed = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert completed.returncode == 0, completed.stderr
    assert (tmp_path / "run" / "plots" / "force.png").stat().st_size > 0
    assert list((tmp_path / "run" / "plots").glob("stress-*.png"))


def test_a_run_past_the_table_is_validated_on_the_tables_range():
    """A run taken past Table 2's last depth (0.70 mm) is judged as the run that stops there:
    the validation fits only the part the table covers, while ``fit`` covers the whole run."""
    import corneasim

    quick = ["mesh.preset=coarse", "preload.duration=0.02", "preload.damping=400",
             "instrument.motion.insertion.rate=5", "solver.field_count=0",
             "materials.epithelium.failure_limit=1.0", "materials.stroma.failure_limit=2.0"]
    stops, goes_on = (corneasim.run_scenario("needle", [*quick, f"solver.end_time={depth / 5}"]).summary
                      for depth in (0.7, 1.0))
    assert goes_on["validation"]["fit_range"][1] == pytest.approx(0.7, abs=1e-6)
    assert stops["validation"]["fit_range"][1] == pytest.approx(0.7, abs=1e-6)
    assert goes_on["validation"]["n_points"] == stops["validation"]["n_points"] == 15
    # the same curve up to 0.7 mm (a shortened last step aside): the same score
    for key in ("rmse_N", "max_abs_error_N", "rmse_raw_N"):
        assert goes_on["validation"][key] == pytest.approx(stops["validation"][key], rel=1e-3), key
    # the whole-run fit is another one: it follows the force beyond 0.7 mm too
    assert goes_on["fit"] != stops["fit"]
    assert "fit" not in stops["validation"]
    assert goes_on["validation"]["fit"] != goes_on["fit"]


def test_depth_option_sets_the_insertion_depth(tmp_path):
    """--depth MM runs the needle to that depth at the scenario's (or --speed's) rate."""
    quick = ["--preset", "coarse", "--set", "preload.duration=0.02", "--set", "preload.damping=400",
             "--set", "solver.field_count=0", "--no-progress"]
    for extra, depth in ((["--speed", "5", "--depth", "0.3"], 0.3), (["--depth", "0.05"], 0.05)):
        out = tmp_path / f"d{depth}"
        result = corneasim_here("run", "needle", *quick, *extra, "--out", str(out))
        assert result.returncode == 0, result.stderr
        history = read_table(out / "history.csv")
        assert history["depth_mm"][-1] == pytest.approx(depth, rel=1e-9)


def test_needle_punctures_follow_the_cut_front_down_the_axis():
    """A depth on the axis is cut when an element the axis crosses there is deleted; the events
    are the front's arrival at the epithelium's last depth, the stroma's first and the cornea's last."""
    from corneasim.scenarios._punctures import column_events

    # epithelium 10 (z 0 to -0.1); stroma 11 and 12 side by side (-0.1 to -0.3), stroma 13 (-0.3 to -0.5)
    column = (np.array([10, 11, 12, 13]), np.array(["epithelium", "stroma", "stroma", "stroma"]),
              np.array([[0.0, -0.1], [-0.1, -0.3], [-0.1, -0.3], [-0.3, -0.5]]))
    assert column_events(column, {12: 2.0, 10: 1.0, 13: 5.0}) == {"epithelium": 1.0, "stroma": 2.0, "cornea": 5.0}
    # a stroma element deleted before the epithelium above it: the front waits for the epithelium
    assert column_events(column, {11: 0.5, 10: 1.0}) == {"epithelium": 1.0, "stroma": 1.0}
    # the deepest element still there: no cornea event
    assert "cornea" not in column_events(column, {12: 2.0, 10: 1.0})
