"""Element deletion: irreversible, logged, creates no energy, releases orphaned nodes.

A bar in uniaxial strain (lateral faces on symmetry planes) is stretched; one element of a
weaker block carries a von Mises failure limit. In uniaxial strain eps the von Mises stress
is 2 mu eps (small strain), so the element fails when eps reaches limit / (2 mu).
"""

import numpy as np

from corneasim.materials import KernelMaterial
from corneasim.materials._kernel_form import FAILURE_VON_MISES
from corneasim.mesh import Mesh
from corneasim.solver import Fixed, Prescribed, SymmetryPlane, build_model, new_state, run
from corneasim.solver._amplitudes import SmoothStep
from test_solver_meshes import box_hex

SHEAR, BULK, DENSITY = 0.4, 2.0, 1.0e-9
STRONG = KernelMaterial(density=DENSITY, c10=SHEAR / 2, d1=2 / BULK)
STRAIN, RAMP = 0.01, 2e-3  # final nominal strain, ramp time s


def weak(limit):
    return KernelMaterial(density=DENSITY, c10=SHEAR / 2, d1=2 / BULK,
                          failure_criterion=FAILURE_VON_MISES, failure_limit=limit)


def bar_model(n, weak_element, limit):
    base = box_hex(n, 1, 1, float(n), 1.0, 1.0)
    block = np.zeros(n, np.int64)
    block[weak_element] = 1
    mesh = Mesh(base.points, base.cells, "hexahedron", block, ["bar", "weak"], False,
                base.node_sets, {}, base.surface_sets)
    conditions = [Fixed("x0", "x"), Prescribed("x1", "x", "displacement", STRAIN * n, SmoothStep(0.0, RAMP))]
    conditions += [SymmetryPlane(name, name[0]) for name in ("y0", "y1", "z0", "z1")]
    return build_model(mesh, {"bar": STRONG, "weak": weak(limit)}, conditions)


def test_deleting_a_loaded_element_creates_no_energy():
    limit = 0.97 * 2 * SHEAR * STRAIN  # fails near the end of the ramp, while loaded
    model = bar_model(6, 2, limit)
    state = new_state(model)
    rows, deletions, fields = [], [], None
    for frame in run(model, state, 3 * RAMP, history_every=5, field_times=[3 * RAMP]):
        deletions += frame.deletions
        if frame.history:
            rows.append(frame.history)
        fields = frame.fields if frame.fields is not None else fields
    assert [(element, block) for _, element, block in deletions] == [(2, "weak")]
    assert list(state.deleted_element) == [2] and state.alive.tolist() == [1, 1, 0, 1, 1, 1]
    time_of_death = deletions[0][0]
    assert 0.5 * RAMP < time_of_death < RAMP
    after = [row for row in rows if row["time_s"] > time_of_death]
    assert after[-1]["deleted_elements"] == 1
    energy_in = max(row["external_work_mJ"] for row in rows)
    assert max(row["kinetic_energy_mJ"] for row in after) < energy_in
    assert max(row["energy_balance_error"] for row in rows[1:]) < 0.01
    # the dead element carries no stress; the support forces relax towards zero
    assert fields["von_mises"][2] == 0.0 and fields["alive"][2] == 0
    assert np.all(fields["von_mises"][[0, 1, 3, 4, 5]] < limit)


def test_orphaned_nodes_are_released_and_fly_free():
    model = bar_model(2, 1, 0.5 * 2 * SHEAR * STRAIN)
    state = new_state(model)
    released_at = None
    for frame in run(model, state, RAMP, history_every=10):
        if frame.deletions and released_at is None:
            released_at = (frame.time, state.v[model.mesh.node_sets["x1"], 0].copy(),
                           state.u[model.mesh.node_sets["x1"], 0].copy())
    assert released_at is not None
    end_nodes = model.mesh.node_sets["x1"]
    assert np.all(state.node_active[end_nodes] == 0)
    assert state.node_active.sum() == model.n_nodes - len(end_nodes)
    # free flight: constant velocity, not the prescribed displacement any more
    t0, v0, u0 = released_at
    np.testing.assert_allclose(state.v[end_nodes, 0], v0, rtol=1e-12)
    np.testing.assert_allclose(state.u[end_nodes, 0], u0 + v0 * (state.time - t0), rtol=1e-9)
    prescribed = STRAIN * 2 * SmoothStep(0.0, RAMP)(state.time)
    assert np.all(np.abs(state.u[end_nodes, 0] - prescribed) > 1e-6)


def test_failure_check_every_k_steps_still_deletes():
    model = bar_model(6, 2, 0.97 * 2 * SHEAR * STRAIN)
    state = new_state(model)
    steps = [frame.step for frame in run(model, state, 3 * RAMP, history_every=1, deletion_every=7)
             if frame.deletions]
    assert list(state.deleted_element) == [2]
    assert len(steps) == 1 and steps[0] % 7 == 0


