"""Variable mass scaling keeps the target step while a block is crushed; momentum and energy balance hold."""

import numpy as np
import pytest

from corneasim.materials import KernelMaterial
from corneasim.mesh import Mesh
from corneasim.solver import Fixed, Prescribed, build_model, new_state, run
from corneasim.solver._mass_scaling import transfer_momentum
from corneasim.solver._amplitudes import Constant

RUBBER = KernelMaterial(density=1.0e-9, c10=0.1, d1=0.4)


def ring_block(n=4):
    """An axisymmetric n x n block, r in [1, 2] mm, z in [0, 1] mm."""
    r, z = np.meshgrid(np.linspace(1.0, 2.0, n + 1), np.linspace(0.0, 1.0, n + 1), indexing="ij")
    points = np.column_stack([r.ravel(), z.ravel()])
    index = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    cells = np.array([[index[i, j], index[i + 1, j], index[i + 1, j + 1], index[i, j + 1]]
                      for i in range(n) for j in range(n)])
    return Mesh(points, cells, "quad", np.zeros(len(cells), np.int64), ["rubber"], axisymmetric=True,
                node_sets={"bottom": np.flatnonzero(points[:, 1] == 0.0), "top": np.flatnonzero(points[:, 1] == 1.0)})


def test_transfer_momentum_conserves_momentum_and_books_the_lost_energy():
    v = np.array([2.0, -1.0, 3.0])
    old, new = np.array([1.0, 2.0, 1.0]), np.array([4.0, 2.0, 3.0])
    fixed = np.array([0, 0, 1], np.uint8)
    kinetic_before = 0.5 * np.sum(old * v * v)
    lost = transfer_momentum(v, old, new, fixed)
    assert v[0] * new[0] == pytest.approx(2.0 * old[0]) and v[1] == -1.0 and v[2] == 3.0
    kinetic_after = 0.5 * (new[0] * v[0] ** 2 + new[1] * v[1] ** 2 + old[2] * v[2] ** 2)
    assert kinetic_before - kinetic_after == pytest.approx(lost)


@pytest.mark.parametrize("variable", [False, True])
def test_crushing_keeps_the_target_step_only_with_variable_scaling(variable):
    mesh = ring_block()
    conditions = [Fixed("bottom", "z"), Prescribed("top", "z", "velocity", -400.0, Constant(1.0))]
    probe = build_model(mesh, {"rubber": RUBBER}, conditions)
    target = 1.2 * probe.stable_time_step()[0] / probe.safety_factor
    model = build_model(mesh, {"rubber": RUBBER}, conditions, target_time_step=target,
                        variable_mass_scaling=variable, time_step_every=10)
    state = new_state(model)
    steps = []
    for frame in run(model, state, end_time=1.25e-3, history_every=10):
        if frame.history and not frame.done:
            steps.append(frame.history["time_step_s"])
            balance = frame.history["energy_balance_error"]
    compressed = 1.0 - (mesh.points[:, 1] + state.u[:, 1]).max()
    assert compressed == pytest.approx(0.5, abs=0.01)
    if variable:
        assert min(steps[1:]) >= 0.999 * target
        initial_scaling = (target / (probe.stable_time_step()[0] / probe.safety_factor)) ** 2 - 1
        assert state.added_mass_fraction > initial_scaling
        assert balance < 1e-2
    else:
        assert min(steps) < 0.8 * target


def test_restart_restores_the_masses_added_during_the_run(tmp_path):
    from corneasim.solver import load_checkpoint, save_checkpoint

    mesh = ring_block()
    conditions = [Fixed("bottom", "z"), Prescribed("top", "z", "velocity", -400.0, Constant(1.0))]

    def model():
        probe = build_model(mesh, {"rubber": RUBBER}, conditions)
        target = 1.2 * probe.stable_time_step()[0] / probe.safety_factor
        return build_model(mesh, {"rubber": RUBBER}, conditions, target_time_step=target,
                           variable_mass_scaling=True, time_step_every=10)

    whole = model()
    state = new_state(whole)
    for _ in run(whole, state, end_time=1.25e-3, history_every=10):
        pass
    first = model()
    part = new_state(first)
    for frame in run(first, part, end_time=1.25e-3, history_every=10, checkpoint_every=200):
        if frame.checkpoint_due and frame.step == 400:
            save_checkpoint(tmp_path / "c.npz", first, frame.state)
            break
    assert part.added_mass_fraction > 0.5
    second = model()
    resumed = load_checkpoint(tmp_path / "c.npz", second)
    assert resumed.added_mass_fraction == part.added_mass_fraction
    for _ in run(second, resumed, end_time=1.25e-3, history_every=10):
        pass
    np.testing.assert_allclose(resumed.u, state.u, rtol=1e-12, atol=1e-15)
