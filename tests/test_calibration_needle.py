"""The strain-stiffening stage of the needle calibration: the ``cornea-needle`` preset and the script's Yeoh variants."""

import sys
from pathlib import Path

import numpy as np
import pytest

from corneasim.materials import check_stability, load_material
from corneasim.materials._calibration import in_vivo_uniaxial_curve
from corneasim.materials._homogeneous import nominal_stress

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "validation"))
import calibrate_needle  # noqa: E402


def yeoh_uniaxial(stretch, c10, c20, c30):
    """Incompressible uniaxial nominal stress of a Yeoh law, MPa (closed form, docs/materials.md)."""
    i1 = stretch**2 + 2.0 / stretch
    w1 = c10 + 2.0 * c20 * (i1 - 3.0) + 3.0 * c30 * (i1 - 3.0) ** 2
    return 2.0 * (stretch - stretch**-2) * w1


def test_yeoh_variant_changes_only_the_three_constants(tmp_path):
    path = calibrate_needle.yeoh_variant("yeoh:0.7,450,12.5", tmp_path)
    variant, base = load_material(str(path), warn=False), load_material("cornea-in-vivo", warn=False)
    assert variant.kernel_form().c10 == 0.7 and variant.kernel_form().c20 == 450.0
    assert variant.kernel_form().c30 == 12.5
    for field in ("density", "c01", "d1", "prony_g", "prony_tau", "failure_criterion", "failure_limit"):
        assert getattr(variant.kernel_form(), field) == getattr(base.kernel_form(), field), field


def test_overrides_point_the_stroma_at_the_variant_and_set_the_step(tmp_path):
    parameters = dict(tip="rounded", epithelium_failure_MPa=10.0, stroma_failure_MPa=200.0, friction="karnopp",
                      stroma_material="yeoh:1,1000,0", target_time_step_s=1.0e-5)
    overrides = dict(o.split("=", 1) for o in calibrate_needle.overrides(parameters, "coarse", tmp_path))
    assert Path(overrides["materials.stroma.material"]).is_absolute()
    assert load_material(overrides["materials.stroma.material"], warn=False).kernel_form().c20 == 1000.0
    assert float(overrides["solver.target_time_step"]) == 1.0e-5
    assert float(overrides["materials.stroma.failure_limit"]) == 200.0


def test_cornea_needle_preset_is_stable_and_matches_the_documented_curve():
    material = load_material("cornea-needle", warn=False)
    record = material.kernel_form()
    assert check_stability("yeoh", [record.c10, record.c20, record.c30, record.d1]).stable
    stretch = np.array([1.01, 1.02, 1.03, 1.05, 1.10])
    expected = yeoh_uniaxial(stretch, record.c10, record.c20, record.c30)
    np.testing.assert_allclose(nominal_stress("yeoh", [record.c10, record.c20, record.c30, 1.0], "uniaxial", stretch),
                               expected, rtol=1e-9)
    # docs/materials.md: softer than the in-vivo target curve at 1 % strain, stiffer at 2 %, 6.8x at 5 %
    target = in_vivo_uniaxial_curve(stretch)
    assert expected[0] < target[0] and expected[1] > target[1]
    assert expected[3] / target[3] == pytest.approx(6.8, abs=0.1)
    # small-strain Young's modulus 6 C10 = 7.8 MPa, below the in-vivo law's 19.7 MPa
    assert 6.0 * record.c10 == pytest.approx(7.8)
