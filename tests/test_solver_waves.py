"""Elastic waves: the period of a bar's fundamental mode gives the dilatational wave speed
sqrt((lambda + 2 mu) / rho); the energy balance closes in this elastic problem."""

import numpy as np
import pytest

from corneasim.materials import KernelMaterial
from corneasim.solver import Fixed, SymmetryPlane, build_model, new_state, run
from corneasim.solver import elements as element_kernels
from test_solver_meshes import box_hex, box_quad

YOUNGS, POISSON, DENSITY = 1.0, 0.3, 1.0e-9  # MPa, -, tonne/mm^3
SHEAR = YOUNGS / (2 * (1 + POISSON))
BULK = YOUNGS / (3 * (1 - 2 * POISSON))
MATERIAL = KernelMaterial(density=DENSITY, c10=SHEAR / 2, d1=2 / BULK)
WAVE_SPEED = np.sqrt((BULK + 4 / 3 * SHEAR) / DENSITY)  # = sqrt((lambda + 2 mu) / rho), mm/s


def fundamental_mode_run(mesh, conditions, length, tip_nodes, axis):
    """Bar fixed at x = 0, free at x = L, in uniaxial strain, started with the velocity of its
    first mode V sin(pi x / 2L); returns times, tip displacements and history rows."""
    model = build_model(mesh, {"solid": MATERIAL}, conditions, bulk_viscosity_linear=0.0,
                        bulk_viscosity_quadratic=0.0)
    x = mesh.points[:, axis]
    velocity = np.zeros_like(mesh.points)
    amplitude = 1e-4 * WAVE_SPEED  # strain about 1e-4
    velocity[:, axis] = amplitude * np.sin(np.pi * x / (2 * length))
    state = new_state(model, velocity=velocity)
    period = 4 * length / WAVE_SPEED
    times, tips, rows = [], [], []
    for frame in run(model, state, 0.75 * period, history_every=1, check_every=50):
        times.append(frame.time)
        tips.append(state.u[tip_nodes, axis].mean())
        rows.append(frame.history)
    return np.array(times), np.array(tips), rows, period


def half_period_from_zero_crossing(times, tips):
    """First downward zero crossing of the tip displacement (linear interpolation), s."""
    k = np.flatnonzero((tips[:-1] > 0) & (tips[1:] <= 0))[0]
    return times[k] + (times[k + 1] - times[k]) * tips[k] / (tips[k] - tips[k + 1])


def test_hexahedron_bar_wave_speed_and_energy_balance():
    length = 40.0
    mesh = box_hex(40, 1, 1, length, 1.0, 1.0)
    conditions = [Fixed("x0", "x")] + [SymmetryPlane(s, a) for s, a in
                                       (("y0", "y"), ("y1", "y"), ("z0", "z"), ("z1", "z"))]
    times, tips, rows, period = fundamental_mode_run(mesh, conditions, length,
                                                     mesh.node_sets["x1"], 0)
    measured_speed = 2 * length / half_period_from_zero_crossing(times, tips)
    assert abs(measured_speed / WAVE_SPEED - 1) < 0.02
    errors = [row["energy_balance_error"] for row in rows[1:]]
    assert max(errors) < 0.01
    internal = max(row["internal_energy_mJ"] for row in rows)
    assert internal > 0.9 * rows[0]["kinetic_energy_mJ"]  # the energy really went through strain
    assert max(abs(row["hourglass_energy_mJ"]) for row in rows) < 0.05 * internal


def test_axisymmetric_column_wave_speed():
    """Axial waves in a column r <= 1 with the mantle held radially: uniaxial strain in z."""
    length = 40.0
    mesh = box_quad(2, 40, 0.0, 1.0, 0.0, length)
    times, tips, rows, period = fundamental_mode_run(
        mesh, [Fixed("z0", "z"), Fixed("r1", "r")], length, mesh.node_sets["z1"], 1)
    measured_speed = 2 * length / half_period_from_zero_crossing(times, tips)
    assert abs(measured_speed / WAVE_SPEED - 1) < 0.02
    assert max(row["energy_balance_error"] for row in rows[1:]) < 0.01


@pytest.mark.parametrize("safety", [0.9, 0.5])
def test_time_step_is_safety_times_smallest_element_step(safety):
    mesh = box_hex(10, 1, 1, 10.0, 1.0, 1.0, x_nodes=np.r_[0.0, 0.4, np.arange(1.0, 10.0)])
    model = build_model(mesh, {"solid": MATERIAL}, safety_factor=safety)
    dt, element = model.stable_time_step()
    element_dt = element_kernels.stable_time_steps(model.elements, np.zeros_like(mesh.points))
    assert element == 0 and np.isclose(dt, safety * element_dt.min(), rtol=1e-12)
    assert dt < safety * element_dt[1]
