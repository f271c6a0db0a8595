"""``corneasim material curve|check|report`` with the fibre-reinforced stroma law.

The curves are checked against the closed forms of tests/test_materials_fibre.py for a
law whose two families both lie along e1 (fibre_angle = 0): along them (the bisector),
sigma_11 = 2 C10 (l^2 - 1/l) + 4 Psi'(E) [kappa (l^2 - 1/l) + (1 - 3 kappa) l^2]; across
them and through the thickness with kappa = 0 the fibres shorten, stay idle, and the
matrix's 2 C10 (l^2 - 1/l) remains.
"""

import numpy as np
import pytest

from corneasim.cli.main import main
from corneasim.data import read_table

C10, K1, K2 = 0.025, 0.2, 30.0


def material_file(tmp_path, kappa, extra=""):
    path = tmp_path / f"hgo-{kappa}.toml"
    path.write_text(f'name = "aligned"\ndensity = 1.062e-9\n[hyperelastic]\nmodel = "holzapfel-gasser-ogden"\n'
                    f"c10 = {C10}\nk1 = {K1}\nk2 = {K2}\nkappa = {kappa}\nfibre_angle = 0.0\nd1 = 0.0667\n{extra}")
    return path


@pytest.fixture
def run(capsys):
    """Run ``corneasim material ...`` in-process; returns (exit code, stdout, stderr)."""

    def run_material(*arguments):
        try:
            code = main(["material", *arguments])
        except SystemExit as stop:
            code = stop.code
        captured = capsys.readouterr()
        return code, captured.out, captured.err

    return run_material


def curve(run, tmp_path, material, direction):
    out = tmp_path / f"{direction}.csv"
    code, _, err = run("curve", str(material), "--stretch", "1.02:1.2:4", "--direction", direction, "--out", str(out))
    assert code == 0, err
    table = read_table(out, required=("stretch", "nominal_stress_MPa", "cauchy_stress_MPa"))
    np.testing.assert_allclose(table["nominal_stress_MPa"], table["cauchy_stress_MPa"] / table["stretch"], rtol=1e-7)
    return table["stretch"], table["cauchy_stress_MPa"]


def test_curves_along_across_and_through_the_fibres(run, tmp_path):
    kappa = 0.1
    lam, sigma = curve(run, tmp_path, material_file(tmp_path, kappa), "bisector")
    E = kappa * (lam**2 + 2.0 / lam - 3.0) + (1.0 - 3.0 * kappa) * (lam**2 - 1.0)
    fibre = 4.0 * K1 * E * np.exp(K2 * E * E) * (kappa * (lam**2 - 1.0 / lam) + (1.0 - 3.0 * kappa) * lam**2)
    np.testing.assert_allclose(sigma, 2.0 * C10 * (lam**2 - 1.0 / lam) + fibre, rtol=1e-7)
    aligned = material_file(tmp_path, 0.0)
    for direction in ("across", "through"):
        lam, sigma = curve(run, tmp_path, aligned, direction)
        np.testing.assert_allclose(sigma, 2.0 * C10 * (lam**2 - 1.0 / lam), rtol=1e-7)


def test_check_and_report_know_the_preset(run):
    code, out, _ = run("check", "stroma-hgo")
    assert code == 0 and "STABLE" in out and "stretch 0.5 to 2" in out
    code, out, err = run("report")
    assert code == 0, err
    block = out.split("stroma-hgo:")[1].split("\n\n")[0]
    for fragment in ("holzapfel-gasser-ogden", "k2 = 70 dimensionless", "fibre_angle = 45 degrees",
                     "along the fibres' bisector", "along ", "across ", "through ", "stability      stable"):
        assert fragment in block


@pytest.mark.parametrize("key, value", [("kappa", "0.5"), ("k1", "-0.2")])
def test_bad_constant_is_one_line_and_exit_code_2(run, tmp_path, key, value):
    path = tmp_path / "bad.toml"
    text = material_file(tmp_path, 0.1).read_text().replace(f"{key} = ", f"{key} = {value} #")
    path.write_text(text)
    code, _, err = run("check", str(path))
    assert code == 2 and err.strip().count("\n") == 0
    assert f"hyperelastic.holzapfel-gasser-ogden.{key}" in err


def test_a_stretch_beyond_the_range_of_float64_is_one_line_and_exit_code_2(run, tmp_path):
    code, _, err = run("curve", "stroma-hgo", "--stretch", "1:3:3", "--direction", "along",
                       "--out", str(tmp_path / "c.csv"))
    assert code == 2 and err.strip().count("\n") == 0
    assert "uniaxial test (along) at stretch 3" in err and "float64" in err
