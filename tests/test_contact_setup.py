"""Contact set-up: configuration tables, hook input errors, areas, the penalty stability rule."""

import math
import warnings

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.materials import KernelMaterial
from corneasim.mesh import Mesh
from corneasim.schema import validate
from corneasim.solver import build_model, new_state
from corneasim.contact._settings import ContactSettings
from corneasim.instruments._motion import MotionConfig
from corneasim.contact._node import N_OUTPUTS, eval_contact
from corneasim.contact._friction import Friction, FrictionValidityWarning
from corneasim.instruments._kinds import Needle, Trephine
from corneasim.contact._instrument_contact import InstrumentContact, nodal_contact_areas, stable_penalty_fraction
from corneasim.instruments._motion import Motion, needle_insertion

MATERIAL = KernelMaterial(density=1e-9, c10=0.2, d1=2.0)


def square_mesh(axisymmetric=True, n=3, size=1.0):
    s = np.linspace(0.0, size, n + 1)
    R, Z = np.meshgrid(s, s - size)
    index = np.arange(R.size).reshape(R.shape)
    cells = np.column_stack([index[:-1, :-1].ravel(), index[:-1, 1:].ravel(), index[1:, 1:].ravel(),
                             index[1:, :-1].ravel()])
    return Mesh(np.column_stack([R.ravel(), Z.ravel()]), cells, "quad", np.zeros(len(cells), np.int64), ["b"],
                axisymmetric=axisymmetric, node_sets={"top": index[-1]})


def test_motion_config_builds_the_paper_trephination():
    config = validate(MotionConfig, {
        "tip_position": [0.0, 0.0, 0.6],
        "insertion": {"type": "linear", "rate": 0.020},
        "rotation": {"type": "fourier", "sine": [1.25], "cosine": [0.0], "circular_frequency": 3.508},
    })
    pose = config.build().pose(0.4)
    assert pose[2] == pytest.approx(0.6 - 0.020 * 0.4)
    assert pose[3] == pytest.approx(1.25 * math.sin(3.508 * 0.4))


@pytest.mark.parametrize("data, key", [
    ({"insertion": {"type": "linear"}}, "rate"),
    ({"insertion": {"type": "jerk", "rate": 1.0}}, "insertion"),
    ({"rotation": {"type": "constant", "value": 0.0, "unit": "deg"}}, "unit"),
])
def test_bad_motion_tables_name_the_key(data, key):
    with pytest.raises(InputError, match=key):
        validate(MotionConfig, data, "scenario.toml")


def test_inconsistent_amplitude_is_an_input_error():
    config = validate(MotionConfig, {"insertion": {"type": "smooth-step", "t0": 1.0, "t1": 0.5}})
    with pytest.raises(InputError, match="t1"):
        config.build()


def test_contact_settings_reject_unstable_or_unknown_values():
    with pytest.raises(InputError, match="penalty_fraction"):
        validate(ContactSettings, {"penalty_fraction": 5.0})
    with pytest.raises(InputError, match="tangential_stiffness_ratio"):
        validate(ContactSettings, {"friction": {"tangential_stiffness_ratio": 2.0}})


def test_hook_input_errors():
    model = build_model(square_mesh(), {"b": MATERIAL}, safety_factor=0.9)
    with pytest.raises(InputError, match="bevelled"):
        InstrumentContact(Needle(tip="bevelled"), Motion(), model)
    with pytest.raises(InputError, match="node_set"):
        InstrumentContact(Needle(), Motion(), model, ContactSettings(node_set="cornea"))
    with pytest.raises(InputError, match="penalty_fraction"):
        InstrumentContact(Needle(), Motion(), model, ContactSettings(penalty_fraction=0.8))
    InstrumentContact(Trephine(), Motion(), model, ContactSettings(penalty_fraction=0.75, node_set="top"))


def test_penalty_stability_limit_of_central_differences():
    """A node held inside a flat face by a constant force F0 oscillates on the penalty spring
    about p0 = F0 / k: bounded for alpha < 4, growing for alpha > 4 ((omega dt)^2 = alpha)."""
    assert stable_penalty_fraction(0.9) == pytest.approx(0.76)
    flat = Needle(tip="flat").pack()
    pose = Motion().pose(0.0)
    dt, mass, p0 = 1e-3, np.ones(1), 0.01
    for alpha, bounded in ((3.9, True), (4.1, False)):
        pull = alpha * mass[0] / dt**2 * p0
        x, v = np.array([[0.0, 0.0, 1.05 * p0]]), np.zeros((1, 3))
        anchor, touching, out = np.zeros((1, 3)), np.zeros(1, np.uint8), np.zeros(N_OUTPUTS)
        largest = 0.0
        for _ in range(300):
            f = np.array([[0.0, 0.0, pull]])
            eval_contact(x, v, np.arange(1), np.ones(1, np.uint8), mass, mass, flat, pose, alpha, 0.0, dt,
                         Friction(law="none").pack(), anchor, touching, f, out, np.empty(1, np.int64))
            v += dt * f / mass[:, None]
            x += dt * v
            largest = max(largest, abs(x[0, 2] - p0))
        assert (largest < 0.5 * p0) == bounded


def test_nodal_areas_of_regular_meshes():
    mesh = square_mesh(axisymmetric=True, n=4, size=1.0)
    areas, smallest = nodal_contact_areas(mesh.points, mesh.cells, True)
    h = 0.25
    assert smallest == pytest.approx(h)
    r = mesh.points[:, 0]
    assert areas == pytest.approx(2 * np.pi * np.maximum(r, h / 8) * h)
    cube = np.array([[0, 0, 0], [2, 0, 0], [2, 3, 0], [0, 3, 0], [0, 0, 4], [2, 0, 4], [2, 3, 4], [0, 3, 4.0]])
    areas, smallest = nodal_contact_areas(cube, np.arange(8)[None, :], False)
    assert smallest == pytest.approx(24 ** (1 / 3))
    assert areas == pytest.approx(np.full(8, 24 ** (2 / 3)))


def test_hook_outputs_and_karnopp_warning():
    mesh = square_mesh(n=3, size=0.3)
    model = build_model(mesh, {"b": MATERIAL})
    state = new_state(model)
    settings = ContactSettings(friction=Friction(law="karnopp"), node_set="top")
    slow = InstrumentContact(Needle(tip="flat", diameter=0.3), needle_insertion(0.5, (0.0, 0.01)), model, settings,
                             name="needle")
    f_ext = np.zeros_like(state.u)
    with pytest.warns(FrictionValidityWarning):
        slow.add_forces(model, state, 0.04, model.stable_time_step()[0], f_ext)
    row = slow.outputs()
    assert row["needle_contact_nodes"] == 2  # r = 0 and r = 0.1 are under the punch of radius 0.15
    assert row["needle_force_z_N"] == pytest.approx(-f_ext[:, 1].sum())
    assert row["needle_max_penetration_mm"] == pytest.approx(0.01)
    assert slow.outputs()["needle_max_penetration_mm"] == 0.0  # reset after each row
    fast = InstrumentContact(Needle(tip="flat", diameter=0.3), needle_insertion(1.0, (0.0, 0.01)), model, settings)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fast.add_forces(model, state, 0.02, model.stable_time_step()[0], np.zeros_like(state.u))


def test_symmetry_factor_reports_the_whole_eye():
    mesh = square_mesh(n=3, size=0.3)
    model = build_model(mesh, {"b": MATERIAL})
    state = new_state(model)
    settings = ContactSettings(friction=Friction(law="none"), node_set="top")
    motion = Motion(tip_position=(0.0, -0.01))
    half = InstrumentContact(Needle(tip="flat", diameter=0.3), motion, model, settings, symmetry_factor=2.0)
    whole = InstrumentContact(Needle(tip="flat", diameter=0.3), motion, model, settings)
    for hook in (half, whole):
        hook.add_forces(model, state, 0.0, model.stable_time_step()[0], np.zeros_like(state.u))
    assert half.outputs()["instrument_force_z_N"] == pytest.approx(2 * whole.outputs()["instrument_force_z_N"])
    with pytest.raises(InputError, match="symmetry_factor"):
        InstrumentContact(Needle(), motion, model, settings, symmetry_factor=0.5)


def test_no_lumped_law_warning_while_the_instrument_rests():
    mesh = square_mesh(n=3, size=0.3)
    model = build_model(mesh, {"b": MATERIAL})
    state = new_state(model)
    settings = ContactSettings(friction=Friction(law="karnopp"), node_set="top")
    resting = InstrumentContact(Needle(tip="flat", diameter=0.3), Motion(tip_position=(0.0, -0.01)), model, settings)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        resting.add_forces(model, state, 0.0, model.stable_time_step()[0], np.zeros_like(state.u))
    assert resting.outputs()["instrument_contact_nodes"] == 2


def test_checkpoint_restores_the_friction_state(tmp_path):
    from corneasim.solver import load_checkpoint, save_checkpoint

    mesh = square_mesh(n=3, size=0.3)
    model = build_model(mesh, {"b": MATERIAL})
    state = new_state(model)
    settings = ContactSettings(friction=Friction(coefficient=0.3), node_set="top")
    motion = needle_insertion(1.0, (0.0, 0.0))
    first = InstrumentContact(Needle(tip="flat", diameter=0.3), motion, model, settings, name="needle")
    first.add_forces(model, state, 0.01, model.stable_time_step()[0], np.zeros_like(state.u))
    save_checkpoint(tmp_path / "c.npz", model, state, [first])
    second = InstrumentContact(Needle(tip="flat", diameter=0.3), motion, model, settings, name="needle")
    load_checkpoint(tmp_path / "c.npz", model, [second])
    assert second.touching.sum() == 2
    assert np.array_equal(second.anchor, first.anchor)
    assert second.largest_penetration == first.largest_penetration == pytest.approx(0.01)
