"""Friction laws: the needle paper's lumped law (eq. 3), its validity warning, its traction."""

import warnings

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.schema import validate
from corneasim.contact._node import FORCE_Z, N_OUTPUTS, NORMAL_FORCE, eval_contact
from corneasim.contact._friction import Friction, FrictionValidityWarning, needle_friction_force
from corneasim.instruments._kinds import Needle
from corneasim.instruments._motion import needle_insertion


@pytest.mark.parametrize("speed, magnitude", [(0.84, 0.371 + 0.1171 * 0.84), (1.0, 0.4881), (5.0, 0.9565)])
def test_needle_paper_law_values(speed, magnitude):
    assert needle_friction_force(speed, 0.371, 0.1171) == pytest.approx(-magnitude, rel=1e-12)
    assert needle_friction_force(-speed, 0.371, 0.1171) == pytest.approx(magnitude, rel=1e-12)
    assert needle_friction_force(0.0, 0.371, 0.1171) == 0.0


def test_warning_below_stated_validity():
    law = Friction(law="karnopp")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert law.check_speed(1.0) and law.check_speed(-5.0)
        assert Friction(law="coulomb").check_speed(0.01)
    with pytest.warns(FrictionValidityWarning, match="0.84 mm/s"):
        assert not law.check_speed(0.5)


def shaft_nodes(n, depth):
    """n nodes pressed by `depth` against the side of a flat needle's shaft, at rest."""
    z = np.linspace(0.5, 2.0, n)
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = 0.1 - depth
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


def run_karnopp(speed, depth, limit=1.0):
    """Touch at t = 0.05 s, then evaluate at t = 0.1 s after the needle slid 0.05 v mm."""
    needle = Needle(tip="flat", length=5.0)
    motion = needle_insertion(speed=speed, tip_position=(0.0, 0.0, 0.0))
    n = 40
    anchor, touching = np.zeros((n, 3)), np.zeros(n, np.uint8)
    friction = Friction(law="karnopp", coefficient_limit=limit).pack()
    for t in (0.05, 0.1):
        pose = motion.pose(t)
        x = shaft_nodes(n, depth) + motion.pose(0.1)[:3]
        f = np.zeros_like(x)
        out = np.zeros(N_OUTPUTS)
        eval_contact(x, np.zeros_like(x), np.arange(n), np.ones(n, np.uint8), np.ones(n), np.ones(n), needle.pack(),
                     pose, 1.0, 0.0, 1.0, friction, anchor, touching, f, out, np.empty(n, np.int64))
    return f, out


@pytest.mark.parametrize("speed", [1.0, 5.0])
def test_lumped_law_gives_its_total_friction_on_the_needle(speed):
    """Every node slides at the needle speed: the axial force on the needle is F(v) = 0.371 + 0.1171 v."""
    f, out = run_karnopp(speed, depth=0.05)
    assert out[NORMAL_FORCE] == pytest.approx(40 * 0.05)
    assert out[FORCE_Z] == pytest.approx(0.371 + 0.1171 * speed, rel=1e-12)  # resists the descent
    # Shared in proportion to the normal force (all equal here), dragging the tissue down.
    assert f[:, 2] == pytest.approx(np.full(40, -(0.371 + 0.1171 * speed) / 40), rel=1e-12)


def test_lumped_law_is_capped_by_the_coefficient_limit_at_first_touch():
    f, out = run_karnopp(1.0, depth=1e-4, limit=0.8)
    assert out[FORCE_Z] == pytest.approx(0.8 * out[NORMAL_FORCE], rel=1e-12)


def test_bad_friction_raises_input_error():
    with pytest.raises(InputError, match="coefficient"):
        validate(Friction, {"law": "coulomb", "coefficient": -0.1}, "scenario.toml")
    with pytest.raises(InputError, match="law"):
        validate(Friction, {"law": "stribeck"})
