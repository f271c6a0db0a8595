"""The relaxation example (examples/relaxation/): a confined column against the Prony closed form.

The tiny run (1 s ramp, held to 40 s, beyond the shortest relaxation time 8.83 s) must follow
the closed form within 0.5% once loaded (measured 0.066%); the recipe's mass scaling keeps it
to about 10^4 steps where the column's own stable step would need 3 x 10^6.
"""

import sys
from pathlib import Path

import numpy as np
import pytest

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "relaxation"
sys.path.insert(0, str(EXAMPLE))
import relaxation  # noqa: E402


def test_relaxation_matches_the_prony_closed_form(tmp_path):
    outcome = relaxation.main("tiny", tmp_path)
    assert outcome["error"] < 0.005
    result = outcome["result"]
    assert result.summary["run"]["steps"] < 20000 and result.summary["quasi_static"]["met"]
    stress = result.history["column_zz_MPa"]
    assert stress[-1] > stress.min() * 0.99  # it relaxed after the ramp's peak


def test_closed_form_limits():
    material = relaxation.load_material(relaxation.HERE / "relaxing.toml", warn=False)
    long_term = relaxation.closed_form(1e9, 1.0, material)
    g_inf = 1 - sum(material.viscoelastic.weights())
    expected = -(material.bulk_modulus + 4 / 3 * material.initial_shear_modulus * g_inf) * relaxation.STRAIN
    assert long_term == pytest.approx(expected, rel=1e-9)
    instant = relaxation.closed_form(1e-6, 1e-6, material)  # a step: the instantaneous modulus
    assert instant == pytest.approx(-(material.bulk_modulus + 4 / 3 * material.initial_shear_modulus)
                                    * relaxation.STRAIN, rel=1e-3)
    assert np.isfinite(relaxation.closed_form(np.linspace(0, 10, 5), 2.0, material)).all()
