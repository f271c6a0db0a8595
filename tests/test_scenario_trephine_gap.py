"""The built-in trephine's start gap puts first contact where the trephination paper has it.

The paper (text on its Fig. 5b) has the trephine touch the cornea at about 3.5 s, i.e. after
70 um of descent at 20 um/s. A trephine is placed with its edge ``instrument.start_gap`` above
the surface the anterior nodes span under it and with no node inside it (docs/contact.md,
"Placement"), so its edge touches first, after a descent of start_gap.
"""

import numpy as np
import pytest

from corneasim.scenarios._build import build, place_on_tissue
from corneasim.scenarios._registry import load_scenario
from corneasim.instruments._motion import pose_at
from corneasim.instruments._placement import clearance, edge_surface_height


@pytest.fixture(scope="module", params=["coarse", "default"])
def placed(request):
    scenario, _, base = load_scenario("trephine", [f"mesh.preset={request.param}"])
    setup = build(scenario, base)
    mesh, hook = setup.mesh, setup.instrument
    place_on_tissue(mesh, hook, scenario.instrument.start_gap, np.zeros_like(mesh.points))
    pose_at(hook.motion_packed, setup.preload_duration, hook.pose)
    nodes = mesh.node_sets["anterior_surface"]
    surface = edge_surface_height(mesh.points, mesh.cells, nodes, hook.instrument.edge_radius, 0.005)
    return scenario, hook, mesh.points[nodes], surface


def test_the_edge_starts_the_gap_above_the_surface_and_no_node_is_inside(placed):
    scenario, hook, nodes, surface = placed
    assert hook.pose[2] - surface == pytest.approx(scenario.instrument.start_gap, abs=1e-9)
    assert clearance(hook.shape, np.ascontiguousarray(nodes), hook.pose[2], False) > 0.0


def test_first_contact_is_at_the_papers_three_and_a_half_seconds(placed):
    scenario, hook, nodes, surface = placed
    assert (hook.pose[2] - surface) / scenario.instrument.motion.insertion.rate == pytest.approx(3.5, abs=1e-6)
