"""``--set`` overrides of nested scenario tables."""

import pytest

from corneasim.errors import InputError
from corneasim.scenarios._overrides import apply_overrides, parse_override


def test_values_are_parsed_as_toml():
    assert parse_override("a.b=2.0e-5") == (["a", "b"], 2.0e-5)
    assert parse_override("a=true") == (["a"], True)
    assert parse_override("a=[1, 2]") == (["a"], [1, 2])
    assert parse_override("a.tip = conical") == (["a", "tip"], "conical")


def test_apply_is_deep_and_does_not_mutate():
    original = {"instrument": {"speed": 1.0, "depth": 0.7}}
    result = apply_overrides(original, ["instrument.speed=5", "solver.target_time_step=1e-5"])
    assert result == {"instrument": {"speed": 5, "depth": 0.7}, "solver": {"target_time_step": 1e-5}}
    assert original["instrument"]["speed"] == 1.0


@pytest.mark.parametrize("text", ["nokey", "=3", "a..b=1"])
def test_malformed_override_is_input_error(text):
    with pytest.raises(InputError):
        apply_overrides({}, [text])


def test_override_through_a_value_is_input_error():
    with pytest.raises(InputError, match="instrument.speed"):
        apply_overrides({"instrument": {"speed": 1}}, ["instrument.speed.x=2"])
