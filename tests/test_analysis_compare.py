"""compare_to_experiment against hand-computed cases."""

import numpy as np
import pytest

from corneasim.analysis import compare_to_experiment
from corneasim.errors import InputError


def test_identical_curve_has_zero_error():
    x = np.linspace(0, 0.7, 15)
    result = compare_to_experiment(x, x**2, x, x**2)
    assert result["rmse"] == 0.0 and result["max_abs_error"] == 0.0 and result["n_points"] == 15


def test_hand_computed_linear_interpolation():
    # simulation y = 2x sampled at 0, 1, 2 (exact under linear interpolation)
    result = compare_to_experiment([0, 1, 2], [0, 2, 4], [0.5, 1.5, 2.0], [1.0, 2.5, 3.0])
    # errors: 1-1=0, 3-2.5=0.5, 4-3=1
    assert result["rmse"] == pytest.approx(np.sqrt((0 + 0.25 + 1) / 3), rel=1e-15)
    assert result["max_abs_error"] == pytest.approx(1.0, rel=1e-15)
    assert result["x_max_error"] == 2.0
    assert result["n_points"] == 3 and result["n_outside"] == 0


def test_constant_offset():
    x = np.linspace(0, 1, 11)
    result = compare_to_experiment(x, np.sin(x), x[::2], np.sin(x[::2]) - 0.03)
    assert result["rmse"] == pytest.approx(0.03, rel=1e-12)
    assert result["max_abs_error"] == pytest.approx(0.03, rel=1e-12)


def test_points_outside_the_simulation_are_excluded_not_extrapolated():
    # like the trephination table (to 100 s) against a 70 s simulation
    result = compare_to_experiment([0, 70], [0, 7], [-1, 10, 50, 90, 100], [99, 1, 4, 99, 99])
    assert result["n_points"] == 2 and result["n_outside"] == 3
    assert result["max_abs_error"] == pytest.approx(1.0)  # 5 - 4 at 50 s
    assert result["rmse"] == pytest.approx(np.sqrt(0.5))


@pytest.mark.parametrize(
    "arguments, fragment",
    [
        (([0, 1], [0, 1], [5, 6], [0, 0]), "no table abscissa inside"),
        (([0, 1, 1], [0, 1, 2], [0.5], [0]), "strictly increasing"),
        (([1, 0], [0, 1], [0.5], [0]), "strictly increasing"),
        (([0], [0], [0], [0]), "at least 2"),
        (([0, 1], [0], [0], [0]), "simulation: 2 abscissae but 1 values"),
        (([0, 1], [0, 1], [0.5], [np.inf]), "experiment: values must be finite"),
    ],
)
def test_bad_input(arguments, fragment):
    with pytest.raises(InputError, match=fragment):
        compare_to_experiment(*arguments)


def test_a_table_point_at_the_simulated_end_up_to_round_off_is_compared():
    """A run that ends one ulp short of 0.7 mm (accumulated time steps) still meets the
    table's 0.70 mm; a table point beyond the run by 1e-4 of its length does not."""
    end = np.nextafter(0.7, 0.0)
    result = compare_to_experiment([0.0, end], [0.0, 1.0], [0.0, 0.35, 0.70], [0.0, 0.5, 2.0])
    assert result["n_points"] == 3 and result["n_outside"] == 0
    assert result["max_abs_error"] == pytest.approx(1.0)
    outside = compare_to_experiment([0.0, 0.7], [0.0, 1.0], [0.0, 0.7001], [0.0, 1.0])
    assert outside["n_points"] == 1 and outside["n_outside"] == 1
