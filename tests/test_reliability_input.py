"""Meaningless or malformed input is one line and exit 2, found before any file is written."""

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from corneasim.cli.main import main
from corneasim.cli.run import RESULTS_ROOT, default_out_dir, folder_name
from corneasim.scenarios._meaning import ADDED_MASS_WARNING, check_setup
from corneasim.scenarios._registry import load_scenario, scenario_text

COARSE = ["--preset", "coarse", "--no-progress"]


def cli(capsys, *arguments):
    """Exit code, stdout and stderr of ``corneasim ARGUMENTS`` run in this process."""
    with pytest.raises(SystemExit) as exit_:
        main([str(a) for a in arguments])
    out, err = capsys.readouterr()
    return exit_.value.code, out, err


def assert_one_line_exit_2(code, err, *words):
    assert code == 2, err
    assert err.startswith("corneasim: error: ") and err.count("\n") == 1, err
    for word in words:
        assert word in err, (word, err)


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.mark.parametrize("options, words", [
    (["--set", "solver.end_time=true"], ["solver.end_time", "got true"]),
    (["--set", 'solver.history_every="20"'], ["solver.history_every", '"20"']),
    (["--set", "solver.end_time=inf"], ["solver.end_time", "finite"]),
    (["--set", "solver.damping=nan"], ["solver.damping", "finite"]),
    (["--set", "instrument.motion.insertion.rate=-1.0"], ["instrument.motion.insertion.rate", "> 0"]),
    (["--set", "solver.target_time_step=1"], ["solver.target_time_step", "steps"]),
    (["--set", "solver.time_step=0.5"], ["solver.time_step", "steps"]),
    (["--set", "materials.stroma.failure_limit=0"], ["materials.stroma.failure_limit"]),
    (["--depth", "inf"], ["--depth", "finite"]),
    (["--depth", "-1"], ["--depth"]),
    (["--speed", "nan"], ["--speed", "finite"]),
])
def test_meaningless_values_are_refused_naming_the_key_and_nothing_is_written(capsys, workdir, options, words):
    code, _, err = cli(capsys, "run", "needle", *COARSE, *options)
    assert_one_line_exit_2(code, err, *words)
    assert "fracture_energy" not in err  # each value is blamed on itself
    assert list(workdir.iterdir()) == []


def test_a_non_finite_material_constant_is_refused_before_the_folder_exists(capsys, workdir):
    (workdir / "soft.toml").write_text('name = "soft"\ndensity = 1.0e-9\n[hyperelastic]\nmodel = "yeoh"\n'
                                       "c10 = 0.3\nc20 = inf\nc30 = 0.0\nd1 = 0.07\n[failure]\ncriterion = \"von-mises\"\nlimit = 10.0\n")
    code, _, err = cli(capsys, "run", "needle", *COARSE, "--set", "materials.epithelium.material=soft.toml",
                       "--out", workdir / "out")
    assert_one_line_exit_2(code, err, "c20")
    assert not (workdir / "out").exists()


def test_mesh_material_and_preload_problems_leave_no_results_folder(capsys, workdir):
    (workdir / "broken.inp").write_text("*NODE\n1, 0.0\n")
    scenario = (workdir / "s.toml")
    scenario.write_text(scenario_text("needle").replace('generator = "eye-axisymmetric"', 'file = "broken.inp"'))
    code, _, err = cli(capsys, "run", scenario, "--no-progress", "--out", workdir / "a")
    assert_one_line_exit_2(code, err, "broken.inp")
    code, _, err = cli(capsys, "run", "needle", *COARSE, "--set", "materials.stroma.material=no-such-material",
                       "--out", workdir / "b")
    assert_one_line_exit_2(code, err, "no-such-material")
    (workdir / "empty").mkdir()
    code, _, err = cli(capsys, "run", "needle", *COARSE, "--preload-from", workdir / "empty", "--out", workdir / "c")
    assert_one_line_exit_2(code, err, "--preload-from")
    assert sorted(p.name for p in workdir.iterdir()) == ["broken.inp", "empty", "s.toml"]


@pytest.mark.parametrize("name", ["../../../../elsewhere/x/ESCAPED", "/etc/passwd", "..", ".hidden", "a/../../b", "", "\x00",
                                  "C:\\Windows\\x", "needle 1 mm/s"])
def test_the_default_folder_stays_inside_the_results_root(name):
    scenario = load_scenario("needle", [f"name={name!r}".replace("'", '"') if '"' not in name else "name=x"])[0]
    folder = default_out_dir(scenario)
    assert folder.parent == RESULTS_ROOT
    assert folder.name not in ("", ".", "..") and not folder.name.startswith(".")
    assert (Path.cwd() / folder).resolve().parent == (Path.cwd() / RESULTS_ROOT).resolve()


def test_folder_names_keep_letters_digits_and_a_few_marks():
    assert folder_name("needle-5") == "needle-5"
    assert folder_name("Hornhaut_ü 2.5") == "Hornhaut_ü-2.5"
    assert folder_name("../..") == "run"


def test_output_paths_that_are_files_are_one_line(capsys, workdir):
    (workdir / "afile").write_text("keep")
    for out in (workdir / "afile", workdir / "afile" / "sub"):
        code, _, err = cli(capsys, "run", "needle", *COARSE, "--out", out)
        assert_one_line_exit_2(code, err, "afile")
    code, _, err = cli(capsys, "material", "curve", "epithelium", "--test", "uniaxial", "--stretch", "1:1.2:5",
                       "--out", workdir / "afile" / "curve.csv")
    assert_one_line_exit_2(code, err, "curve.csv")
    assert (workdir / "afile").read_text() == "keep"


def test_a_binary_scenario_file_is_one_line(capsys, workdir):
    (workdir / "binary.toml").write_bytes(bytes(range(256)) * 4)
    for command in ("run", "show"):
        code, _, err = cli(capsys, command, workdir / "binary.toml")
        assert_one_line_exit_2(code, err, "binary.toml", "UTF-8")


def test_resume_refuses_a_completed_run_and_stray_options(capsys, workdir):
    folder = workdir / "done"
    folder.mkdir()
    (folder / "scenario.toml").write_text(scenario_text("needle"))
    (folder / "summary.json").write_text('{"status": "completed"}')
    code, _, err = cli(capsys, "run", "--resume", folder)
    assert_one_line_exit_2(code, err, "completed")
    code, _, err = cli(capsys, "run", "--resume", folder, "--overwrite")
    assert_one_line_exit_2(code, err, "--resume")
    code, _, err = cli(capsys, "run", "--resume", workdir)
    assert_one_line_exit_2(code, err, "scenario.toml")


def test_extreme_added_mass_is_a_warning_naming_the_block():
    density_scale = np.array([1.0, 3.0e7, 2.0])
    model = SimpleNamespace(added_mass_fraction=2.3e7, density_scale=density_scale,
                            block_of=lambda element: ["stroma", "epithelium", "sclera"][element])
    setup = SimpleNamespace(model=model, warnings=[],
                            scenario=SimpleNamespace(solver=SimpleNamespace(target_time_step=2e-5)))
    check_setup(setup)
    assert len(setup.warnings) == 1 and "epithelium" in setup.warnings[0] and "2.3e+07" in setup.warnings[0]
    model.added_mass_fraction = ADDED_MASS_WARNING / 2
    setup.warnings.clear()
    check_setup(setup)
    assert setup.warnings == []
