"""``materials.BLOCK.failure = false``: the block's elements keep their material but lose its failure
criterion, so that only a scenario's cutting rule or cut separates them; contradictory settings are
one line naming the block."""

import numpy as np
import pytest

from cli_helpers import corneasim

from corneasim.errors import InputError
from corneasim.materials import load_material
from corneasim.materials.kernel import FAILURE_NONE, FAILURE_VON_MISES
from corneasim.scenarios import build, load_scenario
from corneasim.scenarios._build import load_materials, make_mesh

SHORT = ["mesh.preset=coarse"]


def _materials(overrides):
    scenario, _, base = load_scenario("needle", [*SHORT, *overrides])
    return load_materials(scenario, make_mesh(scenario, base), [], base)


def test_a_block_without_failure_keeps_its_law_and_loses_its_criterion():
    scenario, _, _ = load_scenario("needle", SHORT)
    preset = load_material(scenario.materials["epithelium"].material).kernel_form()
    assert preset.failure_criterion == FAILURE_VON_MISES and preset.failure_limit > 0.0
    default = _materials([])
    without = _materials(["materials.epithelium.failure=false"])
    assert without["epithelium"].failure_criterion == FAILURE_NONE
    assert without["epithelium"].c10 == default["epithelium"].c10 == preset.c10
    assert without["stroma"] == default["stroma"]


def test_an_element_of_a_block_without_failure_has_a_zero_failure_ratio():
    """Stretched far past a 0.01 MPa limit, the block's elements report failure ratios > 1 with their
    criterion and 0 without it (so the failure check never deletes them)."""
    from corneasim.solver import elements as element_kernels

    ratios = {}
    for failure, setting in (("true", "materials.epithelium.failure_limit=0.01"),
                             ("false", "materials.epithelium.failure=false")):
        setup = build(load_scenario("needle", [*SHORT, setting])[0])
        elements = setup.model.elements
        u = np.zeros_like(setup.mesh.points)
        u[:, 1] = 0.5 * setup.mesh.points[:, 1]  # 50 % axial stretch of the whole eye
        history = element_kernels.new_history(elements)
        f = np.zeros_like(u)
        ratio = np.zeros(setup.mesh.n_elements)
        alive = np.ones(setup.mesh.n_elements, np.uint8)
        element_kernels.eval_internal_forces(elements, u, 0.0, alive, history, f, ratio, np.zeros(3))
        ratios[failure] = ratio[setup.mesh.element_block == setup.mesh.block_names.index("epithelium")]
    assert ratios["true"].max() > 1.0
    assert np.all(ratios["false"] == 0.0)


@pytest.mark.parametrize("setting", ["materials.stroma.failure_limit=3", "materials.stroma.fracture_energy=0.5"])
def test_failure_settings_on_a_block_without_failure_are_refused(setting):
    with pytest.raises(InputError, match=r"materials\.stroma: failure = false leaves no criterion"):
        load_scenario("needle", [*SHORT, "materials.stroma.failure=false", setting])


def test_the_refusal_is_one_line_exit_2(tmp_path):
    result = corneasim("run", "needle", "--preset", "coarse", "--set", "materials.stroma.failure=false",
                       "--set", "materials.stroma.failure_limit=3", "--out", str(tmp_path / "run"))
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1
    assert "materials.stroma: failure = false" in result.stderr and "Value error" not in result.stderr


def test_the_range_check_leaves_out_a_strength_that_does_not_act():
    from corneasim.materials import scenario_constants

    scenario, _, base = load_scenario("needle", [*SHORT, "materials.epithelium.failure=false"])
    constants = scenario_constants(scenario, base)
    assert "epithelium.tensile_strength" not in constants
    assert "stroma.tensile_strength" in constants and "epithelium.youngs_modulus" in constants
