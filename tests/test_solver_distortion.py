"""Distortion control: corner Jacobian ratios, erosion of a crushed element, the step after a deletion.

Independent truths: a homogeneous deformation F gives every corner the ratio det F (in-plane
det for the axisymmetric quad); a unit square with one corner pulled across the diagonal has
corner ratios worked out by hand; a hexahedron whose every dof is prescribed is compressed
homogeneously, so its corner ratio is the stretch lambda(t) of the prescribed
motion and it must die at the first distortion check with lambda < limit; the stable step after a
deletion is the smallest over the live elements.
"""

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.materials import KernelMaterial
from corneasim.materials._kernel_form import FAILURE_VON_MISES
from corneasim.mesh import Mesh
from corneasim.scenarios._registry import load_scenario
from corneasim.solver import (Fixed, Prescribed, SimulationError, SymmetryPlane, build_model, new_state,
                              run)
from corneasim.solver import elements as element_kernels
from corneasim.solver._deletion import (DISTORTION_EVERY, corner_jacobian_ratio, corner_jacobian_ratios,
                                       delete_distorted_elements, reference_corner_inverse)
from corneasim.solver._amplitudes import Constant, Linear
from test_solver_meshes import box_hex, box_quad

SOLID = KernelMaterial(density=1.0e-9, c10=0.2, d1=1.0)


def ratios(mesh, u):
    inverse = reference_corner_inverse(mesh.points, mesh.cells)
    return np.array([corner_jacobian_ratio(mesh.points, u, mesh.cells, inverse, e)
                     for e in range(mesh.n_elements)])


def test_homogeneous_deformation_gives_det_F_at_every_corner():
    rng = np.random.default_rng(3)
    hexes = box_hex(2, 2, 1, 2.0, 1.5, 1.0)
    hexes.points[:] += 0.1 * rng.standard_normal(hexes.points.shape)  # distorted reference
    F = np.eye(3) + 0.3 * rng.standard_normal((3, 3))
    F *= np.sign(np.linalg.det(F))
    np.testing.assert_allclose(ratios(hexes, hexes.points @ (F - np.eye(3)).T), np.linalg.det(F), rtol=1e-12)
    quads = box_quad(3, 2, 1.0, 2.0, 0.0, 1.0)
    quads.points[:] += 0.05 * rng.standard_normal(quads.points.shape)
    F2 = np.array([[0.7, 0.2], [-0.1, 1.3]])
    u = quads.points @ (F2 - np.eye(2)).T
    np.testing.assert_allclose(ratios(quads, u), np.linalg.det(F2), rtol=1e-12)
    # the per-step quad path of the erosion pass agrees: det F2 = 0.93
    inverse = reference_corner_inverse(quads.points, quads.cells)
    for limit, expected in ((0.92, 0), (0.94, quads.n_elements)):
        alive = np.ones(quads.n_elements, np.uint8)
        deleted = np.empty(quads.n_elements, np.int64)
        assert delete_distorted_elements(quads.points, u, quads.cells, inverse, alive, limit, deleted, 0) == expected


def test_the_ratios_of_a_whole_mesh_are_det_F_for_live_elements_and_1_for_dead_ones():
    rng = np.random.default_rng(5)
    for mesh, F in ((box_hex(3, 2, 2, 2.0, 1.5, 1.0), np.diag([1.2, 0.9, 0.8]) + 0.1 * rng.standard_normal((3, 3))),
                    (box_quad(4, 3, 1.0, 2.0, 0.0, 1.0), np.array([[0.8, 0.3], [-0.2, 1.1]]))):
        mesh.points[:] += 0.02 * rng.standard_normal(mesh.points.shape)
        u = mesh.points @ (F - np.eye(F.shape[0])).T
        alive = np.ones(mesh.n_elements, np.uint8)
        alive[1::3] = 0
        eta = np.empty(mesh.n_elements)
        corner_jacobian_ratios(mesh.points, u, mesh.cells, reference_corner_inverse(mesh.points, mesh.cells),
                               alive, eta)
        np.testing.assert_allclose(eta[alive == 1], np.linalg.det(F), rtol=1e-12)
        assert np.all(eta[alive == 0] == 1.0)


def test_a_folded_quad_is_seen_by_the_corner_ratio_but_not_by_the_centre_jacobian():
    # unit square far from the axis; corner 2 (1, 1) pulled to (0.2, 0.2) across the diagonal:
    # corner ratios by hand: corner 0: 1, corners 1 and 3: 0.2, corner 2: -0.6
    quad = box_quad(1, 1, 10.0, 11.0, 0.0, 1.0)
    corner = quad.cells[0, 2]
    u = np.zeros_like(quad.points)
    u[corner] = np.array([10.2, 0.2]) - quad.points[corner]
    assert ratios(quad, u)[0] == pytest.approx(-0.6, rel=1e-12)
    alive, deleted = np.ones(1, np.uint8), np.empty(1, np.int64)
    inverse = reference_corner_inverse(quad.points, quad.cells)
    assert delete_distorted_elements(quad.points, u, quad.cells, inverse, alive, 0.0, deleted, 0) == 1
    model = build_model(quad, {"solid": SOLID})
    assert element_kernels.element_jacobians(model.elements, u)[0] > 0.0


def crushed_cube(limit, final_stretch, ramp):
    """Two unit hexahedra stacked in z, lateral faces held: the mid plane is pushed down linearly.

    Every dof of the lower element is prescribed (it is compressed homogeneously, stretch
    lambda(t) = 1 + (final - 1) t / ramp); the upper one rides on the mid plane.
    """
    base = box_hex(1, 1, 2, 1.0, 1.0, 2.0)
    node_sets = dict(base.node_sets, middle=np.flatnonzero(np.isclose(base.points[:, 2], 1.0)))
    mesh = Mesh(base.points, base.cells, "hexahedron", base.element_block, base.block_names, False,
                node_sets, {}, base.surface_sets)
    conditions = [SymmetryPlane(name, name[0]) for name in ("x0", "x1", "y0", "y1")]
    conditions += [Fixed("z0", "z"),
                   Prescribed("middle", "z", "displacement", final_stretch - 1.0, Linear(1.0 / ramp))]
    return build_model(mesh, {"solid": SOLID}, conditions, distortion_limit=limit)


def test_a_crushed_element_is_eroded_before_it_inverts_and_the_energy_balance_holds():
    limit, final_stretch, ramp = 0.2, -0.2, 1e-3
    model = crushed_cube(limit, final_stretch, ramp)
    state = new_state(model)
    rows, deletions = [], []
    for frame in run(model, state, ramp, history_every=1):
        deletions += frame.deletions
        if frame.history:
            rows.append(frame.history)
    # lambda(t) = 1 + (final - 1) t / ramp reaches the limit at t*; the erosion comes at the first distortion check past it
    t_star = ramp * (1.0 - limit) / (1.0 - final_stretch)
    assert [element for _, element, _ in deletions] == [0]
    time_of_death = deletions[0][0]
    assert t_star <= time_of_death < t_star + 1.01 * DISTORTION_EVERY * state.time_step
    assert 1.0 + (final_stretch - 1.0) * time_of_death / ramp > 0.0  # eroded before J = lambda reached 0
    # the energy balance closes through the deletion (the velocity jump of the prescribed
    # motion at t = 0 gives a start-up error relative to the tiny energies of the first steps)
    established = [row for row in rows if row["time_s"] > 0.2 * ramp]
    assert max(row["energy_balance_error"] for row in established) < 0.01
    assert any(row["time_s"] > time_of_death for row in established)


def test_without_erosion_the_same_crush_stops_the_run_as_an_inverted_element():
    model = crushed_cube(0.0, -0.2, 1e-3)
    with pytest.raises(SimulationError, match="inverted element"):
        for _ in run(model, new_state(model), 1e-3, history_every=10, check_every=10):
            pass


def test_a_crushed_sliver_stops_the_run_instead_of_shrinking_the_step_without_end():
    # crushed to lambda = 1e-6 (J > 0 throughout, no erosion): the element's stable step falls
    # with lambda, and the run stops once it is below MINIMUM_STEP_RATIO of the reference mesh's
    from corneasim.solver._run import MINIMUM_STEP_RATIO

    model = crushed_cube(0.0, 1e-6, 1e-3)
    model.time_step_every = 1
    state = new_state(model)
    with pytest.raises(SimulationError, match="stable time step fell") as caught:
        for _ in run(model, state, 1e-3, history_every=100):
            pass
    assert caught.value.element == 0
    J = element_kernels.element_jacobians(model.elements, state.u)[0]
    assert 0.0 < J < 10 * MINIMUM_STEP_RATIO  # a sliver, not an inverted element


def test_the_stable_step_is_recomputed_after_a_deletion():
    # a bar of four hexahedra along x whose thin third element (0.1 mm) sets the stable step and
    # fails in tension; the step is recomputed every 10**6 steps only, yet after the deletion
    # it must follow the live elements (ten times larger)
    base = box_hex(4, 1, 1, 3.1, 1.0, 1.0, x_nodes=[0.0, 1.0, 2.0, 2.1, 3.1])
    block = np.array([0, 0, 1, 0], np.int64)
    mesh = Mesh(base.points, base.cells, "hexahedron", block, ["bar", "weak"], False,
                base.node_sets, {}, base.surface_sets)
    weak = KernelMaterial(density=1.0e-9, c10=0.2, d1=1.0, failure_criterion=FAILURE_VON_MISES,
                          failure_limit=0.01)
    conditions = [Fixed("x0", "x"), Prescribed("x1", "x", "velocity", 200.0, Constant(1.0))]
    conditions += [SymmetryPlane(name, name[0]) for name in ("y0", "y1", "z0", "z1")]
    model = build_model(mesh, {"bar": SOLID, "weak": weak}, conditions, time_step_every=10**6)
    state = new_state(model)
    steps_before = []
    for frame in run(model, state, 3e-4, history_every=1):
        if state.deleted_element.size == 0:
            steps_before.append(state.time_step)
    assert state.deleted_element.tolist() == [2]
    live = np.flatnonzero(state.alive)
    expected = model.safety_factor * element_kernels.stable_time_steps(model.elements, state.u)[live].min()
    assert state.next_time_step == pytest.approx(expected, rel=1e-2)  # the last step is cut to land on the end
    assert state.next_time_step > 5.0 * max(steps_before[1:])


@pytest.mark.parametrize("value", [-0.1, 1.0])
def test_distortion_limit_out_of_range_is_input_error(value):
    with pytest.raises(InputError, match="distortion_limit"):
        crushed_cube(value, 0.5, 1e-3)
    with pytest.raises(InputError, match="distortion_limit"):
        load_scenario("needle", [f"solver.distortion_limit={value}", "mesh.preset=coarse"])
