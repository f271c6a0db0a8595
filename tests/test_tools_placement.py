"""Instrument placement: the clearance to the tissue equals the requested gap."""

import numpy as np
import pytest

from corneasim.instruments import Needle, Trephine
from corneasim.instruments._placement import clearance, edge_surface_height, tip_height_for_gap

from ring_helpers import ring_mesh


def dome(radius=7.8, r_max=5.5, n=400):
    """(r, z) points of a spherical cap with its apex at z = 0, mm."""
    r = np.linspace(0.0, r_max, n)
    return np.column_stack([r, np.sqrt(radius ** 2 - r ** 2) - radius])


def test_needle_sits_the_gap_above_the_apex():
    shape = Needle(tip="rounded").pack()
    height = tip_height_for_gap(shape, dome(), 0.01, axisymmetric=True)
    assert clearance(shape, dome(), height, True) == pytest.approx(0.01, abs=1e-9)
    assert height == pytest.approx(0.01, abs=2e-3)


def test_a_node_past_the_axis_is_its_mirror_image():
    """An apex node 5 um past the axis (r < 0) of an axisymmetric model (a penalty's give) is at
    |r|, as the node contact sees it: the conical tip clears it by the gap instead of sinking
    until the next ring of nodes meets its flank."""
    needle = Needle(tip="conical", tip_angle=30.0, diameter=0.2)
    points = dome()
    points[0, 0] = -5e-3
    height = tip_height_for_gap(needle.pack(), points, 0.002, axisymmetric=True)
    assert clearance(needle.pack(), points[:1], height, True) == pytest.approx(0.002, abs=1e-9)


def test_trephine_edge_meets_the_dome_at_its_cutting_radius():
    shape = Trephine().pack()
    points = dome()
    height = tip_height_for_gap(shape, points, 0.0, axisymmetric=True)
    sag = 7.8 - np.sqrt(7.8 ** 2 - 3.75 ** 2)
    assert height == pytest.approx(-sag, abs=0.06)
    xyz = np.column_stack([points[:, 0], np.zeros(len(points)), points[:, 1]])
    assert tip_height_for_gap(shape, xyz, 0.0, axisymmetric=False) == pytest.approx(height, abs=1e-6)


def test_a_trephine_edge_clears_the_surface_between_coarse_node_rings():
    """On a dome meshed with node rings 0.26 mm apart about the edge radius, keeping the nodes
    clear of the trephine leaves its edge below the surface they span (the steep bevel meets
    the outer ring first); the surface under the edge is the faces' height there."""
    dome_radius = 7.8
    height = lambda r: np.sqrt(dome_radius**2 - r**2) - dome_radius  # noqa: E731
    radii = np.array([3.36, 3.49, 3.62, 3.88, 4.01, 4.14])
    mesh = ring_mesh(radii, 96, np.array([-0.5, 0.0]), top=height)
    top = mesh.node_sets["top"]
    nodes_only = tip_height_for_gap(Trephine().pack(), mesh.points[top], 0.0, axisymmetric=False)
    surface = edge_surface_height(mesh.points, mesh.cells, top, 3.75, 0.01)
    # the faces between the 3.62 and 3.88 mm rings, seen from above at r = 3.75 (their chords
    # lie inside the circle by at most 3.88 (1 - cos(pi / 96)) = 0.002 mm): linear in r
    w = (3.75 - 3.62) / (3.88 - 3.62)
    between = (1 - w) * height(3.62) + w * height(3.88)
    assert surface == pytest.approx(between, abs=2e-3)
    assert surface - nodes_only > 0.05


def test_the_surface_under_a_circle_on_a_tilted_plane_is_its_highest_point():
    mesh = ring_mesh(np.array([3.5, 3.7, 3.8, 4.0]), 120, np.array([-0.2, 0.0]))
    mesh.points[:, 2] += 0.1 * mesh.points[:, 0]
    surface = edge_surface_height(mesh.points, mesh.cells, mesh.node_sets["top"], 3.75, 0.005)
    assert surface == pytest.approx(0.1 * 3.75, abs=1e-3)
