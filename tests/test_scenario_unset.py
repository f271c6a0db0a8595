"""``--unset KEY`` and a preset's ``unset = [KEY, ...]``: a key removed takes its default."""

import tomllib
from importlib import resources
from pathlib import Path

import pytest

from cli_helpers import corneasim_here

from corneasim.errors import InputError
from corneasim.scenarios import run_scenario
from corneasim.scenarios._registry import load_scenario

RING = "instrument.contact.cutting_toughness"
"""The trephine's ring rule: an optional key, off when absent."""


def _shipped_trephine() -> dict:
    return tomllib.loads(resources.files("corneasim.scenarios.builtin").joinpath("trephine.toml").read_text())


def test_an_unset_optional_key_is_off_and_others_keep_their_values():
    shipped = _shipped_trephine()
    assert shipped["instrument"]["contact"]["cutting_toughness"] > 0.0
    scenario, resolved, _ = load_scenario("trephine", ["mesh.preset=coarse"], [RING])
    assert scenario.instrument.contact.cutting_toughness is None
    assert "cutting_toughness" not in resolved["instrument"]["contact"]
    assert scenario.instrument.contact.edge_contact == shipped["instrument"]["contact"]["edge_contact"]
    assert scenario.solver.target_time_step == shipped["presets"]["coarse"]["solver.target_time_step"]


def test_an_unset_key_takes_its_default_and_wins_over_a_set():
    scenario, _, _ = load_scenario("needle", ["solver.target_time_step=3e-6"], ["solver.target_time_step"])
    default = type(scenario.solver).model_fields["target_time_step"].default
    assert scenario.solver.target_time_step == default != 3e-6


def test_the_trephine_paper_variant_has_no_ring_rule_on_the_coarse_mesh_too():
    assert "unset" in _shipped_trephine()["presets"]["paper"]
    for overrides in (["variant=paper"], ["variant=paper", "mesh.preset=coarse"]):
        scenario, _, _ = load_scenario("trephine", overrides)
        assert scenario.instrument.contact.cutting_toughness is None, overrides
        assert scenario.materials["stroma"].failure_limit == 5.0
    default, _, _ = load_scenario("trephine", ["mesh.preset=coarse"])
    assert default.instrument.contact.cutting_toughness is not None


def test_unsetting_a_key_the_scenario_does_not_set_changes_nothing():
    scenario, resolved, _ = load_scenario("trephine", [], ["cohesive_cut"])
    reference, resolved_reference, _ = load_scenario("trephine")
    assert scenario.cohesive_cut is None and resolved == resolved_reference


@pytest.mark.parametrize(("key", "named"), [
    ("instrument.contact.cutting_tuffness", "'instrument.contact' has: cutting_toughness"),
    ("materials.cornia.failure_limit", "'materials.cornia': no such entry"),
    ("solver..end_time", "expected a dotted key"),
])
def test_an_unknown_key_exits_2_with_one_line_naming_it(tmp_path, key, named):
    completed = corneasim_here("run", "trephine", "--preset", "coarse", "--unset", key, "--out", str(tmp_path / "out"))
    assert completed.returncode == 2
    lines = completed.stderr.strip().splitlines()
    assert len(lines) == 1 and named in lines[0] and "--unset" in lines[0], completed.stderr
    assert not (tmp_path / "out").exists()


def _needle_with_preset(tmp_path, table: str):
    text = resources.files("corneasim.scenarios.builtin").joinpath("needle.toml").read_text()
    path = tmp_path / "needle.toml"
    path.write_text(text[:text.index("[presets.coarse]")] + table)
    return path


def test_a_preset_unsets_after_its_settings_and_a_bad_list_is_named(tmp_path):
    path = _needle_with_preset(tmp_path, '[presets.plain]\n"solver.target_time_step" = 3e-6\n'
                                         'unset = ["solver.target_time_step"]\n')
    scenario, _, _ = load_scenario(str(path), ["variant=plain"])
    assert scenario.solver.target_time_step == type(scenario.solver).model_fields["target_time_step"].default
    wrong = _needle_with_preset(tmp_path, '[presets.plain]\nunset = ["solver.end_tme"]\n')
    with pytest.raises(InputError, match=r"presets\.plain\.unset 'solver.end_tme'.*'solver' has: "):
        load_scenario(str(wrong), ["variant=plain"])
    not_a_list = _needle_with_preset(tmp_path, '[presets.plain]\nunset = "solver.end_time"\n')
    with pytest.raises(InputError, match=r"presets\.plain\.unset: expected a list of dotted keys"):
        load_scenario(str(not_a_list), ["variant=plain"])


def test_a_key_below_a_table_the_scenario_leaves_out_is_checked_against_its_schema(tmp_path):
    scenario, _, _ = load_scenario("needle", ["mesh.preset=coarse"], ["cohesive_cut.radius"])
    assert scenario.cohesive_cut is None
    with pytest.raises(InputError, match=r"'cohesive_cut.radiuss' is not a key.*'cohesive_cut' has: .*radius"):
        load_scenario("needle", ["mesh.preset=coarse"], ["cohesive_cut.radiuss"])
    completed = corneasim_here("run", "needle", "--preset", "coarse", "--unset", "cohesive_cut.radiuss",
                               "--out", str(tmp_path / "out"))
    lines = completed.stderr.strip().splitlines()
    assert completed.returncode == 2 and len(lines) == 1 and "cohesive_cut.radiuss" in lines[0], completed.stderr


PUNCH = Path(__file__).resolve().parents[1] / "examples" / "flat_punch" / "flat_punch.toml"
DAMPING = "instrument.contact.damping_ratio"
"""A key of the flat punch whose default (0.05) the example keeps."""


def test_run_scenario_removes_the_unset_keys_after_the_overrides(tmp_path):
    default = type(load_scenario(str(PUNCH))[0].instrument.contact).model_fields["damping_ratio"].default
    result = run_scenario(str(PUNCH), ["solver.end_time=0.001", "solver.field_count=0", f"{DAMPING}=0.3"],
                          unset=[DAMPING], out_dir=tmp_path / "out")
    assert result.summary["status"] == "completed"
    recorded = tomllib.loads((tmp_path / "out" / "scenario.toml").read_text())
    assert recorded["instrument"]["contact"]["damping_ratio"] == default != 0.3
    with pytest.raises(InputError, match=r"--unset 'solver.end_tme'"):
        run_scenario(str(PUNCH), unset=["solver.end_tme"])
