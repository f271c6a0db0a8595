"""``corneasim material``: every command runs; bad input is one line and exit code 2."""

import subprocess
import sys

import numpy as np
import pytest

from corneasim.cli.main import main
from corneasim.data import read_table
from corneasim.materials import homogeneous_nominal_stress, load_material


@pytest.fixture
def run_cli(capsys):
    """Run ``corneasim material ...`` in-process; returns (returncode, stdout, stderr)."""

    def run(*arguments):
        try:
            main(["material", *arguments])
            code = 0
        except SystemExit as stop:
            code = stop.code
        captured = capsys.readouterr()
        return subprocess.CompletedProcess(arguments, code, captured.out, captured.err)

    return run


def test_real_entry_point_bad_input():
    result = subprocess.run([sys.executable, "-m", "corneasim.cli.main", "material", "check", "nope"],
                            capture_output=True, text=True)
    assert_one_line_error(result, "unknown material 'nope'")


def assert_one_line_error(result, fragment):
    assert result.returncode == 2, result.stderr
    assert result.stderr.strip().count("\n") == 0 and "Traceback" not in result.stderr
    assert fragment in result.stderr


def test_list_and_report(run_cli):
    result = run_cli("list")
    assert result.returncode == 0 and "cornea" in result.stdout and "seed-paper" in result.stdout
    result = run_cli("report")
    assert result.returncode == 0
    for name in ("cornea", "epithelium", "sclera", "seed-paper", "UNSTABLE", "MPa"):
        assert name in result.stdout


def test_check_exit_status(run_cli):
    stable = run_cli("check", "cornea")
    assert stable.returncode == 0 and "STABLE" in stable.stdout
    unstable = run_cli("check", "seed-paper")
    assert unstable.returncode == 1 and "UNSTABLE" in unstable.stdout and "1-1.058" in unstable.stdout


def test_curve_writes_csv_and_png(run_cli, tmp_path):
    out, png = tmp_path / "curve.csv", tmp_path / "curve.png"
    result = run_cli("curve", "sclera", "--test", "equibiaxial", "--stretch", "0.9:1.2:7", "--out", str(out),
                     "--plot", str(png))
    assert result.returncode == 0, result.stderr
    table = read_table(out, required=("stretch", "nominal_stress_MPa", "cauchy_stress_MPa"))
    np.testing.assert_allclose(table["stretch"], np.linspace(0.9, 1.2, 7))
    # equibiaxial incompressible neo-Hooke: sigma = 2 C10 (lambda^2 - lambda^-4)
    c10 = load_material("sclera").parameters()[0]
    lam = table["stretch"]
    np.testing.assert_allclose(table["cauchy_stress_MPa"], 2 * c10 * (lam**2 - lam**-4), rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(table["nominal_stress_MPa"], table["cauchy_stress_MPa"] / lam, rtol=1e-7)
    assert png.stat().st_size > 1000


def test_curve_of_seed_paper_warns(run_cli, tmp_path):
    result = run_cli("curve", "seed-paper", "--out", str(tmp_path / "c.csv"))
    assert result.returncode == 0 and "warning" in result.stderr and "1-1.058" in result.stderr


def test_fit_prints_a_loadable_toml_block(run_cli, tmp_path):
    truth = [0.2, 0.5, 0.1]
    files = {}
    for test, stretch in (("uniaxial", np.linspace(0.8, 1.5, 15)), ("equibiaxial", np.linspace(1.0, 1.3, 7))):
        nominal = homogeneous_nominal_stress("yeoh", [*truth, 1.0], test, stretch)
        files[test] = tmp_path / f"{test}.csv"
        files[test].write_text("# synthetic Yeoh data\nstretch,nominal_stress_MPa\n"
                               + "".join(f"{float(s)!r},{float(p)!r}\n" for s, p in zip(stretch, nominal)))
    result = run_cli("fit", str(files["uniaxial"]), "--model", "yeoh", "--equibiaxial", str(files["equibiaxial"]))
    assert result.returncode == 0, result.stderr
    block = tmp_path / "fitted.toml"
    block.write_text(result.stdout)
    material = load_material(block)
    np.testing.assert_allclose(material.parameters()[:3], truth, rtol=1e-5)
    assert material.bulk_modulus == pytest.approx(30.0, rel=1e-6)


@pytest.mark.parametrize("arguments, fragment", [
    (("check", "no-such-material"), "unknown material 'no-such-material'"),
    (("curve", "cornea", "--stretch", "a:b", "--out", "x.csv"), "--stretch"),
    (("curve", "cornea", "--stretch", "1.2:0.8:5", "--out", "x.csv"), "MIN < MAX"),
    (("curve", "cornea", "--test", "shear", "--out", "x.csv"), "--test"),
    (("fit", "missing.csv", "--model", "yeoh"), "missing.csv"),
    (("fit", "DATA", "--model", "rubber"), "--model"),
])
def test_bad_input_is_one_line_exit_2(run_cli, arguments, fragment):
    assert_one_line_error(run_cli(*arguments), fragment)


def test_bad_files_are_one_line_exit_2(run_cli, tmp_path):
    bad_csv = tmp_path / "bad.csv"
    bad_csv.write_text("stretch,nominal_stress_MPa\n1.0,0.0\n1.1\n")
    assert_one_line_error(run_cli("fit", str(bad_csv), "--model", "yeoh"), "line 3")
    wrong_columns = tmp_path / "cols.csv"
    wrong_columns.write_text("lambda,P\n1.0,0.0\n")
    assert_one_line_error(run_cli("fit", str(wrong_columns), "--model", "yeoh"), "stretch")
    bad_toml = tmp_path / "bad.toml"
    bad_toml.write_text('name = "b"\ndensity = 1e-9\n[hyperelastic]\nmodel = "neo-hooke"\nc10 = 0.3\nd1 = -1.0\n')
    assert_one_line_error(run_cli("check", str(bad_toml)), "hyperelastic.neo-hooke.d1")
    prony = tmp_path / "prony.toml"
    prony.write_text('name = "p"\ndensity = 1e-9\n[hyperelastic]\nmodel = "neo-hooke"\nc10 = 0.3\nd1 = 0.1\n'
                     "[viscoelastic]\nprony_moduli = [0.1]\nlong_term_modulus = 0.2\nrelaxation_times = [1.0, 2.0]\n")
    assert_one_line_error(run_cli("check", str(prony)), "equal length")
