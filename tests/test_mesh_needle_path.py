"""The ``needle-path`` axisymmetric preset: fine only along the needle path, coarse elsewhere.

Checks against the eye's closed-form volumes, the layer counts and column width of its
specification (9 + 63 layers, 7.7 um columns to a plan radius of 0.25 mm), corner Jacobians
computed here from edge cross products, and the mass-scaling law: an element of the
axisymmetric mesh scaled to a target step gets the mass rho 2 pi r A (dt* c / (s L_min))^2, so
its artificial mass is proportional to 2 pi r A / L_min^2 (docs/calibration.md, "Mass scaling").
"""

import math

import numpy as np
import pytest
from test_mesh_axisymmetric import analytic_volumes, revolved_volume

from corneasim.errors import InputError
from corneasim.mesh import mesh_3d
from corneasim.mesh._axisymmetric import mesh_axisymmetric
from corneasim.mesh._geometry import EyeGeometry
from corneasim.mesh._quality import check_elements
from corneasim.scenarios._registry import load_scenario

CORE_RADIUS = 0.25  # mm, plan radius of the fine core
COLUMN_WIDTH = 0.0077  # mm
LAYERS = (9, 63)  # epithelium, stroma


@pytest.fixture(scope="module")
def mesh():
    return mesh_axisymmetric(preset="needle-path")


def _edges_and_area(mesh):
    x = mesh.points[mesh.cells]  # (n, 4, 2)
    edge = np.roll(x, -1, axis=1) - x
    lengths = np.linalg.norm(edge, axis=2)
    area = 0.5 * np.sum(x[..., 0] * np.roll(x[..., 1], -1, 1) - np.roll(x[..., 0], -1, 1) * x[..., 1], 1)
    return x, edge, lengths, area


def test_volumes_match_the_analytic_shells(mesh):
    expected = analytic_volumes(EyeGeometry())
    assert revolved_volume(mesh, ["epithelium", "stroma"]) == pytest.approx(expected["cornea"], rel=5e-3)
    assert revolved_volume(mesh, ["epithelium"]) == pytest.approx(expected["epithelium"], rel=5e-3)
    assert revolved_volume(mesh, ["sclera"]) == pytest.approx(expected["sclera"], rel=5e-3)


def test_no_inverted_or_flat_elements(mesh):
    _, edge, lengths, area = _edges_and_area(mesh)
    incoming = -np.roll(edge, 1, axis=1)  # from each corner to the previous one
    cross = edge[..., 0] * incoming[..., 1] - edge[..., 1] * incoming[..., 0]
    scaled = cross / (lengths * np.roll(lengths, 1, axis=1))
    assert (area > 0).all()
    assert scaled.min() > 0.3
    check_elements(mesh)


def test_refined_core_is_the_specified_layers_and_columns(mesh):
    radius = EyeGeometry().anterior_radius
    arc = radius * math.asin(CORE_RADIUS / radius)
    columns = round(arc / COLUMN_WIDTH)
    refined = mesh.element_sets["refined"]
    assert refined.size == sum(LAYERS) * columns
    assert mesh.points[mesh.cells[refined], 0].max() == pytest.approx(CORE_RADIUS, abs=1e-3)


def test_elements_on_the_axis_have_the_default_size(mesh):
    g = EyeGeometry()
    x, _, lengths, _ = _edges_and_area(mesh)
    on_axis = (x[..., 0].min(1) == 0.0) & (x[..., 1].max(1) > -g.central_thickness - 1e-9)
    assert on_axis.sum() == sum(LAYERS)
    width = x[on_axis, :, 0].max(1)
    height = x[on_axis, :, 1].max(1) - x[on_axis, :, 1].min(1)
    top = np.argsort(-x[on_axis, :, 1].max(1))
    epithelium, stroma = top[:LAYERS[0]], top[LAYERS[0]:]
    # first column: anterior arc 0.25 mm / 32 columns, along normals that converge to the
    # anterior centre: r = (R_a - depth) sin(w / R_a) at the element's upper edge
    arc = g.anterior_radius * math.asin(CORE_RADIUS / g.anterior_radius) / round(CORE_RADIUS / COLUMN_WIDTH)
    depth = -x[on_axis, :, 1].max(1)
    assert width == pytest.approx((g.anterior_radius - depth) * np.sin(arc / g.anterior_radius), rel=1e-6)
    assert width.max() == pytest.approx(COLUMN_WIDTH, rel=0.02)
    assert height[epithelium] == pytest.approx(g.epithelium_thickness / LAYERS[0], rel=0.02)
    assert height[stroma] == pytest.approx((g.central_thickness - g.epithelium_thickness) / LAYERS[1], rel=0.02)


def test_no_thin_elements_away_from_the_needle_path(mesh):
    x, _, lengths, area = _edges_and_area(mesh)
    centre = x.mean(1)
    smallest = area / lengths.max(1)
    assert smallest[centre[:, 0] > 0.3].min() > 2 * COLUMN_WIDTH
    assert smallest[centre[:, 0] > 0.8].min() > 0.06


def _artificial_mass(mesh):
    """Sum of 2 pi r A / L_min^2 within 1 mm of the axis (anterior) and in total, mm."""
    x, _, lengths, area = _edges_and_area(mesh)
    centre = x.mean(1)
    weight = 2 * math.pi * centre[:, 0] * area / (area / lengths.max(1)) ** 2
    near = (centre[:, 0] < 1.0) & (centre[:, 1] > -1.5)
    return weight[near].sum(), weight.sum()


def test_far_less_artificial_mass_and_elements_than_the_default(mesh):
    default = mesh_axisymmetric(preset="default")
    near, total = _artificial_mass(mesh)
    default_near, default_total = _artificial_mass(default)
    assert near < default_near / 5
    assert total < default_total / 5
    assert mesh.n_elements < default.n_elements / 4


def test_the_needle_scenario_accepts_it_and_the_3d_generator_refuses_it():
    scenario, _, _ = load_scenario("needle", ["mesh.preset=needle-path"])
    assert scenario.mesh.preset == "needle-path"
    with pytest.raises(InputError, match="needle-path"):
        mesh_3d(preset="needle-path")
