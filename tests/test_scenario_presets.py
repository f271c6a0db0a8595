"""``[presets.NAME]``: settings that come with ``mesh.preset = NAME``, under the ``--set`` overrides."""

import tomllib
from importlib import resources

import pytest

from cli_helpers import corneasim_here

from corneasim.errors import InputError
from corneasim.scenarios._registry import load_scenario


def _shipped_needle() -> dict:
    return tomllib.loads(resources.files("corneasim.scenarios.builtin").joinpath("needle.toml").read_text())


@pytest.mark.parametrize("preset", ["coarse", "needle-path"])
def test_a_needle_mesh_preset_takes_the_settings_of_its_table(preset):
    shipped = _shipped_needle()
    step = shipped["presets"][preset]["solver.target_time_step"]
    assert step != shipped["solver"]["target_time_step"]
    default, _, _ = load_scenario("needle")
    assert default.solver.target_time_step == shipped["solver"]["target_time_step"]
    scenario, resolved, _ = load_scenario("needle", [f"mesh.preset={preset}"])
    assert scenario.solver.target_time_step == step
    assert resolved["solver"]["target_time_step"] == step
    assert "presets" not in resolved  # applied once; a resumed run must not apply them again


@pytest.mark.parametrize("order", [0, 1])
def test_a_set_of_the_same_key_wins_whatever_its_place(order):
    overrides = ["mesh.preset=coarse", "solver.target_time_step=3e-6"]
    scenario, _, _ = load_scenario("needle", overrides if order == 0 else overrides[::-1])
    assert scenario.solver.target_time_step == 3e-6


def _scenario_file(tmp_path, preset_table: str, mesh_preset: str):
    text = (resources.files("corneasim.scenarios.builtin").joinpath("needle.toml").read_text()
            .replace('preset = "default"', f'preset = "{mesh_preset}"'))
    start = text.index("[presets.coarse]")
    path = tmp_path / "needle.toml"
    path.write_text(text[:start] + preset_table)
    return path


def test_a_wrong_key_in_the_preset_that_runs_is_named(tmp_path):
    path = _scenario_file(tmp_path, '[presets.coarse]\n"solver.target_time_stepp" = 2e-5\n', "coarse")
    with pytest.raises(InputError, match="target_time_stepp"):
        load_scenario(str(path))
    other = _scenario_file(tmp_path, '[presets.coarse]\n"solver.target_time_stepp" = 2e-5\n', "default")
    load_scenario(str(other))  # a preset that does not run is not applied


def test_a_preset_that_is_not_a_table_exits_2_with_one_line(tmp_path):
    path = _scenario_file(tmp_path, "[presets]\ncoarse = 5\n", "coarse")
    completed = corneasim_here("run", str(path), "--out", str(tmp_path / "out"))
    assert completed.returncode == 2
    lines = completed.stderr.strip().splitlines()
    assert len(lines) == 1 and "presets.coarse" in lines[0], completed.stderr
