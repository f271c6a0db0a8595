"""Published ranges of the constants (``materials/published_ranges.toml``) and their check.

The file is checked for form (every entry sourced, low <= high, ranges without numbers marked
unverified); the checker against synthetic ranges whose verdicts are known by construction; the
constants of a material against the closed-form small-strain moduli of its law.
"""

from pathlib import Path

import numpy as np
import pytest

from corneasim.cli.main import main
from corneasim.errors import InputError
from corneasim.materials import (
    check_constants, load_material, material_constants, out_of_range, published_ranges, scenario_constants)
from corneasim.materials._ranges import SECANT_STRETCH, TISSUES, parse_ranges
from corneasim.scenarios import load_scenario

SYNTHETIC = """
[[range]]
key = "stroma.toughness"
cite = "synthetic"
unit = "N/mm"
low = 0.2
high = 5.0
species = "none"
tissue = "none"
source = "synthetic"
verified = true

[[range]]
key = "stroma.fibre_k2"
cite = "synthetic"
unit = "1"
species = "none"
tissue = "none"
source = "synthetic"
verified = false
"""


def test_shipped_ranges_parse_and_every_entry_is_sourced():
    ranges = published_ranges()
    assert len(ranges) >= 15
    for key, item in ranges.items():
        tissue, _, quantity = key.partition(".")
        assert tissue in (*TISSUES, "contact") and quantity, key
        assert item.source.strip() and item.cite.strip() and item.unit.strip(), key
        if item.bounded:
            assert item.low <= item.high, key
        else:
            assert not item.verified, key


def test_checker_flags_outside_and_passes_inside():
    ranges = parse_ranges(SYNTHETIC)
    checks = check_constants({"stroma.toughness": 0.0042, "stroma.fibre_k2": 70.0, "no.such_key": 1.0}, ranges)
    assert [(c.key, c.status) for c in checks] == [("stroma.toughness", "below"), ("stroma.fibre_k2", "unverified")]
    assert [c.status for c in check_constants({"stroma.toughness": 6.0}, ranges)] == ["above"]
    assert [c.status for c in check_constants({"stroma.toughness": 0.2}, ranges)] == ["inside"]
    assert out_of_range({"stroma.toughness": 1.0, "stroma.fibre_k2": 1e9}, ranges) == []
    assert [c.key for c in out_of_range({"stroma.toughness": 9.0}, ranges)] == ["stroma.toughness"]


@pytest.mark.parametrize("change, fragment", [
    (("low = 0.2", "low = 7.0"), "expected low <= high"),
    (("high = 5.0\n", ""), "give both low and high"),
    (('source = "synthetic"\nverified = true', 'source = " "\nverified = true'), "empty source"),
    (('verified = false', 'verified = true'), "must have verified = false"),
    (('cite = "synthetic"\nunit = "N/mm"', 'unit = "N/mm"'), "missing key 'cite'"),
])
def test_bad_ranges_file_is_one_line_error(change, fragment):
    with pytest.raises(InputError, match=fragment):
        parse_ranges(SYNTHETIC.replace(*change, 1))


def test_material_constants_are_the_laws_small_strain_moduli(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text('name = "m"\ndensity = 1.0e-9\n[hyperelastic]\nmodel = "neo-hooke"\nc10 = 0.2\nd1 = 0.1\n'
                    '[failure]\ncriterion = "von-mises"\nlimit = 3.0\n')
    values = material_constants(load_material(path), "epithelium")
    lam, mu, bulk = SECANT_STRETCH, 0.4, 20.0
    assert values["epithelium.ground_shear_modulus"] == pytest.approx(mu)
    assert values["epithelium.youngs_modulus"] == pytest.approx(9 * bulk * mu / (3 * bulk + mu))
    assert values["epithelium.poisson_ratio"] == pytest.approx((3 * bulk - 2 * mu) / (2 * (3 * bulk + mu)))
    # incompressible neo-Hooke uniaxial nominal stress P = 2 C10 (lambda - lambda^-2)
    assert values["epithelium.in_plane_modulus"] == pytest.approx(0.4 * (lam - lam**-2) / (lam - 1.0), rel=1e-9)
    assert values["epithelium.tensile_strength"] == 3.0 and values["epithelium.density"] == 1.0e-9
    with pytest.raises(InputError, match="tissue"):
        material_constants(load_material(path), "cornea")


def test_fibre_constants_in_degrees(tmp_path):
    path = tmp_path / "f.toml"
    path.write_text('name = "f"\ndensity = 1.0e-9\n[hyperelastic]\nmodel = "holzapfel-gasser-ogden"\nc10 = 0.002\n'
                    'k1 = 0.1\nk2 = 10.0\nkappa = 0.2\nfibre_angle = 30.0\nd1 = 0.1\n')
    values = material_constants(load_material(path), "stroma")
    assert values["stroma.fibre_angle"] == pytest.approx(30.0)
    assert (values["stroma.fibre_k1"], values["stroma.fibre_k2"], values["stroma.fibre_dispersion"]) == (0.1, 10.0, 0.2)
    assert values["stroma.ground_shear_modulus"] == pytest.approx(0.004)


def test_scenario_fracture_constants_are_read_from_their_keys():
    scenario, _, base = load_scenario("needle", ["materials.stroma.failure_limit=7.5",
                                                 "materials.stroma.fracture_energy=0.01"])
    values = scenario_constants(scenario, base)
    assert values["stroma.tensile_strength"] == 7.5 and values["stroma.toughness"] == 0.01
    assert [c.status for c in check_constants({"stroma.toughness": values["stroma.toughness"]})] == ["below"]
    scenario, _, base = load_scenario("trephine", ["instrument.contact.cutting_toughness=0.3",
                                                   "instrument.contact.friction.coefficient=0.2"])
    values = scenario_constants(scenario, base)
    assert values["stroma.toughness"] == values["epithelium.toughness"] == 0.3
    assert values["contact.friction_coefficient"] == 0.2
    cut = Path(__file__).resolve().parents[1] / "validation" / "needle_cut.toml"
    scenario, _, base = load_scenario(str(cut), ["cut.blocks.stroma.strength=4.5",
                                                 "cut.blocks.epithelium.fracture_energy=0.12"])
    values = scenario_constants(scenario, base)
    assert values["stroma.tensile_strength"] == 4.5 and values["epithelium.toughness"] == 0.12


@pytest.mark.parametrize("youngs_modulus, code, status", [(1.0, 0, "inside"), (10.0, 1, "above")])
def test_cli_check_ranges(tmp_path, capsys, youngs_modulus, code, status):
    path = tmp_path / "s.toml"
    path.write_text(f'name = "s"\ndensity = 1.0e-9\n[hyperelastic]\nmodel = "linear-elastic"\n'
                    f'youngs_modulus = {youngs_modulus}\npoisson_ratio = 0.49\n')
    try:
        main(["material", "check", str(path), "--ranges", "--tissue", "sclera"])
        result = 0
    except SystemExit as stop:
        result = stop.code
    out = capsys.readouterr().out
    line = next(line for line in out.splitlines() if line.startswith("sclera.youngs_modulus"))
    key, value, low, _, high, unit, verdict = line.split()[:7]
    assert result == code and verdict == status, out
    assert np.isclose(float(value), youngs_modulus) and (float(low), float(high), unit) == (0.2, 3.08, "MPa")


def test_in_plane_modulus_of_orthogonal_fibres_is_the_softest_direction(tmp_path):
    """Families at +-45 degrees, pulled along their bisector: with stiff fibres the strip narrows
    at constant fibre length, lambda_1^2 + lambda_2^2 = 2, and the neo-Hookean matrix alone
    resists, W = mu/2 (1 / (lambda^2 (2 - lambda^2)) - 1), whose small-strain modulus is 4 mu;
    along a family the fibres carry the load and the modulus is far larger."""
    path = tmp_path / "f.toml"
    path.write_text('name = "f"\ndensity = 1.0e-9\n[hyperelastic]\nmodel = "holzapfel-gasser-ogden"\nc10 = 0.0025\n'
                    'k1 = 5.0\nk2 = 0.0\nkappa = 0.0\nfibre_angle = 45.0\nd1 = 0.1\n')
    mu, lam = 0.005, SECANT_STRETCH
    nominal = mu / 2 * (-(4 * lam - 4 * lam**3) / (lam**2 * (2 - lam**2)) ** 2)  # dW/dlambda
    modulus = material_constants(load_material(path), "stroma")["stroma.in_plane_modulus"]
    assert modulus == pytest.approx(nominal / (lam - 1.0), rel=0.02)
    assert modulus == pytest.approx(4 * mu, rel=0.05)
