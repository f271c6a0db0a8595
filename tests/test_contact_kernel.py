"""Contact kernel: penalty force, stick and slip friction, torque, force balance, masks."""

import math

import numpy as np
import pytest

from corneasim.solver._amplitudes import Linear
from corneasim.contact._node import (
    CONTACT_AREA,
    CONTACT_NODES,
    FORCE_X,
    FORCE_Y,
    FORCE_Z,
    FRICTION_POWER,
    MAX_PENETRATION,
    N_OUTPUTS,
    NORMAL_FORCE,
    TORQUE_Z,
    eval_contact,
)
from corneasim.contact._friction import Friction
from corneasim.instruments._kinds import Needle, Trephine
from corneasim.instruments._motion import Motion, needle_insertion

FRICTIONLESS = Friction(law="none").pack()


class Contact:
    """The kernel with its per-node friction state kept between calls."""

    def __init__(self, n, shape, friction=FRICTIONLESS, mass=None, alpha=1.0, zeta=0.0, dt=1.0):
        self.shape, self.friction, self.alpha, self.zeta, self.dt = shape, friction, alpha, zeta, dt
        self.mass = np.ones(n) if mass is None else np.asarray(mass, dtype=float)
        self.area = np.full(n, 0.01)
        self.anchor = np.zeros((n, 3))
        self.touching = np.zeros(n, np.uint8)

    def __call__(self, x, v, pose, active=None):
        n = x.shape[0]
        f = np.zeros_like(x)
        out = np.zeros(N_OUTPUTS)
        active = np.ones(n, np.uint8) if active is None else active
        eval_contact(x, v, np.arange(n), active, self.mass, self.area, self.shape, pose, self.alpha, self.zeta,
                     self.dt, self.friction, self.anchor, self.touching, f, out, np.empty(n, np.int64))
        return f, out


def test_single_node_force_is_penalty_times_penetration_along_normal():
    cone = Needle(tip="conical", tip_angle=60.0)
    alpha = math.radians(30.0)
    pose = needle_insertion(speed=1.0, tip_position=(0.2, -0.1, 1.0)).pose(0.5)
    s, depth = 0.1, 0.003
    normal = np.array([math.cos(alpha), 0.0, -math.sin(alpha)])
    local = np.array([s * math.sin(alpha), 0.0, s * math.cos(alpha)]) - depth * normal
    x = (pose[:3] + local)[None, :]
    v = np.array([[0.0, 0.0, pose[6]]])  # moving with the needle: no damping force
    mass, dt, fraction = 2.0e-9, 1.0e-7, 0.3
    contact = Contact(1, cone.pack(), Friction(coefficient=0.5).pack(), mass=[mass], alpha=fraction, dt=dt)
    f, out = contact(x, v, pose)
    k = fraction * mass / dt**2
    assert f[0] == pytest.approx(k * depth * normal, rel=1e-10)
    assert out[[FORCE_X, FORCE_Y, FORCE_Z]] == pytest.approx(-k * depth * normal, rel=1e-10)
    assert out[MAX_PENETRATION] == pytest.approx(depth, rel=1e-10)
    assert (out[CONTACT_NODES], out[CONTACT_AREA]) == (1.0, 0.01)


def test_nodes_outside_or_inactive_feel_nothing():
    flat = Needle(tip="flat").pack()
    pose = Motion().pose(0.0)
    x = np.array([[0.0, 0.0, -0.001], [0.0, 0.0, 0.01], [0.05, 0.0, 0.02]])
    contact = Contact(3, flat)
    f, out = contact(x, np.zeros_like(x), pose, active=np.array([1, 1, 0], np.uint8))
    assert np.all(f[0] == 0) and np.all(f[2] == 0)
    assert f[1] == pytest.approx([0, 0, -0.01])
    assert out[CONTACT_NODES] == 1
    assert contact.touching.tolist() == [0, 1, 0]


def test_normal_damping_resists_approach_only():
    flat = Needle(tip="flat").pack()
    pose = Motion().pose(0.0)
    x = np.array([[0.0, 0.0, 0.01]])
    approaching, _ = Contact(1, flat, mass=[4.0], zeta=0.2)(x, np.array([[0.0, 0.0, 0.5]]), pose)
    separating, _ = Contact(1, flat, mass=[4.0], zeta=0.2)(x, np.array([[0.0, 0.0, -100.0]]), pose)
    c = 2 * 0.2 * math.sqrt(1.0 * 4.0 * 4.0)
    assert approaching[0, 2] == pytest.approx(-(4.0 * 0.01 + c * 0.5))
    assert separating[0, 2] == 0.0  # no adhesion


@pytest.mark.parametrize("slip", [[3.0, 0.0], [1.0, -2.0], [-0.3, 0.4]])
def test_friction_sticks_elastically_then_slides_at_mu_n(slip):
    flat = Needle(tip="flat").pack()
    pose = Motion().pose(0.0)
    mu, depth, beta = 0.3, 0.004, 0.5
    contact = Contact(1, flat, Friction(coefficient=mu, tangential_stiffness_ratio=beta).pack())
    start = np.array([[0.01, 0.02, depth]])
    f, _ = contact(start, np.zeros((1, 3)), pose)  # first touch: the anchor is set, no friction
    assert f[0] == pytest.approx([0, 0, -depth])
    direction = np.array([*slip, 0.0]) / np.linalg.norm(slip)
    k_t = beta * 1.0
    # A small tangential move (below the Coulomb cap) is resisted elastically.
    small = mu * depth / k_t * 0.4
    f, _ = contact(start + small * direction, np.zeros((1, 3)), pose)
    assert f[0, :2] == pytest.approx(-k_t * small * direction[:2], rel=1e-12)
    # A large move slides: |f_t| = mu f_n, opposite to the slip.
    velocity = 2.0 * direction[None, :]
    f, out = contact(start + 5 * mu * depth / k_t * direction, velocity, pose)
    assert f[0, 2] == pytest.approx(-depth)
    assert f[0, :2] == pytest.approx(-mu * depth * direction[:2], rel=1e-12)
    assert out[FRICTION_POWER] == pytest.approx(mu * depth * 2.0)
    # Staying put keeps the sliding force (the anchor followed the slip); moving back unloads.
    f_same, _ = contact(start + 5 * mu * depth / k_t * direction, np.zeros((1, 3)), pose)
    assert f_same[0, :2] == pytest.approx(-mu * depth * direction[:2], rel=1e-12)
    back = 0.2 * mu * depth / k_t
    f_back, _ = contact(start + (5 * mu * depth / k_t - back) * direction, np.zeros((1, 3)), pose)
    assert f_back[0, :2] == pytest.approx(-(mu * depth - k_t * back) * direction[:2], rel=1e-12)


def test_leaving_contact_forgets_the_stick_point():
    flat = Needle(tip="flat").pack()
    pose = Motion().pose(0.0)
    contact = Contact(1, flat, Friction(coefficient=0.5).pack())
    contact(np.array([[0.0, 0.0, 0.01]]), np.zeros((1, 3)), pose)
    contact(np.array([[0.0, 0.0, -0.01]]), np.zeros((1, 3)), pose)
    f, _ = contact(np.array([[0.05, 0.0, 0.01]]), np.zeros((1, 3)), pose)
    assert f[0] == pytest.approx([0, 0, -0.01])


def test_rotating_trephine_torque_resists_rotation():
    trephine = Trephine(diameter=7.5, wall_thickness=0.1)
    mu, depth = 0.2, 0.002
    radius = 3.75 + depth  # just inside the inner wall of the bore
    angles = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    x = np.column_stack([radius * np.cos(angles), radius * np.sin(angles), np.full(12, 1.0)])
    for omega in (2.0, -2.0):
        motion = Motion(rotation=Linear(rate=omega))
        contact = Contact(12, trephine.pack(), Friction(coefficient=mu).pack())
        contact(x, np.zeros_like(x), motion.pose(0.1))
        f, out = contact(x, np.zeros_like(x), motion.pose(0.2))  # turned by 0.2 rad: sliding
        normal = 1.0 * depth
        assert out[NORMAL_FORCE] == pytest.approx(12 * normal)
        assert out[TORQUE_Z] == pytest.approx(-np.sign(omega) * 12 * mu * normal * radius, rel=1e-10)
        assert out[[FORCE_X, FORCE_Y, FORCE_Z]] == pytest.approx([0, 0, 0], abs=1e-15)
        # The tissue is dragged along the rotation (tangential force along omega e_z x r).
        hoop = np.column_stack([-np.sin(angles), np.cos(angles)])
        assert np.sum(f[:, :2] * hoop, axis=1) == pytest.approx(np.sign(omega) * mu * normal * np.ones(12))


@pytest.mark.parametrize("instrument", [Trephine(wall_thickness=0.3), Needle(tip="bevelled"), Needle(tip="rounded")])
def test_forces_on_instrument_and_tissue_balance(instrument):
    rng = np.random.default_rng(7)
    motion = Motion(insertion=Linear(rate=0.5), rotation=Linear(rate=1.5), tip_position=(0.1, 0.2, 0.0))
    n = 300
    r = rng.uniform(3.6, 4.2, n) if instrument.kind == "trephine" else rng.uniform(0.0, 0.15, n)
    phi = rng.uniform(0, 2 * np.pi, n)
    pose = motion.pose(0.4)
    x = np.column_stack([pose[0] + r * np.cos(phi), pose[1] + r * np.sin(phi), pose[2] + rng.uniform(-0.05, 0.5, n)])
    contact = Contact(n, instrument.pack(), Friction(coefficient=0.4).pack(), mass=rng.uniform(1, 2, n), alpha=0.5,
                      dt=0.1)
    contact(x, rng.normal(size=(n, 3)), motion.pose(0.3))
    f, out = contact(x, rng.normal(size=(n, 3)), pose)
    assert out[CONTACT_NODES] > 10 and out[FRICTION_POWER] != 0.0
    assert out[[FORCE_X, FORCE_Y, FORCE_Z]] == pytest.approx(-f.sum(axis=0), rel=1e-12)
    arm = x[:, :2] - pose[:2]
    torque_on_tissue = np.sum(arm[:, 0] * f[:, 1] - arm[:, 1] * f[:, 0])
    assert out[TORQUE_Z] == pytest.approx(-torque_on_tissue, rel=1e-12)


def test_axisymmetric_ring_forces():
    """(r, z) nodes: the force on the needle is minus the sum of the nodes' axial ring forces."""
    needle = Needle(tip="conical", tip_angle=90.0)
    motion = needle_insertion(speed=1.0, tip_position=(0.0, 0.5))
    x = np.array([[0.0, 0.395], [0.02, 0.43], [0.05, 0.46], [0.3, 0.3]])
    v = np.zeros_like(x)
    mu = 0.2
    contact = Contact(4, needle.pack(), Friction(coefficient=mu).pack())
    contact(x, v, motion.pose(0.095))
    f, out = contact(x, v, motion.pose(0.1))  # the needle moved 5 um down: the nodes slide
    assert out[CONTACT_NODES] == 2  # the first node is below the tip, the last beside it
    assert out[FORCE_Z] == pytest.approx(-f[:, 1].sum())
    assert out[FORCE_Z] > 0  # the tissue pushes the descending needle up
    assert (out[FORCE_X], out[FORCE_Y], out[TORQUE_Z]) == (0.0, 0.0, 0.0)
    # Node on the cone's face at depth p: normal force p along (cos 45, -sin 45) plus friction
    # mu p dragging it down the face (the tissue slides up the cone relative to it).
    depth = (0.43 - 0.4 - 0.02) * math.sin(math.pi / 4)
    expected = depth * np.array([1, -1]) / math.sqrt(2) - mu * depth * np.array([1, 1]) / math.sqrt(2)
    assert f[1] == pytest.approx(expected, rel=1e-10)


@pytest.mark.parametrize("instrument", [Trephine(bevel_side="symmetric"), Needle(tip="bevelled"), Needle(tip="conical")])
def test_bounding_shell_skips_only_nodes_outside(instrument):
    """The contact count equals the number of nodes with d < 0 evaluated shape by shape."""
    from corneasim.instruments._shapes import signed_distance

    rng = np.random.default_rng(11)
    motion = Motion(insertion=Linear(rate=0.5), rotation=Linear(rate=1.5), tip_position=(0.1, 0.2, 0.0))
    pose = motion.pose(0.4)
    n = 2000
    reach = 4.0 if instrument.kind == "trephine" else 0.15
    x = pose[:3] + np.column_stack([rng.uniform(-reach, reach, (n, 2)), rng.uniform(-0.1, 0.6, n)])
    contact = Contact(n, instrument.pack())
    _, out = contact(x, np.zeros_like(x), pose)
    c, s = math.cos(pose[3]), math.sin(pose[3])
    d = [x_ - pose[:3] for x_ in x]
    inside = sum(signed_distance(instrument.pack(), c * p[0] + s * p[1], -s * p[0] + c * p[1], p[2])[0] < 0 for p in d)
    assert inside > 20
    assert out[CONTACT_NODES] == inside


def test_sticking_dissipates_nothing():
    flat = Needle(tip="flat").pack()
    pose = Motion().pose(0.0)
    contact = Contact(1, flat, Friction(coefficient=0.5).pack())
    x = np.array([[0.0, 0.0, 0.01]])
    contact(x, np.zeros((1, 3)), pose)
    _, out = contact(x + [[1e-4, 0.0, 0.0]], np.array([[1.0, 0.0, 0.0]]), pose)  # 1e-4 < mu p / k_t
    assert out[FRICTION_POWER] == 0.0


def test_candidate_list_holds_every_node_that_can_touch():
    """contact_candidates keeps, in set order, the nodes within the margin of the bounding
    shell; the contact over the candidates equals the contact over the whole set, and a node
    that jumps into the shell between two lists is counted as missed."""
    from corneasim.contact._node import contact_candidates, shape_bounds

    trephine = Trephine(diameter=7.5, wall_thickness=0.1, bevel_angle=30.0)
    shape = trephine.pack()
    pose = Motion(insertion=Linear(rate=0.02), tip_position=(0.1, -0.2, 1.0)).pose(2.0)
    rng = np.random.default_rng(5)
    n = 4000
    radius = rng.uniform(2.0, 5.0, n)
    angle = rng.uniform(0.0, 2.0 * np.pi, n)
    x = np.column_stack([pose[0] + radius * np.cos(angle), pose[1] + radius * np.sin(angle),
                         pose[2] + rng.uniform(-0.5, 1.0, n)])
    nodes = np.arange(n)
    is_candidate, touching = np.zeros(n, np.uint8), np.ones(n, np.uint8)
    candidates = np.empty(n, np.int64)
    margin = 0.25
    count, _ = contact_candidates(x, nodes, shape, pose, margin, is_candidate, touching, candidates)
    r_min, r_max, z_min, z_max = shape_bounds(shape)
    z = x[:, 2] - pose[2]
    inside = (radius >= r_min - margin) & (radius <= r_max + margin) & (z >= z_min - margin) & (z <= z_max + margin)
    np.testing.assert_array_equal(candidates[:count], np.flatnonzero(inside))
    assert np.all(touching[~inside] == 0) and np.all(touching[inside] == 1)
    full, over_candidates = Contact(n, shape), Contact(n, shape)
    v = np.zeros_like(x)
    f_all, out_all = full(x, v, pose)
    f_some = np.zeros_like(x)
    out_some = np.zeros(N_OUTPUTS)
    eval_contact(x, v, candidates[:count], np.ones(n, np.uint8), over_candidates.mass, over_candidates.area,
                 shape, pose, 1.0, 0.0, 1.0, FRICTIONLESS, over_candidates.anchor, over_candidates.touching,
                 f_some, out_some, np.empty(n, np.int64))
    assert out_all[CONTACT_NODES] > 0
    np.testing.assert_array_equal(f_some, f_all)
    np.testing.assert_array_equal(out_some, out_all)
    # a node far outside jumps into the wall of the trephine: the next list reports it
    far = int(np.flatnonzero(~inside)[0])
    x[far] = pose[:3] + np.array([0.5 * (r_min + r_max), 0.0, 0.5 * (z_min + z_max)])
    count, missed = contact_candidates(x, nodes, shape, pose, margin, is_candidate, touching, candidates)
    assert missed == 1 and far in candidates[:count]
