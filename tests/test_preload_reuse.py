"""A run that starts from another run's settled preload gives the same results bit for bit."""

import numpy as np
import pytest

from cli_helpers import corneasim as corneasim_cli, corneasim_here

import corneasim
from corneasim.errors import InputError
from corneasim.scenarios._preload_reuse import PRELOAD_FILE, _first_difference

# a short coarse needle with deletions: cut through its epithelium before 0.05 mm
QUICK = ["mesh.preset=coarse", "preload.duration=0.02", "preload.damping=400", "solver.end_time=0.05",
         "solver.field_count=0", "materials.epithelium.failure_limit=1.0", "materials.stroma.failure_limit=2.0"]
FIVE = ["instrument.motion.insertion.rate=5", "solver.end_time=0.01"]


@pytest.fixture(scope="module")
def settled(tmp_path_factory):
    """A run that settles its own preload (and writes it), at 1 mm/s."""
    folder = tmp_path_factory.mktemp("settled")
    return folder, corneasim.run_scenario("needle", QUICK, out_dir=folder)


def assert_same_histories(one, two):
    assert one.keys() == two.keys()
    for column in one:
        np.testing.assert_array_equal(one[column], two[column], err_msg=column)


def test_a_run_from_a_saved_preload_is_the_same_run(settled):
    folder, own = settled
    assert (folder / PRELOAD_FILE).is_file()
    assert own.history["deleted_elements"][-1] > 0  # the comparison covers deletions
    reused = corneasim.run_scenario("needle", QUICK, preload_from=folder)
    assert_same_histories(own.history, reused.history)
    assert reused.deletions == own.deletions
    assert reused.summary["punctures"] == own.summary["punctures"]
    assert reused.summary["run"]["steps"] == own.summary["run"]["steps"]
    assert reused.summary["run"]["preload"]["reused_from"] == str(folder)
    assert "reused_from" not in own.summary["run"]["preload"]
    assert reused.summary["run"]["preload"]["out_of_balance"] == own.summary["run"]["preload"]["out_of_balance"]


def test_another_speed_from_the_same_preload_is_the_run_at_that_speed(settled):
    """The instrument's motion acts only after the preload: a 5 mm/s run started from the
    1 mm/s run's preload is the 5 mm/s run that settles its own."""
    folder, _ = settled
    own = corneasim.run_scenario("needle", [*QUICK, *FIVE])
    reused = corneasim.run_scenario("needle", [*QUICK, *FIVE], preload_from=folder / PRELOAD_FILE)
    assert_same_histories(own.history, reused.history)


def test_a_preload_of_another_eye_is_refused_naming_the_key(settled):
    folder, _ = settled
    with pytest.raises(InputError, match=r"another value of preload\.damping"):
        corneasim.run_scenario("needle", [*QUICK, "preload.damping=300"], preload_from=folder)
    with pytest.raises(InputError, match=r"another value of materials\.stroma\.failure_limit"):
        corneasim.run_scenario("needle", [*QUICK, "materials.stroma.failure_limit=3.0"], preload_from=folder)


def test_cli_errors_are_one_line_exit_2(settled, tmp_path):
    folder, _ = settled
    sets = [item for override in QUICK for item in ("--set", override)]
    for run, arguments in ((corneasim_cli, ["--preload-from", str(tmp_path / "nowhere")]),
                           (corneasim_here, ["--preload-from", str(folder), "--set", "solver.safety_factor=0.8"]),
                           (corneasim_here, ["--preload-from", str(folder), "--set", "preload.duration=0.03"])):
        result = run("run", "needle", *sets, *arguments, "--out", str(tmp_path / "x"), "--no-progress")
        assert result.returncode == 2, (arguments, result.stderr)
        assert len(result.stderr.strip().splitlines()) == 1, result.stderr


def test_first_difference_names_the_dotted_path():
    assert _first_difference({"a": {"b": 1, "c": [1, 2]}}, {"a": {"b": 1, "c": [1, 2]}}) is None
    assert _first_difference({"a": {"b": 1}}, {"a": {"b": 2}}) == "a.b"
    assert _first_difference({"a": [{"x": 1}, {"x": 2}]}, {"a": [{"x": 1}, {"x": 3}]}) == "a[1].x"
    assert _first_difference({"a": 1}, {"a": 1, "b": 2}) == "b"
    assert _first_difference({"a": [1]}, {"a": [1, 2]}) == "a"


def test_resume_and_a_reused_preload_do_not_mix(settled):
    from corneasim.scenarios._registry import load_scenario
    from corneasim.scenarios._runner import simulate

    folder, _ = settled
    scenario, _, base = load_scenario("needle", QUICK)
    with pytest.raises(InputError, match="not --resume"):
        simulate(scenario, out_dir=folder, base_dir=base, resume=True, preload_from=folder, progress=False)


def test_a_run_resumed_inside_its_preload_saves_a_preload_that_can_be_reused(tmp_path):
    """Interrupted in the middle of the preload (a checkpoint there) and resumed, a run still
    writes its settled state with the key of its eye; a run from it is the resumed run."""
    from corneasim.scenarios._build import build
    from corneasim.scenarios._registry import load_scenario
    from corneasim.scenarios._runner import CHECKPOINT, simulate
    from corneasim.solver import new_state, preload, save_checkpoint

    scenario, _, base = load_scenario("needle", QUICK)
    setup = build(scenario, base)
    state = new_state(setup.model)
    for _ in preload(setup.model, state, setup.preload_duration / 2, scenario.preload.damping,
                     history_every=scenario.solver.history_every, hooks=setup.hooks):
        pass
    save_checkpoint(tmp_path / CHECKPOINT, setup.model, state, setup.hooks)
    resumed = simulate(scenario, out_dir=tmp_path, base_dir=base, resume=True, progress=False)
    reused = simulate(scenario, base_dir=base, preload_from=tmp_path, progress=False)
    procedure = resumed.history["time_s"] > -1e-9  # the preload's last row is the procedure's t = 0
    for column in reused.history:
        np.testing.assert_array_equal(reused.history[column], resumed.history[column][procedure],
                                      err_msg=column)
