"""Axisymmetric eye mesh: volumes, thicknesses, orientation, refinement and named sets."""

import math

import numpy as np
import pytest

from corneasim.mesh._axisymmetric import mesh_axisymmetric
from corneasim.mesh._geometry import EyeGeometry
from corneasim.mesh._quality import check_elements, corner_jacobians


def _sphere_integral(z, radius, centre):
    """Antiderivative of pi r(z)^2 for the sphere r^2 = R^2 - (z - c)^2."""
    return math.pi * (radius**2 * z - (z - centre) ** 3 / 3.0)


def _cone_integral(a, b):
    """pi * integral of r^2 dz along the straight segment a -> b (frustum)."""
    return math.pi * (b[1] - a[1]) * (a[0] ** 2 + a[0] * b[0] + b[0] ** 2) / 3.0


def analytic_volumes(geometry):
    """Cornea, sclera and epithelium volumes of the full eye (mm^3) by Green's theorem.

    V = closed integral of pi r^2 dz, counter-clockwise in (r, z), each boundary piece in
    closed form: spheres, the posterior conic r^2 = 2 R_p sigma - (1 + Q) sigma^2 and the
    straight limbus segment.
    """
    s = geometry.shape()
    A, P = s.anterior_limbus, s.posterior_limbus
    R_a, R_p = geometry.anterior_radius, geometry.posterior_radius
    k = 1.0 + s.conic_constant
    sigma_P = -geometry.central_thickness - P[1]
    posterior = -math.pi * (R_p * sigma_P**2 - k * sigma_P**3 / 3.0)
    anterior = _sphere_integral(0.0, R_a, -R_a) - _sphere_integral(A[1], R_a, -R_a)
    cornea = posterior + _cone_integral(P, A) + anterior
    inner_pole = s.inner_centre - s.inner_radius
    sclera = (_cone_integral(A, P)
              + _sphere_integral(inner_pole, s.inner_radius, s.inner_centre)
              - _sphere_integral(P[1], s.inner_radius, s.inner_centre)
              + _sphere_integral(A[1], s.globe_radius, s.globe_centre)
              - _sphere_integral(-geometry.axial_length, s.globe_radius, s.globe_centre))
    R_i = R_a - geometry.epithelium_thickness
    epithelium = 2 * math.pi / 3 * (R_a**3 - R_i**3) * (1 - math.cos(s.theta_limbus))
    return {"cornea": cornea, "sclera": sclera, "epithelium": epithelium}


def revolved_volume(mesh, blocks):
    """2 pi times the first moment of area about the axis of the quads of ``blocks``."""
    x = mesh.points[mesh.cells]
    r, z = x[..., 0], x[..., 1]
    r1, z1 = np.roll(r, -1, 1), np.roll(z, -1, 1)
    moment = ((r + r1) * (r * z1 - r1 * z)).sum(1) / 6.0
    selected = np.isin(mesh.element_block, [mesh.block_names.index(b) for b in blocks])
    return 2 * math.pi * moment[selected].sum()


@pytest.fixture(scope="module")
def default_mesh():
    return mesh_axisymmetric()


def test_volumes_match_the_analytic_shells(default_mesh):
    expected = analytic_volumes(EyeGeometry())
    assert revolved_volume(default_mesh, ["epithelium", "stroma"]) == pytest.approx(expected["cornea"], rel=5e-3)
    assert revolved_volume(default_mesh, ["sclera"]) == pytest.approx(expected["sclera"], rel=5e-3)
    assert revolved_volume(default_mesh, ["epithelium"]) == pytest.approx(expected["epithelium"], rel=5e-3)
    coarse = mesh_axisymmetric(preset="coarse")
    assert revolved_volume(coarse, ["epithelium", "stroma"]) == pytest.approx(expected["cornea"], rel=5e-3)
    assert revolved_volume(coarse, ["sclera"]) == pytest.approx(expected["sclera"], rel=5e-3)


def test_thickness_at_apex_and_limbus(default_mesh):
    g = EyeGeometry()
    mesh = default_mesh
    blocks = {name: set(mesh.cells[mesh.block_elements(name)].ravel()) for name in mesh.block_names}
    cornea_axis = [n for n in mesh.node_sets["axis"] if n in blocks["stroma"] or n in blocks["epithelium"]]
    z = mesh.points[cornea_axis, 1]
    assert z.max() == pytest.approx(0.0, abs=1e-12)
    assert z.max() - z.min() == pytest.approx(g.central_thickness, abs=1e-9)
    interface = np.array(sorted(blocks["epithelium"] & blocks["stroma"] & set(mesh.node_sets["axis"])))
    assert -mesh.points[interface, 1] == pytest.approx([g.epithelium_thickness])
    anterior_limbus = sorted(blocks["epithelium"] & blocks["sclera"] & set(mesh.node_sets["anterior_surface"]))
    posterior_limbus = sorted(blocks["stroma"] & blocks["sclera"] & set(mesh.node_sets["inner_surface"]))
    assert len(anterior_limbus) == len(posterior_limbus) == 1
    distance = np.linalg.norm(mesh.points[anterior_limbus[0]] - mesh.points[posterior_limbus[0]])
    assert distance == pytest.approx(g.peripheral_thickness, rel=1e-9)
    assert mesh.points[anterior_limbus[0], 0] == pytest.approx(g.limbus_radius)


@pytest.mark.parametrize("preset", ["coarse", "default", "fine"])
def test_every_preset_is_counter_clockwise_and_valid(preset):
    mesh = mesh_axisymmetric(preset=preset)
    assert corner_jacobians(mesh).min() > 0.2
    check_elements(mesh)
    mesh.validate()


def test_refined_insertion_area_holds_about_70_percent(default_mesh):
    mesh = default_mesh
    share = mesh.element_sets["refined"].size / mesh.n_elements
    assert 15_000 <= mesh.n_elements <= 19_000  # the paper: 16,923
    assert 0.65 <= share <= 0.75  # the paper: 11,683 of 16,923
    refined_radius = mesh.points[mesh.cells[mesh.element_sets["refined"]], 0].max()
    assert 1.0 < refined_radius < 3.0
    coarse = mesh_axisymmetric(preset="coarse")
    assert 300 <= coarse.n_elements <= 2_000


@pytest.mark.parametrize("preset", ["coarse", "default", "fine"])
def test_at_least_three_elements_across_the_epithelium_on_the_axis(preset):
    mesh = mesh_axisymmetric(preset=preset)
    epithelium = mesh.block_elements("epithelium")
    touching_axis = np.isin(mesh.cells[epithelium], mesh.node_sets["axis"]).any(axis=1)
    assert touching_axis.sum() >= 3


def test_elements_near_the_needle_are_small_and_square(default_mesh):
    mesh = default_mesh
    x = mesh.points[mesh.cells]
    near = (x[..., 0].max(axis=1) < 0.2) & (x[..., 1].min(axis=1) > -1.0)  # needle radius 0.1 mm, cornea
    edges = np.linalg.norm(np.roll(x[near], -1, 1) - x[near], axis=-1)
    assert edges.max() < 0.0125  # >= 8 elements across the needle radius
    assert (edges.max(1) / edges.min(1)).max() < 1.25
    assert corner_jacobians(mesh)[near].min() > 0.95


def test_named_sets_lie_where_they_should(default_mesh):
    g = EyeGeometry()
    s = g.shape()
    mesh = default_mesh
    r, z = mesh.points.T
    anterior = mesh.node_sets["anterior_surface"]
    assert np.allclose(np.hypot(r[anterior], z[anterior] + g.anterior_radius), g.anterior_radius)
    assert r[anterior].max() == pytest.approx(g.limbus_radius)
    inner = mesh.node_sets["inner_surface"]
    on_conic = np.isclose(z[inner], s.posterior_z(np.minimum(r[inner], s.posterior_limbus[0])), atol=1e-9)
    on_sphere = np.isclose(np.hypot(r[inner], z[inner] - s.inner_centre), s.inner_radius, atol=1e-9)
    assert (on_conic | on_sphere).all()
    assert np.allclose(r[mesh.node_sets["axis"]], 0.0)
    hemisphere = mesh.node_sets["lower_hemisphere"]
    assert (z[hemisphere] <= s.globe_centre + 1e-9).all()
    assert (z[np.setdiff1d(np.arange(mesh.n_nodes), hemisphere)] > s.globe_centre).all()
    faces = mesh.face_nodes("inner_surface")
    assert np.isin(faces, inner).all() and len(faces) == len(inner) - 1  # one open chain
    assert len(mesh.face_nodes("anterior_surface")) == len(anterior) - 1


@pytest.mark.parametrize("dimensions", [
    dict(anterior_radius=7.7, posterior_radius=6.5, central_thickness=0.52, peripheral_thickness=0.67,
         epithelium_thickness=0.05, horizontal_diameter=11.7, vertical_diameter=10.6, axial_length=23.5),
    dict(anterior_radius=6.8, posterior_radius=5.8, horizontal_diameter=10.0, vertical_diameter=10.0),
    dict(anterior_radius=9.0, posterior_radius=8.0, central_thickness=0.4, peripheral_thickness=0.6),
])
def test_other_eyes_keep_volumes_and_orientation(dimensions):
    geometry = EyeGeometry(**dimensions)
    mesh = mesh_axisymmetric(geometry, "coarse")
    assert corner_jacobians(mesh).min() > 0.2
    expected = analytic_volumes(geometry)
    assert revolved_volume(mesh, ["epithelium", "stroma"]) == pytest.approx(expected["cornea"], rel=5e-3)
    assert revolved_volume(mesh, ["sclera"]) == pytest.approx(expected["sclera"], rel=5e-3)
    axis_z = mesh.points[mesh.node_sets["axis"], 1]
    assert axis_z.max() == pytest.approx(0.0, abs=1e-12)
    assert (mesh.points[:, 1].min()) == pytest.approx(-geometry.axial_length)
