"""Point stiffness of a spherical shell, bare and pressurised: the solid model against shell theory.

A shallow spherical shell (mid-surface radius R, thickness t, Young's modulus E, Poisson's
ratio nu, bending stiffness D = E t^3 / (12 (1 - nu^2))) loaded normally by q(r) near its pole
deflects as a plate on an elastic foundation of modulus E t / R^2 (Reissner 1946, J. Math.
Phys. 25:80 and 279; the membrane's stress function eliminated). A uniform internal pressure p
adds the membrane tension T = p R / 2 (Vella, Ajdari, Vaziri and Boudaoud 2012, Phys. Rev. Lett.
109:144302, the linearised equation of their pressurised shell):

    D lap^2 w - T lap w + (E t / R^2) w = q.

Its Hankel transform gives the deflection at the pole under a total force P,

    w(0) = (1 / (2 pi)) integral_0^inf P(xi) xi dxi / (D xi^4 + T xi^2 + E t / R^2),

P(xi) = 2 pi integral q J0(xi r) r dr (P(xi) = P for a point force). For a point force the
integral is closed: with k_0 = 8 sqrt(D E t) / R = 4 E t^2 / (R sqrt(3 (1 - nu^2))) (Reissner's
point stiffness) and tau = T / (2 sqrt(D E t / R^2)) = p R^2 sqrt(12 (1 - nu^2)) / (4 E t^2),

    k = P / w(0) = k_0 (pi / 2) sqrt(1 - tau^2) / arccos(tau)     (tau < 1; arccosh and tau^2 - 1 above).

The model: a spherical cap (mid-surface radius R, thickness t, half-angle theta_e) meshed with
axisymmetric quads (``through`` across the thickness, ``along`` along the meridian), clamped at
its edge; a uniform pressure q on the outer surface within the arc length ``a`` of the pole
(a patch of radius a << the bending length l = (D R^2 / (E t))^(1/4)), an optional internal
pressure p on the inner surface, both ramped by the quasi-static recipe (docs/quasi-static.md)
with the physical hourglass stiffness; the mid-surface pole's u_z is read at the end. The
stiffness is P / (w(p, q) - w(p, 0)), two runs at the same internal pressure. Theory takes the
patch's own P(xi) (a uniform disc load, P(xi) = 2 P J1(xi a) / (xi a)), so the finite patch is
not an error of the model.

Run: ``python validation/shell_point_stiffness.py [coarse|medium|fine]`` (default fine); it prints, for tau = 0 and
the pressurised case, the model's stiffness against shell theory's (patch and point).
"""

from __future__ import annotations

import math
import sys
import tempfile
from pathlib import Path

import numpy as np
import tomli_w
from scipy import integrate, special

import corneasim
from corneasim.mesh import Mesh, write_mesh

SHELL = dict(radius=20.0, thickness=0.2, youngs_modulus=1.0, poisson_ratio=0.3, half_angle=0.45, patch=0.1)
"""Mid-surface radius R (mm), thickness t (mm), E (MPa), nu, cap half-angle (rad), patch radius a (mm)."""
SIZES = {"coarse": dict(through=2, along=180), "medium": dict(through=4, along=180),
         "fine": dict(through=4, along=360)}
"""Elements through the thickness and along the meridian (pole to clamped edge)."""
PATCH_PRESSURE = 1.0e-4
"""q, MPa: the patch load (a pole deflection of about 1e-3 t)."""


def bending_stiffness(thickness: float, youngs_modulus: float, poisson_ratio: float) -> float:
    """D = E t^3 / (12 (1 - nu^2)), N mm."""
    return youngs_modulus * thickness ** 3 / (12.0 * (1.0 - poisson_ratio ** 2))


def pressure_parameter(internal_pressure: float, radius: float, thickness: float, youngs_modulus: float,
                       poisson_ratio: float) -> float:
    """tau = p R^2 sqrt(12 (1 - nu^2)) / (4 E t^2) (Vella et al. 2012), dimensionless."""
    return internal_pressure * radius ** 2 * math.sqrt(12.0 * (1.0 - poisson_ratio ** 2)) / (
        4.0 * youngs_modulus * thickness ** 2)


def point_stiffness(radius: float, thickness: float, youngs_modulus: float, poisson_ratio: float,
                    internal_pressure: float = 0.0) -> float:
    """Closed-form point stiffness k = k_0 (pi/2) sqrt(1 - tau^2) / arccos(tau) (module notes), N/mm."""
    k0 = 4.0 * youngs_modulus * thickness ** 2 / (radius * math.sqrt(3.0 * (1.0 - poisson_ratio ** 2)))
    tau = pressure_parameter(internal_pressure, radius, thickness, youngs_modulus, poisson_ratio)
    if tau == 0.0:
        return k0
    if abs(tau - 1.0) < 1e-9:
        return k0 * math.pi / 2.0
    if tau < 1.0:
        return k0 * 0.5 * math.pi * math.sqrt(1.0 - tau ** 2) / math.acos(tau)
    return k0 * 0.5 * math.pi * math.sqrt(tau ** 2 - 1.0) / math.acosh(tau)


def patch_stiffness(radius: float, thickness: float, youngs_modulus: float, poisson_ratio: float,
                    internal_pressure: float = 0.0, patch: float = 0.0, shear_modulus: float = math.inf) -> float:
    """P / w(0) of a uniform load on a disc of radius ``patch`` (mm) by the Hankel integral, N/mm.

    A finite transverse ``shear_modulus`` G (MPa) adds the shear deflection of a Reissner-Mindlin
    shell, shear stiffness S = (5/6) G t: D xi^4 becomes D xi^4 / (1 + D xi^2 / S), so that at
    scales below sqrt(D / S) the shell bends like a membrane of tension S (module notes).
    """
    D = bending_stiffness(thickness, youngs_modulus, poisson_ratio)
    T = 0.5 * internal_pressure * radius
    foundation = youngs_modulus * thickness / radius ** 2
    shear = 5.0 / 6.0 * shear_modulus * thickness
    scale = (D / foundation) ** 0.25

    def integrand(xi: float) -> float:
        x = xi * patch
        load = 1.0 if x < 1e-8 else 2.0 * special.j1(x) / x
        return load * xi / (D * xi ** 4 / (1.0 + D * xi ** 2 / shear) + T * xi ** 2 + foundation)

    if patch > 0.0:  # half-periods of J1 out to 400 / a; the tail beyond is below 1e-5 of the integral
        pieces = np.union1d(np.linspace(0.0, 40.0 / scale, 81), np.arange(0.0, 400.0 / patch, math.pi / patch))
    elif math.isinf(shear_modulus):
        pieces = np.concatenate([np.linspace(0.0, 40.0 / scale, 81), [np.inf]])
    else:
        raise ValueError("a point force on a shell with a finite shear modulus deflects without bound: give a patch")
    compliance = sum(integrate.quad(integrand, lo, hi, limit=200)[0] for lo, hi in zip(pieces[:-1], pieces[1:]))
    return 2.0 * math.pi / compliance


def cap_mesh(radius: float, thickness: float, half_angle: float, patch: float, through: int, along: int) -> Mesh:
    """Quads of the cap between R - t/2 and R + t/2, pole to ``half_angle`` (rad), with its sets.

    Node sets ``edge`` (theta = half_angle, clamped) and ``pole_mid`` (the mid-surface pole,
    ``through`` even); surface sets ``outer_patch`` (outer faces within the arc length ``patch``
    of the pole, mm) and ``inner`` (the inner surface).
    """
    rho = np.linspace(radius - 0.5 * thickness, radius + 0.5 * thickness, through + 1)
    latitude = np.linspace(0.5 * np.pi - half_angle, 0.5 * np.pi, along + 1)  # index 0 at the edge
    tt, pp = np.meshgrid(latitude, rho, indexing="ij")
    points = np.column_stack([(pp * np.cos(tt)).ravel(), (pp * np.sin(tt)).ravel()])
    points[np.abs(points[:, 0]) < 1e-12, 0] = 0.0
    index = np.arange(points.shape[0]).reshape(along + 1, through + 1)
    cells = np.column_stack([index[:-1, :-1].ravel(), index[:-1, 1:].ravel(),
                             index[1:, 1:].ravel(), index[1:, :-1].ravel()]).astype(np.int64)
    layer = np.tile(np.arange(through), along)
    row = np.repeat(np.arange(along), through)
    edge_side_arc = (0.5 * np.pi - latitude[row]) * radius  # mid-surface arc length from the pole
    outer = np.flatnonzero((layer == through - 1) & (edge_side_arc <= patch + 1e-9))
    inner = np.flatnonzero(layer == 0)
    return Mesh(points, cells, "quad", np.zeros(len(cells), dtype=np.int64), ["shell"], axisymmetric=True,
                node_sets={"edge": index[0].copy(), "pole_mid": index[-1, through // 2:through // 2 + 1].copy()},
                surface_sets={"outer_patch": np.column_stack([outer, np.full(outer.size, 1)]).astype(np.int64),
                              "inner": np.column_stack([inner, np.full(inner.size, 3)]).astype(np.int64)})


PHASES = {"pressure": (0.0, 0.3), "patch": (0.45, 0.75), "end": 0.9}
"""s: the internal pressure's smooth step, then the patch load's, then the hold to the end
(without an internal pressure the patch's step starts at 0). A hold of 0.15 s is 10 lowest
periods of the mass-scaled cap: the damping takes out all but 1e-5 of what a ramp leaves."""
RAMP_PERIODS = 10.0
"""Lowest periods per ramp (docs/quasi-static.md); the deflections are read after the holds."""


def scenario(mesh_file: Path, material: str, internal_pressure: float, patch_pressure: float) -> dict:
    """The cap's scenario (module notes) as a TOML table; pressures in MPa.

    The internal pressure rises over ``PHASES["pressure"]``, the patch load over
    ``PHASES["patch"]``: the pole's deflection at the start of the patch's rise is the
    pressurised state's, its change to the end the patch's.
    """
    shift = 0.0 if internal_pressure > 0.0 else PHASES["patch"][0]

    def step(phase: str) -> dict:
        t0, t1 = PHASES[phase]
        return {"type": "smooth-step", "t0": t0 - shift, "t1": t1 - shift}

    pressures = [{"surface": "outer_patch", "pressure": patch_pressure, "amplitude": step("patch")}]
    if internal_pressure > 0.0:
        pressures.append({"surface": "inner", "pressure": internal_pressure, "amplitude": step("pressure")})
    return {"name": "shell-point", "description": "Spherical cap under a pole patch load",
            "mesh": {"file": str(mesh_file), "axisymmetric": True},
            "materials": {"shell": {"material": material}},
            "constraints": [{"node_set": "edge", "fixed": "rz"}],
            "pressures": pressures,
            "history": [{"name": "pole", "node_set": "pole_mid", "quantity": "displacement", "components": ["z"]}],
            "solver": {"quasi_static": True, "end_time": PHASES["end"] - shift, "history_every": 50,
                       "field_count": 1, "checkpoint_every": 10 ** 7, "hourglass_control": "physical",
                       "ramp_periods": RAMP_PERIODS}}


def write_material(path: Path, youngs_modulus: float, poisson_ratio: float) -> Path:
    """A linear-elastic material file (the compressible neo-Hooke law at small strain)."""
    path.write_text(tomli_w.dumps({"name": "shell", "description": "Elastic shell", "source": "check value",
                                   "density": 1.0e-9,
                                   "hyperelastic": {"model": "linear-elastic", "youngs_modulus": youngs_modulus,
                                                    "poisson_ratio": poisson_ratio}}))
    return path


def patch_deflection(work: Path, mesh_file: Path, material: Path, internal_pressure: float,
                     patch_pressure: float) -> float:
    """The mid-surface pole's deflection (mm, downward positive) that the patch load adds."""
    path = work / "cap.toml"
    path.write_text(tomli_w.dumps(scenario(mesh_file, str(material), internal_pressure, patch_pressure)))
    result = corneasim.run_scenario(str(path), out_dir=work / "cap", overwrite=True)
    history = result.history
    if not history["kinetic_energy_mJ"][-1] < 1e-6 * history["internal_energy_mJ"][-1]:
        raise RuntimeError("the cap is still moving at the end of the hold")
    time, pole = history["time_s"], history["pole_z_mm"]
    start = PHASES["patch"][0] if internal_pressure > 0.0 else 0.0
    before = pole[np.searchsorted(time, start + 1e-12, side="right") - 1]
    return float(before - pole[-1])


def measure(size: str = "coarse", tau: float = 0.0, work_dir: str | Path | None = None, **shell) -> dict:
    """Run the cap at ``size`` with the internal pressure of ``tau``; model and theory stiffness, N/mm."""
    geometry = {**SHELL, **shell}
    R, t, E, nu, a = (geometry[key] for key in ("radius", "thickness", "youngs_modulus", "poisson_ratio", "patch"))
    p = tau * 4.0 * E * t ** 2 / (R ** 2 * math.sqrt(12.0 * (1.0 - nu ** 2)))
    work = Path(work_dir) if work_dir is not None else Path(tempfile.mkdtemp(prefix="shell-point-"))
    work.mkdir(parents=True, exist_ok=True)
    mesh = cap_mesh(R, t, geometry["half_angle"], a, **SIZES[size])
    mesh_file = write_mesh(mesh, work / "cap.inp")
    material = write_material(work / "shell.toml", E, nu)
    loaded = mesh.surface_sets["outer_patch"][:, 0]
    r_patch = float(mesh.points[mesh.cells[loaded].ravel(), 0].max())
    force = PATCH_PRESSURE * math.pi * r_patch ** 2
    w = patch_deflection(work, mesh_file, material, p, PATCH_PRESSURE)
    model = force / w
    return {"tau": tau, "internal_pressure_MPa": p, "force_N": force, "deflection_mm": w, "model_N_per_mm": model,
            "shell_theory_N_per_mm": patch_stiffness(R, t, E, nu, p, r_patch, 0.5 * E / (1.0 + nu)),
            "thin_theory_N_per_mm": patch_stiffness(R, t, E, nu, p, r_patch),
            "point_theory_N_per_mm": point_stiffness(R, t, E, nu, p), "elements": mesh.n_elements}


def main(size: str = "fine") -> list[dict]:
    """Print the bare and the pressurised (tau = 1) cap's stiffness against shell theory."""
    rows = []
    for tau in (0.0, 1.0):
        row = measure(size, tau)
        error = row["model_N_per_mm"] / row["shell_theory_N_per_mm"] - 1.0
        print(f"{size} ({row['elements']} quads) tau = {tau:g} (p = {row['internal_pressure_MPa']:.3g} MPa): "
              f"model {row['model_N_per_mm']:.5g} N/mm; shell theory {row['shell_theory_N_per_mm']:.5g} "
              f"(without transverse shear {row['thin_theory_N_per_mm']:.5g}, point force "
              f"{row['point_theory_N_per_mm']:.5g}); model / shell theory - 1 = {100 * error:+.2f}%")
        rows.append(row)
    return rows


if __name__ == "__main__":
    main(*sys.argv[1:2])
