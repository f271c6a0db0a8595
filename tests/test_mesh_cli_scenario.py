"""``corneasim mesh SCENARIO.toml``: --preset and --strategy override the scenario's mesh settings."""

from pathlib import Path

from cli_helpers import corneasim, corneasim_here

SCENARIO = Path(__file__).resolve().parents[1] / "src" / "corneasim" / "scenarios" / "builtin" / "needle.toml"


def test_preset_overrides_the_scenario_mesh():
    from corneasim.mesh import mesh_axisymmetric

    result = corneasim_here("mesh", str(SCENARIO), "--preset", "coarse")
    assert result.returncode == 0, result.stderr
    assert f"elements {mesh_axisymmetric(preset='coarse').n_elements} (quad)" in result.stdout


def test_preset_on_a_mesh_file_is_an_error(tmp_path):
    mesh_file = tmp_path / "eye.vtu"
    assert corneasim_here("mesh", "needle", "--preset", "coarse", "--out", str(mesh_file)).returncode == 0
    result = corneasim("mesh", str(mesh_file), "--preset", "fine")
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1
    assert "--preset" in result.stderr
