"""3D half model of the eye: volumes, orientation, closed surfaces, trephine-area counts."""

import math

import numpy as np
import pytest
from test_mesh_axisymmetric import analytic_volumes

from corneasim.errors import InputError
from corneasim.mesh import HEXAHEDRON_FACES
from corneasim.mesh._geometry import EyeGeometry
from corneasim.mesh._hexahedral import STRATEGIES, TREPHINE_RADIUS, mesh_3d
from corneasim.mesh._quality import check_elements, corner_jacobians

PAPER_TABLE_1 = {"umbrella": (17215, 13008), "vertical": (21064, 11709), "horizontal": (19377, 15560)}


def tetrahedral_volume(mesh, blocks):
    """Volume of the hexahedra of ``blocks`` split into 5 tetrahedra each (planar faces: exact)."""
    tets = np.array([[0, 1, 3, 4], [1, 2, 3, 6], [1, 4, 5, 6], [3, 4, 6, 7], [1, 3, 4, 6]])
    elements = np.flatnonzero(np.isin(mesh.element_block, [mesh.block_names.index(b) for b in blocks]))
    x = mesh.points[mesh.cells[elements]][:, tets]  # (n, 5, 4, 3)
    a, b, c, d = (x[:, :, k] for k in range(4))
    return np.einsum("nti,nti->nt", np.cross(b - a, c - a), d - a).sum() / 6.0


@pytest.fixture(scope="module")
def meshes():
    return {strategy: mesh_3d(strategy=strategy) for strategy in STRATEGIES}


def test_half_model_volumes_match_the_analytic_shells(meshes):
    expected = analytic_volumes(EyeGeometry())
    mesh = meshes["umbrella"]
    assert 2 * tetrahedral_volume(mesh, ["epithelium", "stroma"]) == pytest.approx(expected["cornea"], rel=5e-3)
    assert 2 * tetrahedral_volume(mesh, ["sclera"]) == pytest.approx(expected["sclera"], rel=5e-3)
    for strategy in ("vertical", "horizontal"):  # fewer sectors: the polygonal faceting costs ~0.5%
        volume = 2 * tetrahedral_volume(meshes[strategy], ["epithelium", "stroma"])
        assert volume == pytest.approx(expected["cornea"], rel=1e-2)


@pytest.mark.parametrize("strategy", STRATEGIES)
@pytest.mark.parametrize("preset", ["coarse", "default", "fine"])
def test_every_strategy_and_preset_has_positive_jacobians(strategy, preset):
    mesh = mesh_3d(strategy=strategy, preset=preset)
    assert corner_jacobians(mesh).min() > 0.15
    check_elements(mesh)
    if preset == "coarse":
        assert 1_000 <= mesh.n_elements <= 4_000


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_element_counts_near_the_papers_table_1(meshes, strategy):
    mesh = meshes[strategy]
    total, trephine_area = PAPER_TABLE_1[strategy]
    assert mesh.n_elements == pytest.approx(total, rel=0.2)
    assert mesh.element_sets["refined"].size == pytest.approx(trephine_area, rel=0.1)
    centres = mesh.points[mesh.cells[mesh.element_sets["refined"]]].mean(axis=1)
    radius = np.hypot(centres[:, 0], centres[:, 1])
    assert radius.min() < TREPHINE_RADIUS - 0.3 and radius.max() > TREPHINE_RADIUS + 0.3
    assert radius.max() - radius.min() < 2.5  # an annulus, not the whole cornea


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_boundary_is_closed_and_sets_lie_on_their_surfaces(strategy):
    g = EyeGeometry()
    s = g.shape()
    mesh = mesh_3d(strategy=strategy, preset="coarse")
    all_faces = mesh.cells[:, HEXAHEDRON_FACES].reshape(-1, 4)
    _, inverse, counts = np.unique(np.sort(all_faces, axis=1), axis=0, return_inverse=True, return_counts=True)
    assert counts.max() == 2  # conforming: no face shared by three elements
    boundary = all_faces[counts[inverse.ravel()] == 1]
    x, y, z = mesh.points.T
    radius = np.hypot(x, y)
    on_anterior = np.isclose(np.hypot(radius, z + g.anterior_radius), g.anterior_radius, atol=1e-9)
    on_globe = np.isclose(np.hypot(radius, z - s.globe_centre), s.globe_radius, atol=1e-9)
    inner = np.zeros(mesh.n_nodes, dtype=bool)
    inner[mesh.node_sets["inner_surface"]] = True
    symmetric = np.abs(y) < 1e-9
    classified = ((on_anterior | on_globe)[boundary].all(1) | inner[boundary].all(1)
                  | symmetric[boundary].all(1))
    assert classified.all()  # no internal cracks: every open face is a surface of the eye
    assert (np.abs(y[mesh.node_sets["symmetry_plane"]]) < 1e-9).all() and (y > -1e-9).all()
    assert on_anterior[mesh.node_sets["anterior_surface"]].all()
    assert (z[mesh.node_sets["lower_hemisphere"]] <= s.globe_centre + 1e-9).all()
    assert np.isin(mesh.face_nodes("inner_surface"), mesh.node_sets["inner_surface"]).all()
    area = 0.0
    for quad in mesh.points[mesh.face_nodes("anterior_surface")]:
        area += 0.5 * np.linalg.norm(np.cross(quad[2] - quad[0], quad[3] - quad[1]))
    cap = math.pi * g.anterior_radius**2 * (1 - math.cos(s.theta_limbus))  # half of the spherical cap
    assert area == pytest.approx(cap, rel=0.03)


def test_unknown_strategy_and_preset_are_input_errors():
    with pytest.raises(InputError, match="strategy 'diagonal'"):
        mesh_3d(strategy="diagonal")
    with pytest.raises(InputError, match="preset 'huge'"):
        mesh_3d(preset="huge")


OTHER_EYES = {
    "human": dict(anterior_radius=7.7, posterior_radius=6.5, central_thickness=0.52, peripheral_thickness=0.67,
                  epithelium_thickness=0.05, horizontal_diameter=11.7, vertical_diameter=10.6, axial_length=23.5,
                  sclera_thickness=0.9),
    "small steep": dict(anterior_radius=6.8, posterior_radius=5.8, horizontal_diameter=10.0, vertical_diameter=10.0),
    "flat thin": dict(anterior_radius=9.0, posterior_radius=8.0, central_thickness=0.4, peripheral_thickness=0.6),
}


@pytest.mark.parametrize("eye", OTHER_EYES)
@pytest.mark.parametrize("strategy", STRATEGIES)
def test_other_eyes_mesh_with_positive_jacobians(eye, strategy):
    geometry = EyeGeometry(**OTHER_EYES[eye])
    mesh = mesh_3d(geometry, strategy, "coarse")
    assert corner_jacobians(mesh).min() > 0.1
    expected = analytic_volumes(geometry)
    assert 2 * tetrahedral_volume(mesh, ["epithelium", "stroma"]) == pytest.approx(expected["cornea"], rel=0.04)
