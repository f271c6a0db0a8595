"""``--set`` into array-of-table entries: by position and by the set an entry names.

The run check is physical: a cylinder (radius R, height H) on a frictionless base compressed
by a prescribed top displacement u carries F = E pi R^2 u / H (uniaxial stress, free sides);
the override of the array entry's ``value`` must change the base reaction to that of the new u.
"""

import pytest

import corneasim
from corneasim.errors import InputError
from corneasim.scenarios._overrides import apply_overrides, parse_override
from corneasim.scenarios import load_scenario

from byom_helpers import compression_scenario

TABLES = {"constraints": [{"node_set": "bottom", "fixed": "z"},
                          {"node_set": "punch", "prescribed": "displacement", "value": -0.005}],
          "reactions": [{"name": "punch_force", "node_set": "punch", "component": "z"}],
          "solver": {"end_time": 1.0}}


def test_index_and_name_paths_are_parsed():
    assert parse_override("constraints[1].value=0.1") == (["constraints", 1, "value"], 0.1)
    assert parse_override("constraints.punch.value=0.1") == (["constraints", "punch", "value"], 0.1)
    assert parse_override("a[0][2]=1") == (["a", 0, 2], 1)


def test_entry_by_position_and_by_name():
    by_index = apply_overrides(TABLES, ["constraints[1].value=0.1"])
    by_name = apply_overrides(TABLES, ["constraints.punch.value=0.1"])
    assert by_index == by_name
    assert by_index["constraints"][1]["value"] == 0.1
    assert TABLES["constraints"][1]["value"] == -0.005  # not mutated
    nested = apply_overrides(TABLES, ["constraints.punch.amplitude.type=constant"])
    assert nested["constraints"][1]["amplitude"] == {"type": "constant"}
    assert apply_overrides(TABLES, ["reactions.punch_force.component=r"])["reactions"][0]["component"] == "r"


@pytest.mark.parametrize("text, fragment", [
    ("constraints[3].value=0.1", "'constraints[3]': index out of range, the list has 2 entries (0..1)"),
    ("constraints.rim.value=0.1", "'constraints.rim': no entry is named 'rim'"),
    ("solver[0].end_time=1", "'solver' is a table, not a list"),
    ("pressures[0].pressure=1", "'pressures' has no entries"),
    ("constraints[0].fixed.x=1", "'constraints[0].fixed' is a value"),
])
def test_wrong_part_of_the_path_is_named(text, fragment):
    with pytest.raises(InputError) as error:
        apply_overrides(TABLES, [text])
    assert fragment in str(error.value)
    assert "\n" not in str(error.value)


def test_name_not_found_lists_the_names():
    with pytest.raises(InputError, match="the names are: bottom, punch$"):
        apply_overrides(TABLES, ["constraints.rim.value=0.1"])


def test_ambiguous_name_asks_for_the_position():
    tables = {"constraints": [{"node_set": "top", "fixed": "r"}, {"node_set": "top", "prescribed": "velocity"}]}
    with pytest.raises(InputError, match=r"2 entries are named 'top' \(\[0\], \[1\]\)"):
        apply_overrides(tables, ["constraints.top.value=1"])


def test_cli_error_is_one_line_exit_2(tmp_path, capsys):
    from corneasim.cli.main import main as cli_main

    scenario = compression_scenario(tmp_path)
    with pytest.raises(SystemExit) as stop:
        cli_main(["run", str(scenario), "--set", "constraints[7].value=0.1", "--no-progress"])
    assert stop.value.code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "the list has 3 entries" in lines[0]


def test_set_into_an_entry_changes_the_run(tmp_path):
    scenario = compression_scenario(tmp_path)
    resolved = load_scenario(str(scenario), ["constraints.top.value=-0.02"])[0]
    assert resolved.constraints[2].value == -0.02
    base = corneasim.run_scenario(scenario).history["base_N"][-1]
    deeper = corneasim.run_scenario(scenario, ["constraints[2].value=-0.02"]).history["base_N"][-1]
    youngs_modulus, radius, height = 1.0, 1.0, 1.0
    for force, depth in ((base, 0.01), (deeper, 0.02)):
        assert force == pytest.approx(youngs_modulus * 3.141592653589793 * radius ** 2 * depth / height, rel=0.03)
