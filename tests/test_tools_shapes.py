"""Instrument shapes: signed distance against analytic points and brute force, normal = grad d."""

import math

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.instruments._kinds import Needle, Trephine, instrument_from_dict
from corneasim.instruments._shapes import signed_distance, signed_distance_rz

SHAPES = [
    Needle(tip="flat"),
    Needle(tip="conical", tip_angle=40.0),
    Needle(tip="rounded"),
    Needle(tip="bevelled", bevel_angle=20.0),
    Trephine(bevel_side="outer"),
    Trephine(bevel_side="inner", wall_thickness=0.2),
    Trephine(bevel_side="symmetric", bevel_angle=25.0),
]
IDS = [f"{s.kind}-{getattr(s, 'tip', getattr(s, 'bevel_side', ''))}" for s in SHAPES]


def inside(instrument, x, y, z):
    """Independent membership test written from the geometric definitions."""
    r = math.hypot(x, y)
    if not 0.0 <= z <= instrument.length:
        return False
    if isinstance(instrument, Trephine):
        edge, wall, h = instrument.edge_radius, instrument.wall_thickness, instrument.bevel_height
        slope = math.tan(math.radians(instrument.bevel_angle))
        if instrument.bevel_side == "outer":
            return edge <= r <= min(edge + wall, edge + z * slope)
        if instrument.bevel_side == "inner":
            return max(edge - wall, edge - z * slope) <= r <= edge
        return max(edge - wall / 2, edge - z * slope) <= r <= min(edge + wall / 2, edge + z * slope)
    radius = instrument.radius
    if r > radius:
        return False
    if instrument.tip == "conical":
        return r <= z * math.tan(math.radians(instrument.tip_angle / 2))
    if instrument.tip == "rounded":
        return z >= radius or math.hypot(r, z - radius) <= radius
    if instrument.tip == "bevelled":
        return z >= (x + radius) / math.tan(math.radians(instrument.bevel_angle))
    return True


def sample_points(instrument, n, seed):
    rng = np.random.default_rng(seed)
    if isinstance(instrument, Trephine):
        centre, half = instrument.edge_radius, 0.4
        r = rng.uniform(centre - half, centre + half, n)
        phi = rng.uniform(0, 2 * np.pi, n)
        return np.column_stack([r * np.cos(phi), r * np.sin(phi), rng.uniform(-0.3, 1.0, n)])
    size = 2.0 * instrument.radius
    return np.column_stack([rng.uniform(-size, size, n), rng.uniform(-size, size, n), rng.uniform(-0.2, 1.2, n)])


@pytest.mark.parametrize("instrument", SHAPES, ids=IDS)
def test_sign_matches_membership(instrument):
    shape = instrument.pack()
    for x, y, z in sample_points(instrument, 400, 1):
        d = signed_distance(shape, x, y, z)[0]
        if abs(d) > 1e-9:
            assert (d < 0) == inside(instrument, x, y, z), (x, y, z, d)


@pytest.mark.parametrize("instrument", SHAPES, ids=IDS)
def test_normal_is_unit_gradient_of_distance(instrument):
    shape = instrument.pack()
    h = 1e-7
    agree = 0
    points = sample_points(instrument, 300, 2)
    for p in points:
        d, *n = signed_distance(shape, *p)
        assert np.linalg.norm(n) == pytest.approx(1.0, abs=1e-12)
        gradient = [
            (signed_distance(shape, *(p + h * e))[0] - signed_distance(shape, *(p - h * e))[0]) / (2 * h)
            for e in np.eye(3)
        ]
        agree += np.allclose(gradient, n, atol=1e-5)
    # Only points on a medial surface (equidistant from two faces) may disagree.
    assert agree >= 0.99 * len(points)


@pytest.mark.parametrize("instrument", [s for s in SHAPES if s.kind == "trephine" or s.tip in ("flat", "conical")])
def test_profile_distance_equals_brute_force(instrument):
    """Exact distance: minimum over a dense sampling of the meridian outline."""
    shape = instrument.pack()
    n = int(shape[1])
    rs, zs = shape[3 : 3 + n], shape[3 + n : 3 + 2 * n]
    edges = n if shape[2] else n - 1
    s = np.linspace(0, 1, 20001)
    outline = np.concatenate(
        [np.column_stack([rs[k] + s * (rs[(k + 1) % n] - rs[k]), zs[k] + s * (zs[(k + 1) % n] - zs[k])]) for k in range(edges)]
    )
    for p in sample_points(instrument, 100, 4):
        r, z = math.hypot(p[0], p[1]), p[2]
        brute = np.min(np.hypot(outline[:, 0] - r, outline[:, 1] - z))
        assert abs(signed_distance_rz(shape, r, z)[0]) == pytest.approx(brute, abs=1e-4)


def test_analytic_points():
    cone = Needle(tip="conical", tip_angle=60.0, diameter=0.2)
    alpha = math.radians(30.0)
    delta = 0.01
    # A point at distance delta outside the cone's generator, off its ends.
    s = 0.1
    point = np.array([s * math.sin(alpha), 0.0, s * math.cos(alpha)]) + delta * np.array([math.cos(alpha), 0, -math.sin(alpha)])
    d, nx, ny, nz = signed_distance(cone.pack(), *point)
    assert d == pytest.approx(delta, rel=1e-12)
    assert (nx, nz) == pytest.approx((math.cos(alpha), -math.sin(alpha)), rel=1e-12)
    assert signed_distance(cone.pack(), 0.0, 0.0, -0.05)[0] == pytest.approx(0.05)
    rounded = Needle(tip="rounded", diameter=0.4)
    direction = np.array([math.sin(0.7), 0.0, -math.cos(0.7)])
    point = np.array([0, 0, 0.2]) + 0.23 * direction
    d, *n = signed_distance(rounded.pack(), *point)
    assert d == pytest.approx(0.03, rel=1e-12)
    assert n == pytest.approx(list(direction), rel=1e-12)
    bevel = Needle(tip="bevelled", bevel_angle=20.0)
    gamma = math.radians(20.0)
    on_face = np.array([0.0, 0.0, 0.1 / math.tan(gamma)])
    normal = np.array([math.cos(gamma), 0.0, -math.sin(gamma)])
    assert signed_distance(bevel.pack(), *(on_face + 0.02 * normal))[0] == pytest.approx(0.02, rel=1e-12)
    assert signed_distance(bevel.pack(), *(on_face - 0.02 * normal))[0] == pytest.approx(-0.02, rel=1e-12)
    trephine = Trephine(diameter=7.5, wall_thickness=0.1, bevel_side="outer")
    assert signed_distance_rz(trephine.pack(), 3.75, -0.2)[0] == pytest.approx(0.2)
    assert signed_distance_rz(trephine.pack(), 3.70, 1.0)[:2] == pytest.approx((0.05, -1.0))
    assert signed_distance_rz(trephine.pack(), 3.90, 1.0)[:2] == pytest.approx((0.05, 1.0))
    assert signed_distance_rz(trephine.pack(), 3.76, 1.0)[:2] == pytest.approx((-0.01, -1.0))


def test_dimensions_are_parameters():
    assert Needle().diameter == 0.2 and Trephine().diameter == 7.5
    wide = Trephine(diameter=8.0)
    assert signed_distance_rz(wide.pack(), 4.0, -0.1)[0] == pytest.approx(0.1)
    assert Needle(diameter=0.5, tip="flat").pack()[4:6].tolist() == [0.25, 0.25]


@pytest.mark.parametrize(
    "data, key",
    [
        ({"kind": "needle", "diameter": -0.2}, "diameter"),
        ({"kind": "needle", "tip": "blunt"}, "tip"),
        ({"kind": "needle", "length": 0.1, "tip_angle": 10.0}, "length"),
        ({"kind": "trephine", "diameter": 0.1, "wall_thickness": 0.2, "bevel_side": "inner"}, "wall_thickness"),
        ({"kind": "trephine", "colour": "red"}, "colour"),
        ({"kind": "scalpel"}, "instrument"),
    ],
)
def test_bad_instrument_raises_input_error(data, key):
    with pytest.raises(InputError, match=key):
        instrument_from_dict(data, source="scenario.toml")
