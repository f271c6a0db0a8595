"""Contact kernel: penalty force, friction direction and saturation, torque, balance, masks."""

import math

import numpy as np
import pytest

from corneasim.tools.contact import (
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
    active_nodes,
    eval_contact,
)
from corneasim.tools.friction import Friction
from corneasim.tools.instruments import Needle, Trephine
from corneasim.tools.motion import Motion, needle_insertion
from corneasim.tools.amplitudes import Linear

FRICTIONLESS = Friction(law="none").pack()


def run(x, v, shape, pose, friction=FRICTIONLESS, mass=None, active=None, alpha=1.0, zeta=0.0, dt=1.0):
    n = x.shape[0]
    f = np.zeros_like(x)
    out = np.zeros(N_OUTPUTS)
    mass = np.ones(n) if mass is None else mass
    active = np.ones(n, np.uint8) if active is None else active
    area = np.full(n, 0.01)
    eval_contact(x, v, np.arange(n), active, mass, area, shape, pose, alpha, zeta, dt, friction, f, out)
    return f, out


def test_single_node_force_is_penalty_times_penetration_along_normal():
    cone = Needle(tip="conical", tip_angle=60.0)
    alpha = math.radians(30.0)
    pose = needle_insertion(speed=1.0, tip_position=(0.2, -0.1, 1.0)).pose(0.5)
    s, depth = 0.1, 0.003
    normal = np.array([math.cos(alpha), 0.0, -math.sin(alpha)])
    local = np.array([s * math.sin(alpha), 0.0, s * math.cos(alpha)]) - depth * normal
    x = (pose[:3] + local)[None, :]
    v = np.array([[0.0, 0.0, pose[6]]])  # moving with the needle: no slip, no damping
    mass, dt, fraction = np.array([2.0e-9]), 1.0e-7, 0.3
    f, out = run(x, v, cone.pack(), pose, mass=mass, alpha=fraction, dt=dt)
    k = fraction * mass[0] / dt**2
    assert f[0] == pytest.approx(k * depth * normal, rel=1e-10)
    assert out[[FORCE_X, FORCE_Y, FORCE_Z]] == pytest.approx(-k * depth * normal, rel=1e-10)
    assert out[MAX_PENETRATION] == pytest.approx(depth, rel=1e-10)
    assert (out[CONTACT_NODES], out[CONTACT_AREA]) == (1.0, 0.01)


def test_nodes_outside_or_inactive_feel_nothing():
    flat = Needle(tip="flat").pack()
    pose = Motion().pose(0.0)
    x = np.array([[0.0, 0.0, -0.001], [0.0, 0.0, 0.01], [0.05, 0.0, 0.02]])
    f, out = run(x, np.zeros_like(x), flat, pose, active=np.array([1, 1, 0], np.uint8))
    assert np.all(f[0] == 0) and np.all(f[2] == 0)
    assert f[1] == pytest.approx([0, 0, -0.01])
    assert out[CONTACT_NODES] == 1


def test_normal_damping_resists_approach_only():
    flat = Needle(tip="flat").pack()
    pose = Motion().pose(0.0)
    x = np.array([[0.0, 0.0, 0.01]])
    approaching, _ = run(x, np.array([[0.0, 0.0, 0.5]]), flat, pose, zeta=0.2, mass=np.array([4.0]))
    separating, _ = run(x, np.array([[0.0, 0.0, -100.0]]), flat, pose, zeta=0.2, mass=np.array([4.0]))
    c = 2 * 0.2 * math.sqrt(1.0 * 4.0 * 4.0)
    assert approaching[0, 2] == pytest.approx(-(4.0 * 0.01 + c * 0.5))
    assert separating[0, 2] == 0.0  # no adhesion


@pytest.mark.parametrize("slip", [[3.0, 0.0], [1.0, -2.0], [-0.3, 0.4]])
def test_coulomb_friction_opposes_slip_and_saturates(slip):
    flat = Needle(tip="flat").pack()
    pose = Motion().pose(0.0)
    x = np.array([[0.01, 0.02, 0.004]])
    mu, v_reg = 0.3, 1.0e-3
    friction = Friction(coefficient=mu, regularisation_speed=v_reg).pack()
    velocity = np.array([[slip[0], slip[1], 0.0]])
    f, out = run(x, velocity, flat, pose, friction=friction, mass=np.array([10.0]), dt=1.0e-3, alpha=1e-4)
    normal = 1e-4 * 10.0 / 1e-6 * 0.004
    tangential = f[0, :2]
    assert f[0, 2] == pytest.approx(-normal)
    assert np.linalg.norm(tangential) == pytest.approx(mu * normal, rel=1e-12)
    assert tangential / np.linalg.norm(tangential) == pytest.approx(-np.array(slip) / np.linalg.norm(slip))
    assert out[FRICTION_POWER] == pytest.approx(mu * normal * np.linalg.norm(slip))
    # Below the regularisation speed the friction grows linearly with the slip.
    slow, _ = run(x, velocity * 1e-4 / np.linalg.norm(slip), flat, pose, friction=friction, mass=np.array([10.0]),
                  dt=1.0e-3, alpha=1e-4)
    assert np.linalg.norm(slow[0, :2]) == pytest.approx(mu * normal * 0.1, rel=1e-12)


def test_friction_regularisation_is_raised_for_explicit_stability():
    flat = Needle(tip="flat").pack()
    pose = Motion().pose(0.0)
    x = np.array([[0.0, 0.0, 0.01]])
    mu, mass, dt, alpha = 0.5, 1e-9, 1e-7, 0.5
    friction = Friction(coefficient=mu, regularisation_speed=1e-6).pack()
    normal = alpha * mass / dt**2 * 0.01
    v_eff = mu * normal * dt / mass
    slip = 0.25 * v_eff
    f, _ = run(x, np.array([[slip, 0.0, 0.0]]), flat, pose, friction=friction, mass=np.array([mass]), dt=dt,
               alpha=alpha)
    assert -f[0, 0] == pytest.approx(mu * normal * 0.25, rel=1e-12)
    assert -f[0, 0] * dt / mass / slip <= 1.0  # the friction dashpot's c dt / m


def test_rotating_trephine_torque_resists_rotation():
    trephine = Trephine(diameter=7.5, wall_thickness=0.1)
    omega = 2.0
    pose = Motion(rotation=Linear(rate=omega)).pose(0.3)
    mu, depth = 0.2, 0.002
    radius = 3.75 + depth  # just inside the inner wall of the bore
    angles = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    x = np.column_stack([radius * np.cos(angles), radius * np.sin(angles), np.full(12, 1.0)])
    friction = Friction(coefficient=mu, regularisation_speed=1e-6).pack()
    f, out = run(x, np.zeros_like(x), trephine.pack(), pose, friction=friction, alpha=1.0, dt=1.0)
    normal = 1.0 * depth
    assert out[NORMAL_FORCE] == pytest.approx(12 * normal)
    assert out[TORQUE_Z] == pytest.approx(-12 * mu * normal * radius, rel=1e-10)
    assert out[TORQUE_Z] / trephine.cutting_radius < 0  # F_c = M_z / R resists the rotation
    assert out[[FORCE_X, FORCE_Y, FORCE_Z]] == pytest.approx([0, 0, 0], abs=1e-15)
    # Reversed rotation reverses the torque.
    backwards = Motion(rotation=Linear(rate=-omega)).pose(0.3)
    _, out_back = run(x, np.zeros_like(x), trephine.pack(), backwards, friction=friction, alpha=1.0, dt=1.0)
    assert out_back[TORQUE_Z] == pytest.approx(-out[TORQUE_Z])


@pytest.mark.parametrize("instrument", [Trephine(wall_thickness=0.3), Needle(tip="bevelled"), Needle(tip="rounded")])
def test_forces_on_instrument_and_tissue_balance(instrument):
    rng = np.random.default_rng(7)
    motion = Motion(insertion=Linear(rate=0.5), rotation=Linear(rate=1.5), tip_position=(0.1, 0.2, 0.0))
    pose = motion.pose(0.4)
    n = 300
    if instrument.kind == "trephine":
        r = rng.uniform(3.6, 4.2, n)
    else:
        r = rng.uniform(0.0, 0.15, n)
    phi = rng.uniform(0, 2 * np.pi, n)
    x = np.column_stack([pose[0] + r * np.cos(phi), pose[1] + r * np.sin(phi), pose[2] + rng.uniform(-0.05, 0.5, n)])
    v = rng.normal(size=(n, 3))
    f, out = run(x, v, instrument.pack(), pose, friction=Friction(coefficient=0.4).pack(), mass=rng.uniform(1, 2, n),
                 alpha=0.5, dt=0.1)
    assert out[CONTACT_NODES] > 10
    assert out[[FORCE_X, FORCE_Y, FORCE_Z]] == pytest.approx(-f.sum(axis=0), rel=1e-12)
    arm = x[:, :2] - pose[:2]
    torque_on_tissue = np.sum(arm[:, 0] * f[:, 1] - arm[:, 1] * f[:, 0])
    assert out[TORQUE_Z] == pytest.approx(-torque_on_tissue, rel=1e-12)


def test_axisymmetric_ring_forces():
    """(r, z) nodes: the force on the needle is minus the sum of the nodes' axial ring forces."""
    needle = Needle(tip="conical", tip_angle=90.0)
    pose = needle_insertion(speed=1.0, tip_position=(0.0, 0.5)).pose(0.1)
    x = np.array([[0.0, 0.395], [0.02, 0.43], [0.05, 0.46], [0.3, 0.3]])
    v = np.zeros_like(x)
    f, out = run(x, v, needle.pack(), pose, friction=Friction(coefficient=0.2).pack(), alpha=1.0, dt=1.0)
    assert out[CONTACT_NODES] == 2  # the first node is below the tip, the last beside it
    assert out[FORCE_Z] == pytest.approx(-f[:, 1].sum())
    assert out[FORCE_Z] > 0  # the tissue pushes the descending needle up
    assert (out[FORCE_X], out[FORCE_Y], out[TORQUE_Z]) == (0.0, 0.0, 0.0)
    # Node on the cone's face at depth p: normal force p along (cos 45, -sin 45) plus friction.
    depth = (0.43 - 0.4 - 0.02) * math.sin(math.pi / 4)
    f_n = depth
    slip_direction = np.array([1.0, 1.0]) / math.sqrt(2)  # tissue slides up the cone relative to it
    expected = f_n * np.array([1, -1]) / math.sqrt(2) - 0.2 * f_n * slip_direction
    assert f[1] == pytest.approx(expected, rel=1e-10)


def test_active_nodes_follow_live_elements():
    cells = np.array([[0, 1, 4, 3], [1, 2, 5, 4]])
    active = np.zeros(6, np.uint8)
    active_nodes(cells, np.array([1, 0], np.uint8), active)
    assert active.tolist() == [1, 1, 0, 1, 1, 0]
    active_nodes(cells, np.array([0, 0], np.uint8), active)
    assert active.sum() == 0
