"""Stability check, presets, validation of material files, calibration and fitting."""

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.materials import (
    calibrate_cornea,
    calibrate_cornea_in_vivo,
    check_stability,
    fit_hyperelastic,
    homogeneous_nominal_stress,
    in_vivo_uniaxial_curve,
    list_presets,
    load_material,
    published_uniaxial_curve,
)
from corneasim.materials._kernel_form import FAILURE_VON_MISES


def test_stability_flags_seed_paper_constants():
    report = check_stability("mooney-rivlin", [10.59, -11.20, 0.05])
    assert not report.stable
    uniaxial = report.tests[0]
    assert uniaxial.test == "uniaxial"
    tension = [r for r in uniaxial.wrong_sign if r[0] >= 1.0]
    assert tension[0][0] == 1.0
    assert tension[0][1] == pytest.approx(11.20 / 10.59, rel=1e-8)  # stress root of the closed form
    assert any(low < 1.0 for low, _ in uniaxial.wrong_sign)  # positive stress in compression
    assert any(low <= 1.0 <= high for low, high in uniaxial.drucker)  # negative small-strain modulus


def test_stability_passes_stable_laws_and_finds_yeoh_limit():
    assert check_stability("neo-hooke", [0.3, 0.1]).stable
    assert check_stability("mooney-rivlin", [0.3, 0.1, 0.1]).stable
    # Yeoh with C20 < 0: uniaxial nominal stress has a maximum where dP/dlambda = 0 (Drucker fails around it)
    report = check_stability("yeoh", [0.5, -0.05, 0.0, 0.1])
    assert not report.stable and report.tests[0].drucker


def test_presets_load_and_default_is_stable(capsys):
    assert {"cornea", "seed-paper", "epithelium", "sclera"} <= set(list_presets())
    for name in ("cornea", "epithelium", "sclera"):
        material = load_material(name)
        assert check_stability(material.model, material.parameters()).stable
        assert 0.9e-9 < material.density < 1.2e-9
    assert capsys.readouterr().err == ""
    cornea = load_material("cornea").kernel_form()
    assert cornea.failure_criterion == FAILURE_VON_MISES and cornea.failure_limit == 5.0
    assert sum(cornea.prony_g) == pytest.approx(1 - 0.43 / 2.26)
    assert load_material("epithelium").failure.limit == 10.0


def test_seed_paper_warns_on_every_load(capsys):
    for _ in range(2):
        material = load_material("seed-paper")
        err = capsys.readouterr().err
        assert "UNSTABLE" in err and "1-1.058" in err and err.count("\n") == 1
    assert material.parameters()[1] == -11.20


def test_sclera_small_strain_moduli():
    sclera = load_material("sclera")
    assert sclera.youngs_modulus == pytest.approx(3.08)
    assert sclera.poisson_ratio == pytest.approx(0.49)


def test_cornea_preset_is_the_calibration():
    fit = calibrate_cornea()
    preset = load_material("cornea").parameters()
    assert fit.stability.stable
    np.testing.assert_allclose(fit.parameters[:2], preset[:2], rtol=2e-4)
    assert abs(fit.parameters[2] - preset[2]) < 1e-3
    # close to the published curve where that curve is physical (stretch 1.1-1.2)
    stretch = np.linspace(1.1, 1.2, 11)
    fitted = homogeneous_nominal_stress("yeoh", preset, "uniaxial", stretch)
    assert np.max(np.abs(fitted - published_uniaxial_curve(stretch))) < 0.1


@pytest.mark.parametrize("model, truth", [
    ("neo-hooke", [0.3]), ("mooney-rivlin", [0.3, 0.05]), ("yeoh", [0.2, 0.5, 0.1]),
    ("yeoh", [0.2, -0.02, 0.05])])
def test_fit_recovers_known_parameters(model, truth):
    stretch, biaxial = np.linspace(0.8, 1.6, 30), np.linspace(1.0, 1.4, 20)
    law = [*truth, 1.0]
    uniaxial = (stretch, homogeneous_nominal_stress(model, law, "uniaxial", stretch))
    equibiaxial = (biaxial, homogeneous_nominal_stress(model, law, "equibiaxial", biaxial))
    result = fit_hyperelastic(model, uniaxial, equibiaxial)
    np.testing.assert_allclose(result.parameters, truth, rtol=1e-4)
    assert result.stability.stable


def test_fit_never_returns_an_unstable_law():
    stretch = np.linspace(1.0, 1.2, 41)
    data = (stretch, homogeneous_nominal_stress("mooney-rivlin", [10.59, -11.20, 1.0], "uniaxial", stretch))
    for model in ("neo-hooke", "mooney-rivlin", "yeoh"):
        assert fit_hyperelastic(model, data).stability.stable


def write(tmp_path, text):
    path = tmp_path / "m.toml"
    path.write_text(text)
    return path


BASE = """name = "x"
density = 1.0e-9
[hyperelastic]
model = "yeoh"
c10 = 0.1
d1 = 0.05
"""


@pytest.mark.parametrize("text, fragment", [
    (BASE + "c99 = 1.0\n", "hyperelastic.yeoh.c99: unknown key"),
    (BASE.replace("c10 = 0.1", 'c10 = "soft"'), "hyperelastic.yeoh.c10"),
    (BASE.replace("c10 = 0.1", "c10 = -0.1"), "greater than 0"),
    (BASE.replace("d1 = 0.05", "d1 = 0.0"), "hyperelastic.yeoh.d1"),
    (BASE.replace('"yeoh"', '"rubber"'), "hyperelastic"),
    (BASE + "[viscoelastic]\nprony_moduli = [0.1, 0.2]\nlong_term_modulus = 0.4\nrelaxation_times = [1.0]\n",
     "equal length"),
    (BASE + "[failure]\ncriterion = \"von-mises\"\n", "limit must be > 0"),
    (BASE.replace("density = 1.0e-9", "density = -1.0"), "density"),
    ("name = 'x'\ndensity = [", "invalid TOML"),
])
def test_bad_material_files_are_one_line_errors(tmp_path, text, fragment):
    with pytest.raises(InputError) as error:
        load_material(write(tmp_path, text))
    message = str(error.value)
    assert fragment in message and "\n" not in message and "m.toml" in message


def test_unknown_preset_and_missing_file():
    with pytest.raises(InputError, match="unknown material 'nope'"):
        load_material("nope")
    with pytest.raises(InputError, match="file not found"):
        load_material("missing/file.toml")


def _published_slope(stretch):
    """dP/dlambda of the published incompressible uniaxial Mooney-Rivlin curve (closed form)."""
    c10, c01 = 10.59, -11.20
    return (2.0 * (1.0 + 2.0 * stretch**-3) * (c10 + c01 / stretch)
            - 2.0 * (stretch - stretch**-2) * c01 / stretch**2)


def test_in_vivo_curve_is_the_published_curve_re_referenced():
    stretch = np.linspace(1.0, 1.2, 9)
    np.testing.assert_allclose(in_vivo_uniaxial_curve(stretch, 0.0), published_uniaxial_curve(stretch),
                               atol=1e-14)
    assert in_vivo_uniaxial_curve(np.array([1.0]), 0.17)[0] == pytest.approx(0.0, abs=1e-14)
    # force balance of a strip prestretched to 1.17: N / A_vivo with A_vivo = A_0 / 1.17
    total = 1.17 * 1.1
    published = 2.0 * (total - total**-2) * (10.59 - 11.20 / total)
    prestress = 2.0 * (1.17 - 1.17**-2) * (10.59 - 11.20 / 1.17)
    assert in_vivo_uniaxial_curve(np.array([1.1]), 0.17)[0] == pytest.approx(1.17 * (published - prestress),
                                                                               rel=1e-12)
    h = 1e-6  # slope at the in-vivo state: lambda_0^2 P'(lambda_0)
    slope = (in_vivo_uniaxial_curve(np.array([1.0 + h]), 0.17)[0]
             - in_vivo_uniaxial_curve(np.array([1.0 - h]), 0.17)[0]) / (2 * h)
    assert slope == pytest.approx(1.17**2 * _published_slope(1.17), rel=1e-6)


def test_cornea_in_vivo_preset_is_its_calibration():
    fit = calibrate_cornea_in_vivo()
    preset = load_material("cornea-in-vivo").parameters()
    assert fit.stability.stable and fit.rmse < 0.05
    np.testing.assert_allclose(fit.parameters[:2], preset[:2], rtol=2e-4)
    assert abs(fit.parameters[2] - preset[2]) < 1e-3
    # much stiffer at small strain than the toe-region fit of the `cornea` preset
    assert preset[0] > 20 * load_material("cornea").parameters()[0]
