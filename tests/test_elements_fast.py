"""The fast (SIMD, threaded) kernels agree with the reference kernels to round-off."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from corneasim.materials import KernelMaterial, kernel_table
from corneasim.materials._kernel_form import P_FAILURE_CRITERION
from corneasim.solver import elements as el
from corneasim.solver.elements import _schedule

from elements_helpers import RHO, grid_hex, grid_quad

TABLE = kernel_table([
    KernelMaterial(density=RHO, c10=0.05, c20=0.3, c30=0.1, d1=0.05,
                   prony_g=(0.3, 0.2, 0.1, 0.15), prony_tau=(1e-4, 1e-3, 1e-2, 1.0),
                   failure_criterion=1, failure_limit=0.4),
    KernelMaterial(density=2 * RHO, c10=0.04, c01=0.03, d1=0.1, prony_g=(0.4, 0.2),
                   prony_tau=(2e-4, 5e-3), failure_criterion=1, failure_limit=0.3),
    KernelMaterial(density=RHO, c10=0.3, d1=0.02, failure_criterion=0, failure_limit=0.2),
    KernelMaterial(density=RHO, c10=0.1, c01=0.01, d1=0.3),
])


def run(es, u, alive, steps=3, dt=2e-4):
    n, dim = es.points.shape
    history = el.new_history(es)
    out = []
    for step in range(steps):
        f = np.zeros((n, dim))
        ratio = np.zeros(es.n_elements)
        rates = np.zeros(3)
        el.eval_internal_forces(es, u * (step + 1) / steps, dt, alive, history, f, ratio, rates)
        out.append((f, ratio, rates))
    return out, history


@pytest.mark.parametrize("cell_type", ["quad", "hexahedron"])
@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.parametrize("layout", ["mixed", "banded"])
def test_fast_equals_reference(cell_type, threads, layout):
    if threads > numba.config.NUMBA_NUM_THREADS:
        pytest.skip("one thread only")
    rng = np.random.default_rng(7)
    if cell_type == "quad":
        points, cells = grid_quad(14, 11, jitter=0.3)
    else:
        points, cells = grid_hex(5, jitter=0.25)
    size = points.max()
    h = size / (14 if cell_type == "quad" else 5)
    n_e = len(cells)
    if layout == "mixed":  # blocks with several materials
        materials = rng.integers(0, len(TABLE), n_e)
    else:  # runs of blocks with one material each, changing between consecutive blocks
        materials = (np.arange(n_e) // 40) % len(TABLE)
    alive = (rng.uniform(size=n_e) > 0.1).astype(np.uint8)
    u = 0.08 * h * rng.uniform(-1, 1, points.shape)
    u[:, -1] += 0.1 * points[:, -1]
    if cell_type == "quad":
        u[points[:, 0] == 0.0, 0] = 0.0
    results = {}
    previous = numba.get_num_threads()
    numba.set_num_threads(threads)
    try:
        for kernel in ("reference", "fast"):
            es = el.prepare(points, cells, cell_type, materials, TABLE, kernel=kernel)
            results[kernel] = run(es, u, alive)
    finally:
        numba.set_num_threads(previous)
    (ref, h_ref), (fast, h_fast) = results["reference"], results["fast"]
    J = el.element_jacobians(el.prepare(points, cells, cell_type, materials, TABLE), u)
    assert 0.7 < J.min() and J.max() < 1.4
    for (f0, r0, e0), (f1, r1, e1) in zip(ref, fast):
        assert np.abs(f1 - f0).max() < 1e-12 * np.abs(f0).max()
        assert np.abs(r1 - r0).max() < 1e-10 * np.abs(r0).max()
        assert np.allclose(e1, e0, rtol=1e-11, atol=1e-13 * np.abs(e0).max())
        assert np.all(r1[alive == 0] == 0.0) and np.all(r0 > 0) == np.all(r1 > 0)
    assert np.abs(h_fast - h_ref).max() < 1e-12 * np.abs(h_ref).max()
    assert {TABLE[m, P_FAILURE_CRITERION] for m in materials[alive == 1]} >= {0.0, 1.0}


@pytest.mark.parametrize("cell_type", ["quad", "hexahedron"])
def test_fast_forces_are_the_same_on_any_thread_count(cell_type, monkeypatch):
    """Each node sums its elements' contributions in one order, whichever thread computed
    them: forces, failure ratios, energies and history agree bitwise on 1 and 2 threads
    (with one buffer per thread, the nodes shared by two threads were summed in another
    order and differed at round-off). The mesh is below the size from which the kernels use
    a second thread, so that limit is lifted here."""
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("one thread only")
    monkeypatch.setitem(_schedule.PARALLEL_MIN_ELEMENTS, cell_type, 0)
    rng = np.random.default_rng(11)
    points, cells = grid_quad(40, 30, jitter=0.3) if cell_type == "quad" else grid_hex(8, jitter=0.25)
    order = rng.permutation(len(cells))  # elements far from node order: parts share many nodes
    cells = cells[order]
    materials = rng.integers(0, len(TABLE), len(cells))
    alive = (rng.uniform(size=len(cells)) > 0.05).astype(np.uint8)
    h = points.max() / (40 if cell_type == "quad" else 8)
    u = 0.08 * h * rng.uniform(-1, 1, points.shape)
    if cell_type == "quad":
        u[points[:, 0] == 0.0, 0] = 0.0
    results = []
    previous = numba.get_num_threads()
    try:
        for threads in (1, 2):
            numba.set_num_threads(threads)
            es = el.prepare(points, cells, cell_type, materials, TABLE, kernel="fast")
            results.append(run(es, u, alive))
            assert es.fast["scratch"].shape[0] == threads  # the kernels ran on this many threads
    finally:
        numba.set_num_threads(previous)
    (one, h_one), (two, h_two) = results
    for (f1, r1, e1), (f2, r2, e2) in zip(one, two):
        assert np.array_equal(f1, f2) and np.array_equal(r1, r2) and np.array_equal(e1, e2)
    assert np.array_equal(h_one, h_two)
    assert np.abs(one[-1][0]).max() > 0.0


@pytest.mark.parametrize("cell_type", ["quad", "hexahedron"])
def test_small_element_sets_run_their_kernels_on_one_thread(cell_type, monkeypatch):
    """Below PARALLEL_MIN_ELEMENTS of its kind an element set's kernels (forces, stable steps,
    centre Jacobians) run on one thread while Numba has two, give what one thread gives, and
    leave Numba's thread count as it was; at the limit the force kernels run on two."""
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("one thread only")
    points, cells = grid_quad(8, 6, jitter=0.3) if cell_type == "quad" else grid_hex(3, jitter=0.25)
    u = 0.01 * np.random.default_rng(3).uniform(-1, 1, points.shape)
    if cell_type == "quad":
        u[points[:, 0] == 0.0, 0] = 0.0
    alive = np.ones(len(cells), np.uint8)
    materials = np.zeros(len(cells), np.int64)
    previous = numba.get_num_threads()
    rows, results, steps, jacobians = [], [], [], []
    try:
        for threads, limit in ((1, len(cells) + 1), (2, len(cells) + 1), (2, len(cells))):
            numba.set_num_threads(threads)
            monkeypatch.setitem(_schedule.PARALLEL_MIN_ELEMENTS, cell_type, limit)
            es = el.prepare(points, cells, cell_type, materials, TABLE, kernel="fast")
            results.append(run(es, u, alive))
            rows.append(es.fast["scratch"].shape[0])
            steps.append(el.stable_time_steps(es, u))
            jacobians.append(el.element_jacobians(es, u))
            assert numba.get_num_threads() == threads
    finally:
        numba.set_num_threads(previous)
    assert rows == [1, 1, 2]
    (one, _), (small, _), (two, _) = results
    for (f1, _, _), (f2, _, _), (f3, _, _) in zip(one, small, two):
        assert np.array_equal(f1, f2) and np.array_equal(f1, f3)
    for values in (steps, jacobians):
        assert np.array_equal(values[0], values[1]) and np.array_equal(values[0], values[2])


def test_centre_jacobian_of_a_homogeneous_hexahedral_deformation_is_det_F():
    points, cells = grid_hex(3, jitter=0.2)
    F = np.array([[1.1, 0.2, -0.05], [0.03, 0.9, 0.1], [-0.1, 0.04, 1.05]])
    u = points @ (F - np.eye(3)).T
    es = el.prepare(points, cells, "hexahedron", np.zeros(len(cells), np.int64), TABLE)
    np.testing.assert_allclose(el.element_jacobians(es, u), np.linalg.det(F), rtol=1e-13)


@pytest.mark.parametrize("cell_type", ["quad", "hexahedron"])
def test_parallel_centre_jacobians_match_the_reference_loop(cell_type, monkeypatch):
    """The parallel kernel of the time loop's inversion check gives the reference loop's det F
    (general gradient routine, one element at a time) on a distorted mesh, folded elements
    (J < 0) included, on 1 and 2 threads (the small mesh's one-thread limit lifted)."""
    from corneasim.solver.elements import _reference
    monkeypatch.setitem(_schedule.PARALLEL_MIN_ELEMENTS, cell_type, 0)
    rng = np.random.default_rng(5)
    points, cells = grid_quad(30, 20, jitter=0.3) if cell_type == "quad" else grid_hex(6, jitter=0.25)
    h = points.max() / (30 if cell_type == "quad" else 6)
    u = (0.6 if cell_type == "quad" else 1.5) * h * rng.uniform(-1, 1, points.shape)
    if cell_type == "quad":
        u[points[:, 0] == 0.0, 0] = 0.0
    es = el.prepare(points, cells, cell_type, np.zeros(len(cells), np.int64), TABLE)
    expected = np.empty(len(cells))
    _reference.jacobians_reference(es.points, es.cells, es.b, es.hoop, u, expected)
    assert expected.min() < 0.0 < expected.max()
    previous = numba.get_num_threads()
    try:
        for threads in (1, min(2, numba.config.NUMBA_NUM_THREADS)):
            numba.set_num_threads(threads)
            np.testing.assert_allclose(el.element_jacobians(es, u), expected, rtol=1e-12, atol=1e-14)
    finally:
        numba.set_num_threads(previous)
