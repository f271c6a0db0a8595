"""Material-point driver: Prony ramp-and-hold against the linear viscoelastic closed form.

A strain ramp gamma(t) = gamma_0 t / t_r, held from t_r, in a material with the relaxation
function mu(t) = mu_0 (g_inf + sum g_i exp(-t / tau_i)) has the stress (Boltzmann
superposition, e.g. Findley, Lai & Onaran 1976, ch. 6)

    sigma(t) = mu_0 gamma_0 / t_r [g_inf t + sum g_i tau_i (1 - exp(-t / tau_i))],            t <= t_r
    sigma(t) = mu_0 gamma_0 / t_r [g_inf t_r + sum g_i tau_i (exp(-(t - t_r) / tau_i) - exp(-t / tau_i))], t > t_r

in shear; in uniaxial tension of a nearly incompressible solid (K >> mu) the modulus is
3 mu(t). Small strains (1e-3) keep the finite-strain law within 1e-5 of the linear one.
"""

import numpy as np
import pytest

from corneasim.cli.main import main as cli_main
from corneasim.errors import InputError
from corneasim.materials import load_material
from corneasim.materials._point_driver import (
    material_point_test, parse_strain_history, prony_reading, ramp_hold)

MATERIAL = """
name = "relaxing"
density = 1.0e-9
[hyperelastic]
model = "neo-hooke"
c10 = 0.5            # MPa: mu_0 = 1 MPa
d1 = {d1}            # 1/MPa
[viscoelastic]
prony_moduli = [0.3, 0.2, 0.1]       # MPa
long_term_modulus = 0.4              # MPa (sum 1.0 = mu_0: consistent)
relaxation_times = [0.5, 20.0, 900.0]  # s
"""


def closed_form(t, amplitude, ramp_time, modulus, weights, taus):
    g_inf = 1.0 - sum(weights)
    t = np.asarray(t, dtype=float)
    during = g_inf * t + sum(g * tau * (1 - np.exp(-t / tau)) for g, tau in zip(weights, taus))
    after = g_inf * ramp_time + sum(g * tau * (np.exp(-(t - ramp_time) / tau) - np.exp(-t / tau))
                                    for g, tau in zip(weights, taus))
    return modulus * amplitude / ramp_time * np.where(t <= ramp_time, during, after)


@pytest.fixture
def relaxing(tmp_path):
    def make(d1):
        path = tmp_path / f"relaxing_{d1}.toml"
        path.write_text(MATERIAL.format(d1=d1))
        return load_material(path)
    return make


def test_shear_ramp_hold_matches_the_closed_form(relaxing):
    material = relaxing(0.01)
    times, strains = ramp_hold(1e-3, 2.0, 1e4, ramp_steps=50, hold_steps=150)
    result = material_point_test(material, "shear", times, strains)
    weights, taus = material.viscoelastic.weights(), material.viscoelastic.relaxation_times
    expected = closed_form(times, 1e-3, 2.0, 1.0, weights, taus)
    loaded = times > 0
    error = np.abs(result["sigma_12_MPa"][loaded] / expected[loaded] - 1.0)
    assert error.max() < 5e-3
    assert result["sigma_12_MPa"][-1] == pytest.approx(1e-3 * 0.4, rel=1e-3)  # long-term g_inf mu_0 gamma


def test_uniaxial_relaxation_of_a_nearly_incompressible_solid(relaxing):
    material = relaxing(2.0 / 1e4)  # K = 1e4 MPa = 1e4 mu_0
    times, strains = ramp_hold(1e-3, 1.0, 5e3)
    result = material_point_test(material, "uniaxial", times, strains)
    weights, taus = material.viscoelastic.weights(), material.viscoelastic.relaxation_times
    expected = closed_form(times, 1e-3, 1.0, 3.0, weights, taus)
    loaded = times > 0
    assert np.abs(result["nominal_stress_MPa"][loaded] / expected[loaded] - 1.0).max() < 5e-3
    assert np.abs(result["sigma_22_MPa"]).max() < 1e-6 * np.abs(result["sigma_11_MPa"]).max()  # free sides
    assert result["stretch_2"][-1] == pytest.approx(1.0 - 0.5e-3, rel=1e-5)  # nu -> 1/2


def test_the_cornea_preset_relaxes_as_its_weights_say():
    material = load_material("cornea")
    times, strains = ramp_hold(1e-3, 1.0, 1e4, hold_steps=100)
    result = material_point_test(material, "shear", times, strains)
    weights, taus = material.viscoelastic.weights(), material.viscoelastic.relaxation_times
    expected = closed_form(times, 1e-3, 1.0, material.initial_shear_modulus, weights, taus)
    assert np.abs(result["sigma_12_MPa"][1:] / expected[1:] - 1.0).max() < 5e-3


def test_equibiaxial_elastic_small_strain_modulus(tmp_path):
    path = tmp_path / "elastic.toml"
    path.write_text('name = "e"\ndensity = 1e-9\n[hyperelastic]\nmodel = "linear-elastic"\n'
                    'youngs_modulus = 2.0\npoisson_ratio = 0.3\n')
    result = material_point_test(load_material(path), "equibiaxial", [0.0, 1.0], [0.0, 1e-5])
    assert result["sigma_11_MPa"][-1] == pytest.approx(2.0 / 0.7 * 1e-5, rel=1e-4)  # E / (1 - nu) eps
    assert result["stretch_3"][-1] == pytest.approx(1.0 - 2 * 0.3 / 0.7 * 1e-5, rel=1e-9)


def test_prony_reading_says_how_absolute_moduli_are_read(relaxing):
    assert prony_reading(relaxing(0.01)) is None  # sum E_i + E_inf = mu_0
    note = prony_reading(load_material("cornea"))
    assert "read as weights" in note and "2.26 MPa) are not used" in note


@pytest.mark.parametrize("text", ["ramp-hold:0.1,1", "ramp-hold:a,1,2", "nowhere.csv", "ramp-hold:0.1,0,2"])
def test_bad_strain_history_is_input_error(text):
    with pytest.raises(InputError):
        parse_strain_history(text)


def test_cli_writes_the_table_and_notes_the_prony_reading(tmp_path, capsys):
    table = tmp_path / "strain.csv"
    table.write_text("time_s,strain\n1,0.001\n100,0.001\n")
    with pytest.raises(SystemExit) as stop:
        cli_main(["material", "test", "cornea", "--history", "shear", "--strain", str(table),
                  "--out", str(tmp_path / "out.csv")])
    assert stop.value.code == 0
    captured = capsys.readouterr()
    assert "not used" in captured.err and len(captured.err.strip().splitlines()) == 1
    lines = (tmp_path / "out.csv").read_text().splitlines()
    assert lines[0].startswith("time_s,strain") and len(lines) == 4  # the added origin and the two rows
    with pytest.raises(SystemExit) as stop:
        cli_main(["material", "test", "cornea", "--history", "shear", "--strain", "ramp-hold:x",
                  "--out", str(tmp_path / "bad.csv")])
    assert stop.value.code == 2
