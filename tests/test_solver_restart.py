"""Checkpoint/restart reproduces an uninterrupted run; broken runs stop with one clear line.

Restart: run A goes straight to the end; run B saves checkpoints, is abandoned between two
checkpoints (as if killed), and a fresh model resumes from the last checkpoint file. The
history rows of B (before the checkpoint) plus the resumed rows must equal A's.
"""

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.materials import KernelMaterial
from corneasim.materials._kernel_form import FAILURE_VON_MISES
from corneasim.mesh import Mesh
from corneasim.solver import (
    Fixed, Prescribed, Pressure, SimulationError, SymmetryPlane, build_model, load_checkpoint,
    new_state, run, save_checkpoint)
from corneasim.solver._amplitudes import SmoothStep
from corneasim.solver._run import update_time_step
from test_solver_meshes import box_hex

VISCOUS = KernelMaterial(density=1e-9, c10=0.2, d1=1.0, prony_g=(0.3,), prony_tau=(1e-3,))
WEAK = KernelMaterial(density=1e-9, c10=0.2, d1=1.0, prony_g=(0.3,), prony_tau=(1e-3,),
                      failure_criterion=FAILURE_VON_MISES, failure_limit=0.006)
END = 2e-3


def loaded_model():
    """A viscoelastic bar pulled at one end, pressed on top, with one element that fails."""
    base = box_hex(4, 1, 2, 4.0, 1.0, 2.0)
    block = np.zeros(base.n_elements, np.int64)
    block[5] = 1
    mesh = Mesh(base.points, base.cells, "hexahedron", block, ["bar", "weak"], False,
                base.node_sets, {}, base.surface_sets)
    conditions = [Fixed("x0", "xyz"), Prescribed("x1", "x", "velocity", 20.0)]
    conditions += [SymmetryPlane(name, name[0]) for name in ("y0", "y1")]
    # safety factor 0.5: see the hexahedron stable-step note in docs/solver.md
    return build_model(mesh, {"bar": VISCOUS, "weak": WEAK}, conditions,
                       [Pressure("z1", 1e-3, SmoothStep(0.0, 1e-3))], safety_factor=0.5,
                       time_step_every=7)


def test_resumed_run_reproduces_the_uninterrupted_history(tmp_path):
    model = loaded_model()
    state = new_state(model)
    straight = [frame.history for frame in run(model, state, END, history_every=3) if frame.history]
    assert straight[-1]["deleted_elements"] == 1  # the deletion is part of what must replay

    checkpoint = tmp_path / "run" / "checkpoint.npz"
    state = new_state(model)
    before, saved_step = [], None
    for frame in run(model, state, END, history_every=3, checkpoint_every=40):
        if frame.history:
            before.append(frame.history)
        if frame.checkpoint_due:
            save_checkpoint(checkpoint, model, frame.state)
            saved_step = frame.step
        if frame.step >= 130:  # killed between checkpoints 120 and 160
            break
    assert saved_step == 120
    assert [p.name for p in checkpoint.parent.iterdir()] == ["checkpoint.npz"]  # no temporary files

    fresh_model = loaded_model()
    resumed_state = load_checkpoint(checkpoint, fresh_model)
    assert resumed_state.step == 120
    resumed = [frame.history for frame in run(fresh_model, resumed_state, END, history_every=3)
               if frame.history]
    combined = [row for row in before if row["step"] <= saved_step] + resumed
    assert [row["step"] for row in combined] == [row["step"] for row in straight]
    for a, b in zip(combined, straight):
        assert a.keys() == b.keys()
        np.testing.assert_allclose([a[k] for k in a], [b[k] for k in b], rtol=1e-12, atol=1e-300)


def test_checkpoint_of_another_mesh_or_garbage_is_an_input_error(tmp_path):
    model = loaded_model()
    path = tmp_path / "c.npz"
    save_checkpoint(path, model, new_state(model))
    other = build_model(box_hex(2, 1, 1, 2.0, 1.0, 1.0), {"solid": VISCOUS})
    with pytest.raises(InputError, match="different mesh"):
        load_checkpoint(path, other)
    (tmp_path / "bad.npz").write_bytes(b"not a checkpoint")
    with pytest.raises(InputError, match="bad.npz: not a readable checkpoint"):
        load_checkpoint(tmp_path / "bad.npz", model)
    with pytest.raises(InputError, match="checkpoint not found"):
        load_checkpoint(tmp_path / "missing.npz", model)


class NaNAfter:
    """A hook that puts NaN into the external force of node 0 after a given time."""

    name = "nan_injector"

    def __init__(self, time):
        self.time = time

    def add_forces(self, model, state, time, time_step, f_ext):
        if time > self.time:
            f_ext[0, 0] = np.nan

    def outputs(self):
        return {"injector_armed": 1.0}


def collect_until_failure(model, state, hooks=(), **options):
    rows = []
    with pytest.raises(SimulationError) as error:
        for frame in run(model, state, 1.0, hooks=hooks, **options):
            if frame.history:
                rows.append(frame.history)
    return rows, error.value


def test_nan_stops_the_run_naming_node_element_and_block():
    model = build_model(box_hex(2, 1, 1, 2.0, 1.0, 1.0), {"solid": VISCOUS}, [Fixed("x0", "xyz")])
    dt = model.stable_time_step()[0]
    rows, error = collect_until_failure(model, new_state(model), [NaNAfter(20.5 * dt)],
                                        history_every=5, check_every=10)
    message = str(error)
    assert "\n" not in message
    assert "non-finite" in message and "node 0" in message and "element 0 (block 'solid')" in message
    assert error.element == 0 and error.block == "solid"
    assert [row["step"] for row in rows] == [0, 5, 10, 15, 20]  # history up to the last good state
    assert rows[-1]["injector_armed"] == 1.0


def test_nan_met_by_the_stable_step_update_names_the_element():
    """A NaN reaching the geometry between two checks stops the run at the next stable-step
    update, naming an element of the node (the umbrella trephine's failure at 62 s said only
    "no stable time step")."""
    model = build_model(box_hex(2, 1, 1, 2.0, 1.0, 1.0), {"solid": VISCOUS}, [Fixed("x0", "xyz")])
    state = new_state(model)
    node = int(np.argmax(model.mesh.points[:, 0]))  # on the free end
    state.u[node, 2] = np.nan
    with pytest.raises(SimulationError) as error:
        update_time_step(model, state)
    message = str(error.value)
    assert "\n" not in message and "non-finite geometry" in message
    assert error.value.element in np.flatnonzero((model.mesh.cells == node).any(axis=1))
    assert f"element {error.value.element} (block 'solid')" in message


def test_inverted_element_stops_the_run():
    model = build_model(box_hex(1, 1, 1, 1.0, 1.0, 1.0), {"solid": VISCOUS},
                        [Fixed("z0", "xyz"), Prescribed("z1", "z", "velocity", -2e3)])
    rows, error = collect_until_failure(model, new_state(model), history_every=10, check_every=1)
    assert "inverted element" in str(error) and "element 0 (block 'solid')" in str(error)
    assert 0.4e-3 < error.time < 0.6e-3  # the top face passes the bottom at 1 mm / 2000 mm/s
    assert rows


def test_unstable_step_stops_with_runaway_energy_or_non_finite_values():
    model = build_model(box_hex(2, 1, 1, 2.0, 1.0, 1.0), {"solid": VISCOUS}, [Fixed("x0", "xyz")])
    model.safety_factor = 3.0  # deliberately beyond the stability limit
    velocity = np.random.default_rng(2).standard_normal(model.mesh.points.shape)
    rows, error = collect_until_failure(model, new_state(model, velocity=velocity), check_every=1)
    assert str(error).startswith("simulation stopped at t = ")
    assert "block 'solid'" in str(error)
    assert rows and rows[0]["step"] == 0


def test_frames_carry_fields_at_the_requested_times():
    model = loaded_model()
    state = new_state(model)
    fields = {frame.time: frame.fields for frame in run(model, state, 1e-3, history_every=1000,
                                                        field_times=[0.0, 5e-4, 1e-3]) if frame.fields}
    times = sorted(fields)
    assert len(times) == 3 and times[0] == 0.0 and np.isclose(times[-1], 1e-3)
    assert 5e-4 <= times[1] < 5e-4 + 2 * model.stable_time_step()[0]
    frame = fields[times[-1]]
    assert frame["displacement"].shape == (model.n_nodes, 3)
    assert frame["cauchy_stress"].shape == (model.n_elements, 6)
    assert frame["von_mises"].shape == (model.n_elements,) and np.all(frame["von_mises"] >= 0)
    assert set(frame["block"]) == {0, 1}


class CountingHook:
    """A hook with its own state: counts its calls and pushes node 0 with a constant force."""

    name = "counter"

    def __init__(self):
        self.calls = np.zeros(1)

    def add_forces(self, model, state, time, time_step, f_ext):
        self.calls[0] += 1
        f_ext[0, 0] += 1e-4

    def outputs(self):
        return {"counter_calls": float(self.calls[0])}

    def checkpoint(self):
        return {"calls": self.calls.copy()}

    def restore(self, arrays):
        self.calls = arrays["calls"].copy()


def test_hook_state_and_work_survive_a_checkpoint(tmp_path):
    model = build_model(box_hex(2, 1, 1, 2.0, 1.0, 1.0), {"solid": VISCOUS}, [Fixed("x1", "xyz")],
                        safety_factor=0.5)
    hook = CountingHook()
    state = new_state(model)
    for frame in run(model, state, 1.0, hooks=[hook], history_every=25):
        if frame.step == 50:
            save_checkpoint(tmp_path / "c.npz", model, state, [hook])
            break
    assert frame.history["counter_calls"] == 50.0
    assert frame.history["external_work_mJ"] > 0  # the hook's force does work
    restored_hook = CountingHook()
    resumed = load_checkpoint(tmp_path / "c.npz", model, [restored_hook])
    assert restored_hook.calls[0] == 50.0
    frame = next(run(model, resumed, 1.0, hooks=[restored_hook], history_every=25))
    assert frame.step == 75 and frame.history["counter_calls"] == 75.0
    assert frame.history["energy_balance_error"] < 1e-6
