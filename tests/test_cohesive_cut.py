"""The trephine scenario's cohesive cut: the split cylinder, its pairs and its ties."""

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.mesh._hexahedral import mesh_3d
from corneasim.scenarios import run_scenario
from corneasim.scenarios._build import build
from corneasim.scenarios._registry import load_scenario

CUT = ["mesh.preset=coarse", "cohesive_cut.strength=0.05",
       "cohesive_cut.fracture_energy=0.004"]


def radius(points):
    return np.hypot(points[:, 0], points[:, 1])


@pytest.mark.parametrize("strategy", ["vertical", "umbrella"])
def test_the_mesh_gets_a_node_cylinder_through_the_cornea(strategy):
    plain = mesh_3d(strategy=strategy, preset="coarse")
    mesh = mesh_3d(strategy=strategy, preset="coarse", cut_radius=3.75)
    assert mesh.n_elements == plain.n_elements and mesh.n_nodes == plain.n_nodes
    on = np.isclose(radius(mesh.points), 3.75, rtol=0.0, atol=1e-9)
    assert not np.isclose(radius(plain.points), 3.75, rtol=0.0, atol=1e-6).any()
    # every through-thickness level of the half ring: 25 azimuths (24 sectors) x the cornea's levels,
    # from the anterior surface (z = -0.96 mm at r = 3.75 on the 7.8 mm sphere) to the posterior
    levels = np.unique(np.round(mesh.points[on, 2], 9))
    assert on.sum() == 25 * levels.size and levels.size >= 4
    assert levels[-1] == pytest.approx(np.sqrt(7.8 ** 2 - 3.75 ** 2) - 7.8, abs=1e-9)
    if strategy == "umbrella":  # the ribs turn to the axis only within 1 mm inside the cut
        central = radius(plain.points) < 3.75 - 1.0 - 0.5
        np.testing.assert_allclose(np.unique(mesh.points[radius(mesh.points) < 2.25], axis=0),
                                   np.unique(plain.points[central], axis=0), rtol=0.0, atol=1e-12)


def test_the_split_cornea_is_tied_over_the_half_cylinder():
    scenario, _, base_dir = load_scenario("trephine", CUT)
    setup = build(scenario, base_dir)
    ties, mesh, model = setup.cohesive, setup.mesh, setup.model
    work = setup.edge_work
    assert ties is not None and setup.hooks[:4] == (work.before, setup.instrument, work, ties)
    pairs = ties.pairs
    np.testing.assert_array_equal(mesh.points[pairs[:, 0]], mesh.points[pairs[:, 1]])
    np.testing.assert_allclose(radius(mesh.points[pairs[:, 0]]), 3.75, atol=1e-9)
    # the tied area is the half cylinder (faces are chords of it: 0.07% less)
    depth = np.ptp(mesh.points[pairs[:, 0], 2])
    assert ties.area.sum() == pytest.approx(np.pi * 3.75 * depth, rel=2e-3)
    # the copies on the cyclic cut plane y = 0 are each other's images, as their originals are
    copies = set(pairs[:, 1].tolist())
    copy_pairs = [(a, b) for a, b in zip(model.cyclic_master, model.cyclic_slave) if a in copies]
    levels = np.unique(np.round(mesh.points[pairs[:, 0], 2], 9)).size
    assert len(copy_pairs) == levels  # one node at (3.75, 0, z) per level, imaged at (-3.75, 0, z)
    for a, b in copy_pairs:
        assert b in copies
        np.testing.assert_allclose(mesh.points[b], mesh.points[a] * [-1.0, 1.0, 1.0], atol=1e-9)


def test_a_fine_band_at_the_cut_splits_by_the_nodes_side():
    """Columns 0.01 mm wide (along the surface) on either side of the cut: every tied pair
    joins an element inside to one outside, although the outer elements' centroids lie
    inside the cylinder (a chord's sagitta, 0.2 % of r, exceeds the column width)."""
    scenario, _, base_dir = load_scenario("trephine", [*CUT, "cohesive_cut.radius=3.74",
                                                       "cohesive_cut.element_width=0.01"])
    setup = build(scenario, base_dir)
    mesh, pairs = setup.mesh, setup.cohesive.pairs
    node_radius = radius(mesh.points)
    columns = np.unique(np.round(node_radius[(node_radius > 3.7) & (node_radius < 3.78)], 4))
    assert np.min(np.diff(columns)) < 0.01 and 3.74 in columns
    levels = np.unique(np.round(mesh.points[pairs[:, 0], 2], 9)).size
    assert len(pairs) == 25 * levels
    inner = np.flatnonzero(np.isin(mesh.cells, pairs[:, 0]).any(axis=1))
    outer = np.flatnonzero(np.isin(mesh.cells, pairs[:, 1]).any(axis=1))
    assert np.all(node_radius[mesh.cells[inner]].mean(axis=1) < 3.74)
    assert np.all(node_radius[mesh.cells[outer]].mean(axis=1) > 3.74)
    assert np.all(radius(mesh.points[mesh.cells[outer]].mean(axis=1)) < 3.74)  # the centroids


def test_a_cut_needs_the_blocks_it_splits():
    scenario, _, base_dir = load_scenario("trephine", [*CUT, "cohesive_cut.blocks=[\"lens\"]"])
    with pytest.raises(InputError, match="lens"):
        build(scenario, base_dir)


def test_a_run_with_a_cut_reports_its_ties():
    result = run_scenario("trephine", [*CUT, "preload.duration=0.05", "solver.end_time=0.05",
                                       "solver.field_count=0"])
    history = result.history
    for column in ("cohesive_stored_energy_mJ", "cohesive_dissipated_energy_mJ", "cohesive_broken_ties",
                   "cohesive_softening_ties", "cohesive_edge_energy_mJ"):
        assert column in history
    assert np.all(history["cohesive_stored_energy_mJ"] >= 0.0)
    assert history["cohesive_stored_energy_mJ"][-1] > 0.0  # the IOP pulls on the ties


def test_toughness_and_strength_by_block_weigh_each_tie_by_its_layers():
    """G_c and sigma_c per split block: each tie takes its blocks' values weighted by their share
    of its area, so sum G A = G_e pi R h_e + G_s pi R h_s over the half cylinder (h the layers'
    depths at R; the faces are chords of it: 0.2 %)."""
    cut = [*CUT[:1], "cohesive_cut.strength={ epithelium = 10.0, stroma = 5.0 }",
           "cohesive_cut.fracture_energy={ epithelium = 0.15, stroma = 0.3 }"]
    scenario, _, base_dir = load_scenario("trephine", cut)
    setup = build(scenario, base_dir)
    ties, mesh = setup.cohesive, setup.mesh
    toughness = 0.5 * ties.strength * ties.separation
    epithelium = mesh.cells[mesh.element_block == mesh.block_names.index("epithelium")]
    z = mesh.points[ties.pairs[:, 0], 2]
    in_epithelium = np.isin(ties.pairs[:, 0], epithelium)
    interface = z[in_epithelium].min()
    top, bottom = z.max(), z.min()
    expected = np.pi * 3.75 * (0.15 * (top - interface) + 0.3 * (interface - bottom))
    assert np.sum(toughness * ties.area) == pytest.approx(expected, rel=2e-3)
    assert set(np.round(ties.strength[z > interface + 1e-9], 12)) == {10.0}
    assert set(np.round(ties.strength[z < interface - 1e-9], 12)) == {5.0}
    with pytest.raises(InputError, match="fracture_energy.*missing stroma"):
        build(*load_scenario("trephine", [*CUT[:2], "cohesive_cut.fracture_energy={ epithelium = 0.15 }"])[::2])


def test_the_cohesive_variant_is_inside_the_published_ranges():
    from corneasim.materials import check_constants

    cut = load_scenario("trephine", ["variant=cohesive"])[0].cohesive_cut
    values = {f"{block}.{name}": getattr(cut, key)[block] for block in ("epithelium", "stroma")
              for name, key in (("toughness", "fracture_energy"), ("tensile_strength", "strength"))}
    checks = check_constants(values)
    assert len(checks) == 4 and all(check.status == "inside" for check in checks)


def test_on_a_prestressed_reference_the_ties_keep_the_measured_mesh_lines():
    """The stress-free geometry moves each node by its own displacement, so the ties of one
    through-thickness line no longer share x, y there; the lines (and the layer events read from
    them) are the measured mesh's: 25 azimuths of the half ring, each tie once, ordered from the
    anterior surface down."""
    scenario, _, base_dir = load_scenario("trephine", CUT)
    measured = build(scenario, base_dir)
    points = measured.mesh.points
    r, z = radius(points), points[:, 2]
    shrink = 1.0 - 0.017 - 0.002 * (z - z.min()) / np.ptp(z)  # radial, varying through the thickness
    reference = np.column_stack((points[:, 0] * shrink, points[:, 1] * shrink, z + 0.15 * (r < 6.0)))
    setup = build(scenario, base_dir, reference_points=reference)
    pairs = setup.cohesive.pairs
    start, order = setup.edge_work.line_start, setup.edge_work.line_pairs
    assert start.size - 1 == 25 and np.array_equal(np.sort(order), np.arange(len(pairs)))
    for line in range(25):
        ties = pairs[order[start[line]:start[line + 1]], 0]
        assert np.ptp(points[ties, 0]) < 1e-9 and np.ptp(points[ties, 1]) < 1e-9
        assert np.all(np.diff(points[ties, 2]) < 0)
    np.testing.assert_array_equal(setup.tie_events.entered, measured.tie_events.entered)
