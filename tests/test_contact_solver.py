"""Contact integrated with the explicit solver, against closed forms.

Each model is small and quasi-static: mass scaling equalises the element time steps (the
static answer does not depend on the mass) and mass-proportional damping settles it.
"""

import math

import numpy as np
import pytest

from corneasim.materials import KernelMaterial
from corneasim.mesh import Mesh
from corneasim.solver import Fixed, Prescribed, build_model, new_state, run
from corneasim.solver._amplitudes import Linear, SmoothStep
from corneasim.contact._settings import ContactSettings
from corneasim.contact._node import MAX_PENETRATION
from corneasim.contact._friction import Friction
from corneasim.instruments._kinds import Needle
from corneasim.contact._instrument_contact import InstrumentContact
from corneasim.instruments._motion import Motion, needle_insertion

E, NU = 1.0, 0.3
LAMBDA, G = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
MATERIAL = KernelMaterial(density=1e-9, c10=G / 2, d1=2 / (LAMBDA + 2 * G / 3))


def graded(fine_end, h, total, growth):
    """Uniform spacing h up to fine_end, then geometric growth up to total."""
    coordinates = list(np.arange(0.0, fine_end + 1e-12, h))
    step = h
    while coordinates[-1] < total:
        step *= growth
        coordinates.append(coordinates[-1] + step)
    return np.array(coordinates)


def half_space_mesh(h, fine_radius, fine_depth, size):
    """Axisymmetric (r, z) quad mesh of a cylinder of radius and depth `size`, top at z = 0."""
    r = graded(fine_radius, h, size, 1.3)
    z = -graded(fine_depth, h, size, 1.3)[::-1]
    R, Z = np.meshgrid(r, z)
    index = np.arange(R.size).reshape(R.shape)
    cells = np.column_stack([index[:-1, :-1].ravel(), index[:-1, 1:].ravel(), index[1:, 1:].ravel(),
                             index[1:, :-1].ravel()])
    return Mesh(np.column_stack([R.ravel(), Z.ravel()]), cells, "quad", np.zeros(len(cells), np.int64), ["layer"],
                axisymmetric=True, node_sets={"bottom": index[0], "top": index[-1]}), max(R.shape)


def quasi_static_model(mesh, conditions):
    """Model with every element's step raised to half the largest (mass scaling)."""
    probe = build_model(mesh, {"layer": MATERIAL}, conditions)
    return build_model(mesh, {"layer": MATERIAL}, conditions, target_time_step=0.5 * probe.element_time_step.max())


def test_flat_punch_matches_sneddon_and_penetration_is_small():
    """Frictionless rigid flat punch of radius a on a thick layer: F = 2 a E delta / (1 - nu^2)."""
    h = 0.0625
    mesh, n_across = half_space_mesh(h, 0.625, 0.25, 10.0)  # 20a wide and deep
    a = 0.5 + 0.5 * h  # the punch edge midway between the last loaded node and the next
    model = quasi_static_model(mesh, [Fixed("bottom", "rz")])
    dt = model.stable_time_step()[0]
    transit = n_across * dt
    duration = 20 * transit
    delta = 0.005
    motion = Motion(insertion=SmoothStep(0.0, duration, -0.001, delta), tip_position=(0.0, 0.0))
    punch = InstrumentContact(Needle(tip="flat", diameter=2 * a, length=1.0), motion, model,
                              ContactSettings(friction=Friction(law="none"), node_set="top"), name="punch")
    state = new_state(model)
    damping = 0.5 * 2 * math.pi / (4 * transit)
    for frame in run(model, state, 1.5 * duration, history_every=10**6, hooks=[punch], damping=damping):
        row = frame.history
    penetration = punch.out[MAX_PENETRATION]  # in the final state
    sneddon = 2 * a * E / (1 - NU**2) * (delta - penetration)
    assert row["punch_force_z_N"] == pytest.approx(sneddon, rel=0.05)
    assert punch.largest_penetration < 0.01 * punch.smallest_element_size
    # Static balance: the punch force is carried by the support.
    assert row["reaction_bottom_z_N"] == pytest.approx(row["punch_force_z_N"], rel=0.01)


def box_mesh(xs, ys, zs):
    X, Y, Z = np.meshgrid(xs, ys, zs, indexing="ij")
    index = np.arange(X.size).reshape(X.shape)
    cells = []
    for i in range(len(xs) - 1):
        for j in range(len(ys) - 1):
            for k in range(len(zs) - 1):
                bottom = [index[i, j, k], index[i + 1, j, k], index[i + 1, j + 1, k], index[i, j + 1, k]]
                top = [index[i, j, k + 1], index[i + 1, j, k + 1], index[i + 1, j + 1, k + 1], index[i, j + 1, k + 1]]
                cells.append(bottom + top)
    return Mesh(np.column_stack([X.ravel(), Y.ravel(), Z.ravel()]), np.array(cells, np.int64), "hexahedron",
                np.zeros(len(cells), np.int64), ["layer"],
                node_sets={"bottom": index[:, :, 0].ravel(), "top": index[:, :, -1].ravel()})


def test_block_dragged_under_a_plate_feels_mu_n():
    mesh = box_mesh(np.linspace(-0.5, 0.5, 5), np.linspace(-0.5, 0.5, 5), np.linspace(-0.25, 0.0, 3))
    step = build_model(mesh, {"layer": MATERIAL}).stable_time_step()[0]
    press = 200 * step
    mu = 0.3
    model = build_model(mesh, {"layer": MATERIAL}, [
        Fixed("bottom", "yz"), Prescribed("bottom", "x", "displacement", 0.1, SmoothStep(press, 2 * press))])
    motion = Motion(insertion=SmoothStep(0.0, press, -0.001, 0.0025))
    plate = InstrumentContact(Needle(tip="flat", diameter=4.0, length=1.0), motion, model,
                              ContactSettings(friction=Friction(coefficient=mu), node_set="top"), name="plate")
    sliding, held = [], []
    for frame in run(model, new_state(model), 3 * press, history_every=20, hooks=[plate]):
        row = frame.history
        if row and 1.3 * press < frame.time < 1.7 * press:
            sliding.append((row["plate_force_x_N"], row["plate_force_z_N"]))
        if row and frame.time > 2.5 * press:
            held.append((row["plate_force_x_N"], row["plate_force_z_N"]))
    sliding, held = np.array(sliding), np.array(held)
    assert len(sliding) > 3
    assert sliding[:, 0] == pytest.approx(mu * sliding[:, 1], rel=1e-3)  # drags the plate along +x
    assert np.all(sliding[:, 1] > 0)
    # At rest the friction holds the sheared block without exceeding mu N (static friction).
    assert np.all((held[:, 0] > 0.5 * mu * held[:, 1]) & (held[:, 0] <= mu * held[:, 1] * (1 + 1e-9)))


def annulus_mesh(radii, n_theta, height):
    theta = np.linspace(0, 2 * np.pi, n_theta, endpoint=False)
    R, T, Z = np.meshgrid(radii, theta, [0.0, height], indexing="ij")
    index = np.arange(R.size).reshape(R.shape)
    cells = []
    for i in range(len(radii) - 1):
        for j in range(n_theta):
            k = (j + 1) % n_theta
            cells.append([index[i, j, 0], index[i + 1, j, 0], index[i + 1, k, 0], index[i, k, 0],
                          index[i, j, 1], index[i + 1, j, 1], index[i + 1, k, 1], index[i, k, 1]])
    points = np.column_stack([(R * np.cos(T)).ravel(), (R * np.sin(T)).ravel(), Z.ravel()])
    return Mesh(points, np.array(cells, np.int64), "hexahedron", np.zeros(len(cells), np.int64), ["layer"],
                node_sets={"all": np.arange(R.size), "outer": index[-1].ravel(), "hole": index[0].ravel()})


def test_cylinder_turning_in_a_hole_feels_the_friction_torque():
    """A rigid shaft (radius a + delta) pushed into a hole of radius a in a ring held at its
    outer radius b, in plane strain, then turned: M_z = -mu a p 2 pi a H, with the Lame pressure
    p = delta' a / (b^2 - a^2) [2 (lambda + G) + 2 G b^2 / a^2] (delta' the interference less the
    contact penetration)."""
    a, b, height, delta, mu, omega = 0.5, 1.5, 0.1, 0.005, 0.2, 20.0
    mesh = annulus_mesh(a * (b / a) ** np.linspace(0, 1, 5), 24, height)
    conditions = [Fixed("all", "z"), Fixed("outer", "xy")]
    probe = build_model(mesh, {"layer": MATERIAL}, conditions)
    model = build_model(mesh, {"layer": MATERIAL}, conditions, target_time_step=0.9 * probe.element_time_step.max())
    transit = 16 * model.stable_time_step()[0]
    duration = 20 * transit
    shaft = Needle(tip="conical", tip_angle=90.0, diameter=2 * (a + delta), length=3.0)
    start = height - a + 0.001  # the cone's shoulder touches the hole at once, at low speed
    motion = Motion(insertion=SmoothStep(0.0, duration, 0.0, start + shaft.tip_height + 0.05),
                    rotation=Linear(rate=omega, start_time=duration), tip_position=(0.0, 0.0, start))
    hook = InstrumentContact(shaft, motion, model, ContactSettings(friction=Friction(coefficient=mu), node_set="hole"),
                             name="shaft")
    for frame in run(model, new_state(model), 1.5 * duration, history_every=10**6, hooks=[hook],
                     damping=2 * math.pi / (4 * transit)):
        row = frame.history
    interference = delta - hook.out[MAX_PENETRATION]  # in the final state
    pressure = interference * a / (b**2 - a**2) * (2 * (LAMBDA + G) + 2 * G * b**2 / a**2)
    normal = pressure * 2 * math.pi * a * height
    assert row["shaft_normal_force_N"] == pytest.approx(normal, rel=0.05)
    assert row["shaft_torque_z_Nmm"] == pytest.approx(-mu * normal * (a + delta), rel=0.05)
    assert row["shaft_rotary_cutting_force_N"] == pytest.approx(row["shaft_torque_z_Nmm"] / (a + delta))


def test_deleted_elements_release_their_nodes_and_expose_the_next_layer():
    mesh, _ = half_space_mesh(0.1, 0.3, 0.3, 0.5)
    model = build_model(mesh, {"layer": MATERIAL}, [Fixed("bottom", "rz")])
    state = new_state(model)
    top = mesh.points[:, 1].max()
    top_row = np.flatnonzero(mesh.points[mesh.cells].max(axis=1)[:, 1] > top - 1e-9)
    state.alive[top_row] = 0
    state.node_active[:] = 0
    state.node_active[mesh.cells[state.alive == 1].ravel()] = 1
    punch = InstrumentContact(Needle(tip="flat", diameter=0.4, length=1.0), Motion(tip_position=(0.0, top - 0.15)),
                              model, ContactSettings(friction=Friction(law="none")))
    f_ext = np.zeros_like(state.u)
    punch.add_forces(model, state, 0.0, model.stable_time_step()[0], f_ext)
    loaded = np.flatnonzero(np.any(f_ext != 0, axis=1))
    assert loaded.size > 0
    assert np.all(state.node_active[loaded] == 1)
    assert np.allclose(mesh.points[loaded, 1], top - 0.1)  # the newly exposed surface
    assert np.all(mesh.points[loaded, 0] < 0.2)


def test_needle_cutting_through_failing_elements_meets_the_exposed_nodes():
    """A conical needle pushed into a block whose elements fail: nodes of the layers below
    the original surface take over the contact, and no released node is ever loaded."""
    from corneasim.materials._kernel_form import FAILURE_VON_MISES

    h, size = 0.05, 0.4
    s = np.arange(0.0, size + 1e-12, h)
    R, Z = np.meshgrid(s, s - size)
    index = np.arange(R.size).reshape(R.shape)
    cells = np.column_stack([index[:-1, :-1].ravel(), index[:-1, 1:].ravel(), index[1:, 1:].ravel(),
                             index[1:, :-1].ravel()])
    mesh = Mesh(np.column_stack([R.ravel(), Z.ravel()]), cells, "quad", np.zeros(len(cells), np.int64), ["layer"],
                axisymmetric=True, node_sets={"bottom": index[0], "side": index[:, -1]})
    brittle = KernelMaterial(density=1e-9, c10=0.17, d1=0.2, failure_criterion=FAILURE_VON_MISES, failure_limit=0.05)
    model = build_model(mesh, {"layer": brittle}, [Fixed("bottom", "rz"), Fixed("side", "rz")], target_time_step=4e-6)
    speed = 100.0
    needle = InstrumentContact(Needle(tip="conical", tip_angle=30.0), needle_insertion(speed, (0.0, 0.001)), model,
                               ContactSettings(friction=Friction(coefficient=0.1)), name="needle")
    state = new_state(model)
    interior = mesh.points[:, 1] < -0.5 * h
    joined = np.zeros(mesh.n_nodes, bool)
    active_during_step = state.node_active.copy()
    for frame in run(model, state, 0.2 / speed, history_every=1, hooks=[needle]):
        # Contact is evaluated before the step's deletions: nodes released in this step may
        # still hold it (the solver zeroes their acceleration), released ones before may not.
        loaded = np.any(state.f_ext != 0, axis=1)
        assert np.all(active_during_step[loaded] == 1)
        active_during_step = state.node_active.copy()
        joined |= loaded & interior
        row = frame.history
    assert row["deleted_elements"] > 0
    assert joined.sum() >= 2


def test_oscillating_trephine_torque_follows_the_fourier_rotation():
    """Trephine edge pressed into a ring of tissue, then turned by theta = B sin(omega t)
    (trephination paper eq. 1, sped up): while sliding, M_z = -sgn(omega) mu N r and
    F_c = M_z / R."""
    from corneasim.solver._amplitudes import Fourier
    from corneasim.instruments._kinds import Trephine

    r_node, mu = 3.76, 0.2  # one ring of nodes just outside the edge, under the outer bevel
    mesh = annulus_mesh(np.array([3.6, 3.7, r_node, 3.9, 4.0]), 72, 0.1)
    mesh.points[:, 2] -= 0.1
    mesh.node_sets["bottom"] = np.flatnonzero(mesh.points[:, 2] < -0.099)
    mesh.node_sets["top"] = np.flatnonzero(mesh.points[:, 2] > -1e-9)
    probe = build_model(mesh, {"layer": MATERIAL}, [Fixed("bottom", "xyz")])
    model = build_model(mesh, {"layer": MATERIAL}, [Fixed("bottom", "xyz")],
                        target_time_step=0.9 * probe.element_time_step.max())
    dt = model.stable_time_step()[0]
    press, omega = 300 * dt, 2 * math.pi / (600 * dt)
    motion = Motion(insertion=SmoothStep(0.0, press, -0.001, 0.03),
                    rotation=Fourier(sine=(0.05,), cosine=(0.0,), circular_frequency=omega, start_time=press))
    trephine = Trephine(diameter=7.5, wall_thickness=0.1)
    hook = InstrumentContact(trephine, motion, model,
                             ContactSettings(friction=Friction(coefficient=mu), node_set="top"), name="trephine")
    checked = 0
    for frame in run(model, new_state(model), press + 2 * math.pi / omega, history_every=20, hooks=[hook]):
        row = frame.history
        rate = hook.pose[7]
        if row is None or frame.time < press + 0.3 * math.pi / omega or abs(rate) < 0.3 * 0.05 * omega:
            continue
        torque = row["trephine_torque_z_Nmm"]
        assert torque == pytest.approx(-np.sign(rate) * mu * row["trephine_normal_force_N"] * r_node, rel=0.01)
        assert row["trephine_rotary_cutting_force_N"] == pytest.approx(torque / 3.75)
        assert row["trephine_linear_cutting_force_N"] > 0
        checked += 1
    assert checked > 10


def test_frictionless_trephine_normal_force_does_not_depend_on_its_rotation():
    """A frictionless body of revolution turning about its axis exerts the same forces as a
    still one: the same tissue ring pressed by the same edge, once still and once turned by
    1.25 sin(omega t) rad (the paper's amplitude, sped up), gives identical normal forces."""
    from corneasim.solver._amplitudes import Fourier
    from corneasim.instruments._kinds import Trephine

    mesh = annulus_mesh(np.array([3.6, 3.7, 3.76, 3.9, 4.0]), 72, 0.1)
    mesh.points[:, 2] -= 0.1
    mesh.node_sets["bottom"] = np.flatnonzero(mesh.points[:, 2] < -0.099)
    mesh.node_sets["top"] = np.flatnonzero(mesh.points[:, 2] > -1e-9)
    probe = build_model(mesh, {"layer": MATERIAL}, [Fixed("bottom", "xyz")])
    histories = []
    for amplitude in (0.0, 1.25):
        model = build_model(mesh, {"layer": MATERIAL}, [Fixed("bottom", "xyz")],
                            target_time_step=0.9 * probe.element_time_step.max())
        dt = model.stable_time_step()[0]
        press, omega = 300 * dt, 2 * math.pi / (600 * dt)
        motion = Motion(insertion=SmoothStep(0.0, press, -0.001, 0.03),
                        rotation=Fourier(sine=(amplitude,), cosine=(0.0,), circular_frequency=omega,
                                         start_time=press))
        hook = InstrumentContact(Trephine(diameter=7.5, wall_thickness=0.1), motion, model,
                                 ContactSettings(friction=Friction(coefficient=0.0), node_set="top"),
                                 name="trephine")
        histories.append([frame.history["trephine_normal_force_N"]
                          for frame in run(model, new_state(model), press + 2 * math.pi / omega,
                                           history_every=50, hooks=[hook])
                          if frame.history is not None])
    still, turning = np.array(histories[0]), np.array(histories[1])
    assert still.max() > 0.05
    np.testing.assert_allclose(turning, still, rtol=1e-9, atol=1e-12)
