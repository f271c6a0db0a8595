"""The built-in trephine's start gap puts first contact where the trephination paper has it.

The paper (text on its Fig. 5b) has the trephine touch the cornea at about 3.5 s, i.e. after
70 um of descent at 20 um/s. ``instrument.start_gap`` is the smallest distance from the
trephine to the surface nodes, and the first node it meets lies under the 30 degree bevel, so
the descent to contact is gap / sin(30 deg) (docs/trephination.md, Session 5). Checked on the
coarse mesh (undeformed; the preload changes it by < 1 um there); on the default mesh the
preloaded surface has a node ring 6.4 um inside the wall and contact comes after 0.14 mm.
"""

import math

import numpy as np
import pytest

from corneasim.scenarios.build import build
from corneasim.scenarios.registry import load_scenario
from corneasim.tools.placement import tip_height_for_gap


@pytest.fixture(scope="module")
def coarse():
    scenario, _, base = load_scenario("trephine", ["mesh.preset=coarse"])
    setup = build(scenario, base)
    surface = np.ascontiguousarray(setup.mesh.points[setup.mesh.node_sets["anterior_surface"]])
    return scenario, setup.instrument.shape, surface


def test_descent_to_first_contact_is_the_gap_over_the_sine_of_the_bevel(coarse):
    scenario, shape, surface = coarse
    gap = scenario.instrument.start_gap
    descent = tip_height_for_gap(shape, surface, gap, False) - tip_height_for_gap(shape, surface, 0.0, False)
    assert descent == pytest.approx(gap / math.sin(math.radians(30.0)), rel=1e-3)


def test_first_contact_is_at_the_papers_three_and_a_half_seconds(coarse):
    scenario, shape, surface = coarse
    descent = tip_height_for_gap(shape, surface, scenario.instrument.start_gap, False) \
        - tip_height_for_gap(shape, surface, 0.0, False)
    assert descent / scenario.instrument.motion.insertion.rate == pytest.approx(3.5, abs=0.1)
