"""History requests: node-set and element-set columns, and prescribed motions logged.

Truth: a cylinder (radius R = 1 mm, height H = 1 mm, E = 1 MPa) on a frictionless base
compressed quasi-statically by u = 0.01 mm is in uniaxial stress: sigma_zz = -E u / H
everywhere, the other components 0, the base carries F = E pi R^2 u / H, and the stored
energy is E (u / H)^2 pi R^2 H / 2.
"""

import numpy as np
import pytest

import corneasim
from corneasim.errors import InputError

from byom_helpers import compression_scenario

REQUESTS = """
[[history]]
name = "top"
node_set = "top"
quantity = "displacement"
components = ["z"]
[[history]]
name = "base"
node_set = "bottom"
quantity = "reaction"
components = ["z"]
reduce = "nodes"
[[history]]
name = "rim"
node_set = "top"
quantity = "velocity"
reduce = "max"
[[history]]
name = "solid"
element_set = "solid"
quantity = "stress"
[[history]]
name = "energy"
element_set = "solid"
quantity = "strain_energy"
"""


def _scenario(tmp_path, requests=REQUESTS):
    path = compression_scenario(tmp_path)
    path.write_text(path.read_text().replace("[solver]", requests + "\n[solver]"))
    return path


@pytest.fixture(scope="module")
def history(tmp_path_factory):
    return corneasim.run_scenario(_scenario(tmp_path_factory.mktemp("history"))).history


def test_node_columns(history):
    assert history["top_z_mm"][-1] == pytest.approx(-0.01, rel=1e-12)
    assert history["prescribed_top_z_mm"][-1] == pytest.approx(-0.01, rel=1e-12)
    assert history["prescribed_top_z_mm"][0] == 0.0  # the smooth step starts at rest
    per_node = sum(history[f"base_z_{node}_N"] for node in range(4))
    np.testing.assert_allclose(per_node, history["base_N"], rtol=1e-9, atol=1e-15)
    assert history["base_N"][-1] == pytest.approx(np.pi * 0.01, rel=0.02)
    assert abs(history["rim_r_mm_per_s"][-1]) < 1e-3 and abs(history["rim_z_mm_per_s"][-1]) < 1e-3


def test_element_columns_match_uniaxial_stress(history):
    assert history["solid_zz_MPa"][-1] == pytest.approx(-0.01, rel=0.01)
    assert history["solid_mises_MPa"][-1] == pytest.approx(0.01, rel=0.01)
    for component in ("rr", "tt", "rz"):
        assert abs(history[f"solid_{component}_MPa"][-1]) < 1e-5
    assert history["energy_mJ"][-1] == pytest.approx(0.5 * 1.0 * 0.01 ** 2 * np.pi, rel=0.02)
    assert history["energy_mJ"][-1] == pytest.approx(history["internal_energy_mJ"][-1], rel=0.01)


@pytest.mark.parametrize("request_text, fragment", [
    ('name = "x"\nnode_set = "nowhere"\nquantity = "displacement"', "node set 'nowhere' does not exist"),
    ('name = "x"\nelement_set = "solid"\nquantity = "velocity"', "not velocity"),
    ('name = "x"\nnode_set = "top"\nquantity = "displacement"\ncomponents = ["x"]', "component 'x'"),
    ('name = "x"\nelement_set = "solid"\nquantity = "stress"\ncomponents = ["xx"]', "stress component 'xx'"),
    ('name = "x"\nelement_set = "lid"\nquantity = "stress"', "neither a block nor an element set"),
    ('name = "x"\nquantity = "stress"', "exactly one of node_set or element_set"),
])
def test_bad_request_is_one_line_input_error(tmp_path, request_text, fragment):
    path = _scenario(tmp_path, "[[history]]\n" + request_text)
    with pytest.raises(InputError, match=fragment) as error:
        corneasim.run_scenario(path, ["solver.end_time=1e-6"])
    assert "\n" not in str(error.value) and "history[0]" in str(error.value)
