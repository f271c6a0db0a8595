"""Relaxation test of a confined material column, checked against the Prony closed form.

Confined compression (no lateral strain) by eps(t) = eps_0 min(t / t_r, 1) of a solid whose
bulk response is elastic (K) and whose shear relaxes as mu(t) = mu_0 (g_inf + sum g_i
exp(-t / tau_i)) has the axial stress, by Boltzmann superposition (small strain),

    sigma_zz(t) = -[K eps(t) + 4/3 mu_0 eps_0 / t_r R(t)],
    R(t) = g_inf t + sum g_i tau_i (1 - exp(-t / tau_i)),                          t <= t_r,
    R(t) = g_inf t_r + sum g_i tau_i (exp(-(t - t_r) / tau_i) - exp(-t / tau_i)),    t > t_r,

(the deviatoric strain is 2 eps / 3 along the axis). The model: two axisymmetric quads in a
column of radius 1 mm and height 2 mm, every node held radially, the bottom fixed, the top
pressed by eps_0 = 1e-3 (``relaxation.toml``, material ``relaxing.toml``: mu_0 = K = 1 MPa,
the published Prony series), by the quasi-static recipe. Explicit dynamics would take 10^9
steps to 10^4 s at the column's own stable step; the recipe's mass scaling (from the lowest
period and the 10 s ramp) takes about 2 x 10^5.

Run: ``python examples/relaxation/relaxation.py [default|tiny]``: default to 10^4 s, tiny a
1 s ramp held to 40 s; prints the largest error of sigma_zz against the closed form once
loaded (measured: see docs/quasi-static.md).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import corneasim
from corneasim.materials import load_material
from corneasim.mesh import Mesh

HERE = Path(__file__).resolve().parent
SCENARIO = HERE / "relaxation.toml"
STRAIN = 1.0e-3
"""eps_0: the scenario's 2e-3 mm over the 2 mm column."""
SIZES = {"default": dict(ramp=10.0, end=1.0e4), "tiny": dict(ramp=1.0, end=40.0)}
"""Ramp and end time per size, s."""


def column_mesh() -> Mesh:
    """Two 1 x 1 mm axisymmetric quads stacked on the axis; node sets all, bottom, top; block column."""
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [1.0, 2.0], [0.0, 2.0]])
    cells = np.array([[0, 1, 2, 3], [3, 2, 4, 5]], dtype=np.int64)
    return Mesh(points, cells, "quad", np.zeros(2, dtype=np.int64), ["column"], axisymmetric=True,
                node_sets={"all": np.arange(6), "bottom": np.array([0, 1]), "top": np.array([4, 5])})


def closed_form(t, ramp: float, material=None) -> np.ndarray:
    """sigma_zz(t), MPa (module notes), at the strain ``STRAIN`` reached over ``ramp`` (s)."""
    material = material or load_material(HERE / "relaxing.toml", warn=False)
    weights, taus = material.viscoelastic.weights(), material.viscoelastic.relaxation_times
    g_inf = 1.0 - float(np.sum(weights))
    t = np.asarray(t, dtype=float)
    during = g_inf * t + sum(g * tau * (1 - np.exp(-t / tau)) for g, tau in zip(weights, taus))
    after = g_inf * ramp + sum(g * tau * (np.exp(-(t - ramp) / tau) - np.exp(-t / tau)) for g, tau in zip(weights, taus))
    shear = 4.0 / 3.0 * material.initial_shear_modulus * STRAIN / ramp * np.where(t <= ramp, during, after)
    return -(material.bulk_modulus * STRAIN * np.minimum(t / ramp, 1.0) + shear)


def main(size: str = "default", work_dir: str | Path | None = None) -> dict:
    """Run the column; print and return the largest relative error of sigma_zz once loaded."""
    if size not in SIZES:
        raise SystemExit(f"size must be one of {', '.join(SIZES)}")
    ramp, end = SIZES[size]["ramp"], SIZES[size]["end"]
    work = Path(work_dir) if work_dir is not None else HERE
    mesh = corneasim.mesh.write_mesh(column_mesh(), work / "column.inp")
    result = corneasim.run_scenario(SCENARIO, [
        f"mesh.file={mesh.resolve()}", f"solver.end_time={end}", f"constraints.top.amplitude.times=[0.0, {ramp}, {end}]"])
    time, stress = result.history["time_s"], result.history["column_zz_MPa"]
    exact = closed_form(time, ramp)
    loaded = time >= 0.1 * ramp
    error = float(np.max(np.abs(stress[loaded] / exact[loaded] - 1.0)))
    steps = result.summary["run"]["steps"]
    print(f"sigma_zz at t = {time[-1]:.4g} s: {stress[-1]:.6g} MPa, closed form {exact[-1]:.6g} MPa; "
          f"largest error once loaded {100 * error:.3f}%; {steps} steps, max KE/IE "
          f"{result.summary['quasi_static']['max_kinetic_to_internal']:.2g}")
    return {"error": error, "result": result}


if __name__ == "__main__":
    main(*sys.argv[1:2])
