"""Elastic supports (solver._support) and the damping that spares a free translation (_integrate).

Truths: the static equilibrium of a body on springs (their force balances the load, so the
supported set's mean displacement is -F / K whatever the body's deformation), the
logarithmic decrement of a damped oscillator, the conservation of momentum under forces
that sum to zero, and the exponential decay of a velocity under mass-proportional damping.
"""

import math

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.materials import KernelMaterial
from corneasim.mesh import Mesh
from corneasim.scenarios._build import build
from corneasim.scenarios._registry import load_scenario
from corneasim.scenarios._format import Support
from corneasim.solver import (
    ElasticSupport, Fixed, Pressure, build_model, critical_dashpot, new_state, preload, run)
from corneasim.solver._amplitudes import SmoothStep

from cli_helpers import corneasim_here
from elements_helpers import grid_hex

STIFF = KernelMaterial(density=1e-9, c10=2.0, c01=0.0, d1=0.05)
"""A block much stiffer than its supports: its own modes are far above the support's."""


def block(n=2, side=1.0):
    """A cube of n^3 hexahedra, side ``side`` mm, bottom at z = 0: node sets ``bottom`` and
    ``all``, surface ``top``."""
    points, cells = grid_hex(n, side)
    top = [(e, 1) for e, cell in enumerate(cells) if points[cell, 2].min() == side * (n - 1) / n]
    mesh = Mesh(points, cells.astype(np.int64), "hexahedron", np.zeros(len(cells), np.int64), ["block"], False,
                {"bottom": np.flatnonzero(points[:, 2] == 0.0), "all": np.arange(points.shape[0])}, {},
                {"top": np.array(top, np.int64)})
    assert np.all(points[mesh.face_nodes("top"), 2] == side)  # local face 1 is the top
    return mesh


def supported_block(stiffness, pressures=(), fixed="xy"):
    """The block with its bottom held in x and y and on springs of total ``stiffness`` in z."""
    mesh = block()
    model = build_model(mesh, {"block": STIFF}, [Fixed("bottom", fixed)], list(pressures))
    support = ElasticSupport("bottom", mesh.node_sets["bottom"], 2, "z", stiffness)
    return model, support


def test_the_springs_carry_the_load_and_the_set_moves_by_force_over_stiffness():
    """Pressure p on the 1 mm^2 top: at rest the springs push back with F = p A, and their
    mean displacement is -F / K exactly, however the block deforms (p is small enough that
    the follower pressure's area grows by less than 1e-5)."""
    p, stiffness = 1e-4, 0.5
    model, support = supported_block(stiffness, [Pressure("top", p, SmoothStep(0.0, 2e-3))])
    state = new_state(model)
    omega = math.sqrt(stiffness / model.mass.sum())
    for _ in preload(model, state, 0.02, 2.0 * omega, hooks=[support]):
        pass
    assert support.force == pytest.approx(p * 1.0, rel=1e-4)
    assert support.mean_displacement == pytest.approx(-p / stiffness, rel=1e-4)
    assert support.outputs() == {"support_bottom_z_N": support.force, "support_bottom_z_mm": support.mean_displacement}


@pytest.mark.parametrize("ratio", [0.05, 0.2])
def test_the_dashpot_gives_the_translation_its_damping_ratio(ratio):
    """A block thrown upwards bounces on its springs; c = 2 zeta sqrt(K M) makes successive
    maxima of its mean displacement fall by exp(-2 pi zeta / sqrt(1 - zeta^2))."""
    stiffness = 0.05
    model, _ = supported_block(stiffness)
    support = ElasticSupport("bottom", model.mesh.node_sets["bottom"], 2, "z", stiffness,
                             critical_dashpot(ratio, stiffness, model.mass.sum()))
    state = new_state(model)
    state.v[:, 2] = 1.0
    period = 2 * math.pi * math.sqrt(model.mass.sum() / stiffness)
    w = [(frame.time, support.mean_displacement)
         for frame in run(model, state, 2.5 * period, hooks=[support], history_every=1)]
    times, values = np.array(w).T
    peaks = [i for i in range(1, len(values) - 1) if values[i - 1] < values[i] >= values[i + 1] and values[i] > 0]
    assert len(peaks) >= 2
    expected = math.exp(-2 * math.pi * ratio / math.sqrt(1 - ratio**2))
    assert values[peaks[1]] / values[peaks[0]] == pytest.approx(expected, rel=0.03)
    assert times[peaks[1]] - times[peaks[0]] == pytest.approx(period / math.sqrt(1 - ratio**2), rel=0.02)


def test_a_held_set_keeps_its_equilibrium_at_the_release_and_then_takes_load_over_stiffness():
    """Held while a first load settles (by springs k_h,i = 0.05 m_i / dt^2, more than 20 times
    stiffer than K here), then released onto K: nothing moves at the release (the springs keep
    the force they carried), and a second, equal load then moves the set by -F / K."""
    p, stiffness, release = 1e-4, 0.2, 0.01
    first = Pressure("top", p, SmoothStep(0.0, 2e-3))
    second = Pressure("top", p, SmoothStep(0.012, 0.014))
    model, support = supported_block(stiffness, [first, second])
    support.hold(release, model.mass, model.stable_time_step()[0])
    state = new_state(model)
    omega = math.sqrt(stiffness / model.mass.sum())
    rows = [(frame.time, support.force, support.mean_displacement)
            for frame in preload(model, state, 0.03, 4.0 * omega, hooks=[support], history_every=1)]
    times, forces, displacements = np.array(rows).T
    before = np.searchsorted(times, release) - 1
    held = displacements[before]
    assert support.hold_stiffness.sum() > 20 * stiffness
    assert -0.05 * p / stiffness < held < 0.0
    assert forces[before] == pytest.approx(p, rel=1e-3)
    after = np.searchsorted(times, 0.0115)  # released, before the second load
    np.testing.assert_allclose(displacements[before:after], held, atol=1e-6 * p / stiffness)
    assert forces[-1] == pytest.approx(2 * p, rel=1e-4)
    assert displacements[-1] - held == pytest.approx(-p / stiffness, rel=1e-3)


def test_the_damping_spares_a_free_translation_and_slows_it_otherwise():
    """A free block moving at 1 mm/s in z: mass-proportional damping alpha on v - v_mean keeps
    its momentum (the damping forces sum to zero) and slows nothing; on v it slows the block
    as exp(-alpha t)."""
    mesh = block()
    model = build_model(mesh, {"block": STIFF}, [Fixed("bottom", "xy")], free_translation=[2])
    alpha, end = 200.0, 5e-3
    free = new_state(model)
    free.v[:, 2] = 1.0
    for _ in run(model, free, end, damping=alpha):
        pass
    np.testing.assert_allclose(free.v[:, 2], 1.0, rtol=1e-12)
    held = new_state(model)
    held.v[:, 2] = 1.0
    for _ in run(model, held, end, damping=alpha, free_translation=False):
        pass
    np.testing.assert_allclose(held.v[:, 2], math.exp(-alpha * end), rtol=2e-3)


def needle_with(support: Support):
    """The coarse needle scenario with one more support (its build raises what is wrong)."""
    scenario, _, base = load_scenario("needle", ["mesh.preset=coarse"])
    return build(scenario.model_copy(update={"supports": [support]}), base)


@pytest.mark.parametrize("support, message", [
    (Support(node_set="lower_hemisphere", component="z", stiffness=0.1),
     "supports\\[0\\]: component 'z' of node set 'lower_hemisphere' is also held by a constraint"),
    (Support(node_set="nowhere", component="z", stiffness=0.1), "supports\\[0\\]: the mesh has no node set 'nowhere'"),
    (Support(node_set="axis", component="x", stiffness=0.1), "supports\\[0\\].component: component 'x'"),
    (Support(node_set="anterior_surface", component="z", stiffness=1e12), "supports\\[0\\].stiffness: .* too stiff"),
])
def test_a_wrong_support_names_itself(support, message):
    with pytest.raises(InputError, match=message):
        needle_with(support)


def test_the_cli_rejects_a_support_on_a_fixed_component_in_one_line(tmp_path):
    text = corneasim_here("show", "needle").stdout
    scenario = tmp_path / "s.toml"
    scenario.write_text(text.replace("[[pressures]]", '[[supports]]\nnode_set = "lower_hemisphere"\n'
                                     'component = "z"\nstiffness = 0.1\n\n[[pressures]]', 1))
    done = corneasim_here("run", str(scenario), "--set", "mesh.preset=coarse", "--out", str(tmp_path / "out"))
    assert done.returncode == 2
    assert done.stderr.strip().count("\n") == 0 and "supports[0]" in done.stderr


def test_a_dashpot_too_strong_for_the_step_names_its_damping_ratio():
    """c_i dt / m_i must stay below 0.1: a dashpot 20 times the bound is refused."""
    from corneasim.solver import check_support_stability

    model, _ = supported_block(0.05)
    nodes = model.mesh.node_sets["bottom"]
    dt = model.stable_time_step()[0]
    dashpot = 20 * 0.1 * model.mass[nodes].min() / dt * nodes.size
    support = ElasticSupport("bottom", nodes, 2, "z", 0.05, dashpot)
    with pytest.raises(InputError, match=r"supports\[0\]\.damping_ratio: the dashpot is too strong"):
        check_support_stability(support, model.mass, dt, "supports[0]")
    check_support_stability(ElasticSupport("bottom", nodes, 2, "z", 0.05, dashpot / 40), model.mass, dt,
                            "supports[0]")


def test_a_deletion_step_damps_the_same_relative_velocity():
    """The step in which an element dies recomputes the acceleration without its forces
    (``drop_dead_element_forces``); with the damping on v - v_mean, a block translating
    rigidly at the mean velocity still feels no damping there (and on v it does: -alpha v)."""
    from corneasim.solver._deletion import drop_dead_element_forces

    mesh = block()
    model = build_model(mesh, {"block": STIFF}, [Fixed("bottom", "xy")])
    alpha = 200.0
    state = new_state(model)
    state.v[:, 2] = 1.0
    state.alive[0] = 0
    drop_dead_element_forces(model, state, alpha, np.array([0.0, 0.0, 1.0]))
    np.testing.assert_allclose(state.a, 0.0, atol=1e-9)
    drop_dead_element_forces(model, state, alpha)
    np.testing.assert_allclose(state.a[:, 2], -alpha, rtol=1e-12)
