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


def _preset_overrides(*names: str, sets: tuple[str, ...] = ()) -> list[str]:
    """The overrides that ``corneasim run needle --preset NAME ... --set ...`` gives."""
    from corneasim.cli.main import build_parser
    from corneasim.cli.run import shortcut_overrides

    words = ["run", "needle"] + [w for name in names for w in ("--preset", name)]
    words += [w for key in sets for w in ("--set", key)]
    return shortcut_overrides(build_parser().parse_args(words), "needle")


def test_preset_paper_runs_the_needle_papers_own_model():
    # the needle paper: von Mises deletion at 10 MPa (epithelium) and 5 MPa (stroma), target step 2e-5 s
    scenario, resolved, _ = load_scenario("needle", _preset_overrides("paper"))
    assert scenario.variant == "paper"
    assert scenario.materials["epithelium"].failure_limit == 10.0
    stroma = scenario.materials["stroma"]
    assert (stroma.material, stroma.failure_limit, stroma.fracture_energy) == ("cornea", 5.0, 0.0)
    assert scenario.solver.target_time_step == 2.0e-5
    assert scenario.solver.distortion_limit == 0.0
    assert resolved["variant"] == "paper" and "presets" not in resolved
    default, _, _ = load_scenario("needle")
    assert default.variant is None and default.materials["stroma"].material != "cornea"


def test_a_variant_composes_with_a_mesh_preset_and_a_set_still_wins():
    overrides = _preset_overrides("paper", "coarse", sets=("materials.stroma.failure_limit=7.5",))
    scenario, _, _ = load_scenario("needle", overrides)
    assert scenario.mesh.preset == "coarse" and scenario.variant == "paper"
    assert scenario.materials["stroma"].failure_limit == 7.5
    assert scenario.materials["stroma"].material == "cornea"


def test_an_unknown_variant_is_named_with_the_choices():
    with pytest.raises(InputError, match=r"variant: .*\(coarse, needle-path, paper\).*'papr'"):
        load_scenario("needle", _preset_overrides("papr"))


def test_a_resolved_scenario_of_a_variant_loads_as_it_ran(tmp_path):
    """A run's scenario.toml keeps the variant that ran and no presets table: read as resolved
    (as --resume does), it gives the scenario that ran; read as an input, its variant names a
    presets table it no longer has."""
    from corneasim.scenarios._registry import resolved_tables, to_toml

    ran, resolved, _ = load_scenario("trephine", ["variant=cohesive", "mesh.preset=coarse"])
    path = tmp_path / "scenario.toml"
    path.write_text(to_toml(resolved))
    again, _, _ = load_scenario(str(path), resolved=True)
    assert resolved_tables(again) == resolved_tables(ran)
    assert again.variant == "cohesive" and again.cohesive_cut.radius == 3.686
    with pytest.raises(InputError, match="variant"):
        load_scenario(str(path))
