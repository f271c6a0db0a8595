"""solver.time_scaling: a compressed run reproduces the physical viscoelastic response in physical time.

A confined block (F = diag(lambda, 1, 1)) of a neo-Hooke + Prony material is stretched with a
smooth step over RAMP and held. In *physical* time the ramp lasts 0.05 s and the relaxation
times are 0.2 s and 1 s; the scenario runs with time_scaling = 100 (so the solver sees a
0.5 ms ramp and 2 ms / 10 ms relaxation times, 1/100 of the steps). The reported reaction,
in physical time, must follow the closed form of the physical problem:

    sigma_xx(t) = K (J - 1) + lambda S_xx(t),
    S_xx(t) = g_inf S0(t) + sum_i g_i int_0^t exp(-(t - s)/tau_i) dS0/ds ds,
    S0(lambda) = (2 C10 / lambda^2) lambda^(-2/3) (2/3)(lambda^2 - 1)

(Simo & Hughes 1998 sec. 10.3; kernel form in materials/_kernel_form.py), evaluated by
quadrature of the prescribed physical history.
"""

import numpy as np
import pytest

from corneasim import run_scenario
from corneasim.mesh import write_mesh
from corneasim.scenarios._registry import load_scenario
from corneasim.scenarios._time_scaling import scaled_material, scaled_scenario
from corneasim.materials import KernelMaterial
from test_solver_meshes import box_hex

C10, BULK = 0.2, 2.0                      # MPa
MODULI, LONG_TERM = (0.3, 0.2), 0.5       # MPa: weights g = 0.3, 0.2
TAU = (0.2, 1.0)                          # s, physical
STRETCH, RAMP, END = 1.05, 0.05, 2.0      # -, s, s (physical)
SCALE = 100.0

MATERIAL = f"""
name = "block"
density = 1.0e-9
[hyperelastic]
model = "neo-hooke"
c10 = {C10}
d1 = {2 / BULK}
[viscoelastic]
prony_moduli = [{MODULI[0]}, {MODULI[1]}]
long_term_modulus = {LONG_TERM}
relaxation_times = [{TAU[0]}, {TAU[1]}]
"""

SCENARIO = f"""
name = "relaxation"
[mesh]
file = "block.inp"
[materials]
solid = {{ material = "block.toml" }}
[[constraints]]
node_set = "x0"
fixed = "x"
[[constraints]]
node_set = "y0"
fixed = "y"
[[constraints]]
node_set = "y1"
fixed = "y"
[[constraints]]
node_set = "z0"
fixed = "z"
[[constraints]]
node_set = "z1"
fixed = "z"
[[constraints]]
node_set = "x1"
prescribed = "displacement"
component = "x"
value = {2.0 * (STRETCH - 1)}
amplitude = {{ type = "smooth-step", t0 = 0.0, t1 = {RAMP} }}
[[reactions]]
name = "pull"
node_set = "x1"
component = "x"
[solver]
end_time = {END}
time_scaling = {SCALE}
history_every = 20
field_count = 0
"""


def closed_form_stress(t):
    """sigma_xx (MPa) at physical time t >= RAMP (quintic smooth-step stretch up to RAMP)."""
    s = np.linspace(0.0, RAMP, 100001)
    xi = s / RAMP
    stretch = 1 + (STRETCH - 1) * xi ** 3 * (10 - 15 * xi + 6 * xi ** 2)
    S0 = 2 * C10 / stretch ** 2 * stretch ** (-2 / 3) * (2 / 3) * (stretch ** 2 - 1)
    dS0 = np.gradient(S0, s)
    g = np.array(MODULI) / (sum(MODULI) + LONG_TERM)
    S = (1 - g.sum()) * S0[-1]
    for weight, tau in zip(g, TAU):
        integrand = np.exp(-(t - s) / tau) * dS0
        S += weight * np.sum(0.5 * (integrand[1:] + integrand[:-1]) * np.diff(s))
    return BULK * (STRETCH - 1) + STRETCH * S


@pytest.fixture(scope="module")
def history(tmp_path_factory):
    folder = tmp_path_factory.mktemp("scaling")
    write_mesh(box_hex(2, 1, 1, 2.0, 1.0, 1.0), folder / "block.inp")
    (folder / "block.toml").write_text(MATERIAL)
    (folder / "relaxation.toml").write_text(SCENARIO)
    return run_scenario(str(folder / "relaxation.toml")).history


def test_scaled_run_follows_the_physical_relaxation_in_physical_time(history):
    time, force = history["time_s"], history["pull_N"]
    assert time[-1] == pytest.approx(END, rel=1e-9)
    held = time >= 2 * RAMP
    assert held.sum() > 20
    exact = np.array([closed_form_stress(t) for t in time[held]])
    np.testing.assert_allclose(force[held], exact, rtol=0.01)
    # the isochoric part relaxed visibly over the physical 2 s (tau 0.2 s and 1 s)
    volumetric = BULK * (STRETCH - 1)
    assert (force[-1] - volumetric) / (closed_form_stress(2 * RAMP) - volumetric) < 0.7


def test_scaled_scenario_compresses_rates_durations_and_relaxation_times():
    scenario, _, _ = load_scenario("trephine", ["solver.time_scaling=10"])
    scaled = scaled_scenario(scenario)
    motion = scaled.instrument.motion
    assert motion.insertion.rate == pytest.approx(0.020 * 10)        # mm/s: 20 um/s, 10x faster
    assert motion.rotation.circular_frequency == pytest.approx(33.5 * 2 * 3.141592653589793 / 60 * 10)
    assert scaled.solver.end_time == pytest.approx(100.0 / 10)
    assert scaled.preload.duration == pytest.approx(scenario.preload.duration / 10)
    assert scaled.preload.damping == pytest.approx(scenario.preload.damping * 10)
    damped = scaled_scenario(load_scenario("trephine", ["solver.time_scaling=10", "solver.damping=3"])[0])
    assert damped.solver.damping == pytest.approx(30.0)                # 1/s: a rate, 10x
    assert scaled.pressures[0].amplitude.t1 == pytest.approx(scenario.pressures[0].amplitude.t1 / 10)
    assert scenario.solver.end_time == 100.0                          # the original is untouched
    material = KernelMaterial(density=1e-9, c10=0.1, prony_g=(0.3,), prony_tau=(8.83,))
    assert scaled_material(material, 10.0).prony_tau == pytest.approx((0.883,))
