"""Stress maps: the colour scale follows its stated rule, no mesh lines, a uniform colour map, the
window around the instrument, titles that say the event; the experiment's legend entry."""

import numpy as np
import pytest

from corneasim.output import _stress_maps as stress_maps
from corneasim.output import (
    CLIP_PERCENTILE, axisymmetric_section, colour_limits, experiment_label, lowest_point, map_title, stress_map,
    tip_window)


def _grid(n):
    """n x n unit squares on [0, n]^2: polygons (n*n, 4, 2)."""
    x, z = np.meshgrid(np.arange(n, dtype=float), np.arange(n, dtype=float))
    corners = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    return np.stack([x.ravel(), z.ravel()], axis=1)[:, None, :] + corners[None]


def test_colour_limits_are_zero_to_the_99th_percentile():
    values = np.arange(1.0, 1001.0)
    # linear interpolation between order statistics: rank 0.99 * 999 = 989.01 -> 990 + 0.01
    assert colour_limits(values) == (0.0, pytest.approx(990.01, rel=1e-12))
    assert colour_limits(np.zeros(5)) == (0.0, 1e-12)


@pytest.fixture
def captured(monkeypatch):
    figures = []
    monkeypatch.setattr(stress_maps, "save", lambda figure, path: figures.append(figure))
    return figures


def test_map_scale_clips_a_spike_and_counts_only_the_window(captured, tmp_path):
    polygons = _grid(40)  # 1600 squares
    rng = np.random.default_rng(1)
    values = rng.uniform(0.0, 1.0, len(polygons))
    values[55] = 1000.0  # the tip element
    values[polygons[:, 0, 0] >= 30.0] = 50.0  # outside the window x <= 29.5: must not count
    x_limits, z_limits = (0.0, 29.5), (0.0, 40.0)
    limits = stress_map(polygons, values, title="t", path=tmp_path / "m.png", x_limits=x_limits, z_limits=z_limits)
    inside = polygons[:, 0, 0] <= 29.5
    assert limits == (0.0, pytest.approx(np.percentile(values[inside], CLIP_PERCENTILE)))
    assert limits[1] < 1.0  # the spike and the values outside the window do not set the scale
    (figure,) = captured
    axes, bar_axes = figure.axes
    collection = axes.collections[0]
    assert collection.get_cmap().name == "viridis"
    assert np.all(collection.get_linewidths() == 0.0) and not collection.get_antialiased()[0]
    assert len(collection.get_paths()) == inside.sum()
    assert collection.get_clim() == pytest.approx(limits)
    label = bar_axes.get_ylabel()
    assert "99th percentile" in label and "MPa" in label and f"peak {1000:.3g}" in label
    assert axes.get_xlim() == pytest.approx(x_limits) and axes.get_ylim() == pytest.approx(z_limits)


def test_axisymmetric_section_mirrors_live_quads_only():
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.0], [2.0, 1.0]])
    cells = np.array([[0, 1, 2, 3], [1, 4, 5, 2]])
    displacement = np.full((6, 2), 0.1)
    polygons, values = axisymmetric_section(points, cells, displacement, np.array([3.0, 4.0]), np.array([0, 1]))
    assert values.tolist() == [4.0, 4.0]
    np.testing.assert_allclose(polygons[0], points[cells[1]] + 0.1)
    np.testing.assert_allclose(polygons[1], (points[cells[1]] + 0.1) * [-1.0, 1.0])


def test_lowest_point_of_a_disc_and_the_window_around_it():
    X, Z = np.meshgrid(np.linspace(-1, 1, 401), np.linspace(0, 2, 401))
    D = np.hypot(X, Z - 1.2) - 0.5  # a disc of radius 0.5 centred at z = 1.2: lowest point (0, 0.7)
    x, z = lowest_point((X, Z, D))
    assert x == pytest.approx(0.0, abs=0.005) and z == pytest.approx(0.7, abs=0.005)
    assert lowest_point((X, Z, np.ones_like(D))) is None and lowest_point(None) is None
    assert tip_window(0.7, 3.75, half_width=0.9, below=0.9, above=0.3) == (
        (pytest.approx(2.85), pytest.approx(4.65)), (pytest.approx(-0.2), pytest.approx(1.0)))


def test_titles_name_the_event_and_labels_the_speed():
    assert map_title("von Mises stress", "stroma", 0.437, "depth 0.437 mm").splitlines() == [
        "von Mises stress", "stroma punctured, t = 0.437 s, depth 0.437 mm"]
    assert map_title("s", "38.5s", 38.5).splitlines()[1] == "t = 38.5 s"
    assert "cornea cut through" in map_title("s", "cornea", 70.0, events={"cornea": "cornea cut through"})
    assert experiment_label("experiment_1mm_s_N") == "experiment (1 mm/s)"
    assert experiment_label("experiment_5mm_s_N") == "experiment (5 mm/s)"
    assert experiment_label("experiment_Fz_N") == "experiment"
