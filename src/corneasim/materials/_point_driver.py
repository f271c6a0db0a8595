"""Material-point driver: a homogeneous test integrated in time at one point, without dynamics.

For checking a material (and fitting one) without a mesh: the deformation gradient of a
homogeneous test follows a prescribed strain history, and the free stress components are
held at zero by solving for the lateral stretch at every step:

* ``uniaxial``: F = diag(lambda, lambda_t, lambda_t), sigma_22 = sigma_33 = 0;
  strain lambda - 1 (engineering), nominal stress P_11 = J sigma_11 / lambda.
* ``equibiaxial``: F = diag(lambda, lambda, lambda_t), sigma_33 = 0; strain lambda - 1,
  nominal stress P_11 = P_22.
* ``shear``: simple shear F = I + gamma e_1 (x) e_2 (volume-preserving), strain gamma,
  stress sigma_12 (= P_12).

The stress is the law the element kernels integrate, for any registered law
(``materials/_laws.py``): :func:`~corneasim.materials.viscoelastic_stress` of the material's
kernel record, which evaluates the one material law of ``materials/_law.py`` with its Prony
step (exact for an isochoric stress linear in time within a step, so a held strain relaxes
exactly with any step; Simo & Hughes 1998, *Computational Inelasticity*, sec. 10.3).

How a Prony series is read: its moduli E_i, E_inf give the normalised weights
g_i = E_i / (sum_j E_j + E_inf) (needle paper eq. 2) of the *instantaneous* response, which
is the hyperelastic law's. Their absolute size is not used: a series whose sum differs from
the law's small-strain Young's or shear modulus scales nothing. :func:`prony_reading` says so
in one line (the driver prints it), with the numbers.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from corneasim.errors import InputError
from corneasim.materials._spec import MaterialSpec
from corneasim.materials._viscoelastic import new_history, viscoelastic_stress

HISTORIES = ("uniaxial", "equibiaxial", "shear")
"""Homogeneous tests of the driver."""

COLUMNS = ("time_s", "strain", "stretch_1", "stretch_2", "stretch_3", "shear",
           "sigma_11_MPa", "sigma_22_MPa", "sigma_33_MPa", "sigma_12_MPa", "nominal_stress_MPa")
"""CSV columns: time, the prescribed strain, the diagonal of F and F_12 (dimensionless),
the Cauchy stress (MPa) and the nominal stress of the loaded direction (MPa)."""

CONSISTENT_MODULUS = 0.01
"""Relative difference within which the Prony sum matches the law's Young's or shear modulus."""


def ramp_hold(strain: float, ramp_time: float, hold_time: float, ramp_steps: int = 100,
              hold_steps: int = 200) -> tuple[np.ndarray, np.ndarray]:
    """Times (s) and strains of a linear ramp to ``strain`` over ``ramp_time``, then held for ``hold_time``.

    The ramp has equal steps; the hold has steps growing geometrically from ramp_time / ramp_steps
    (a relaxation spans decades of time, and the update is exact for a held strain).
    """
    if ramp_time <= 0.0 or hold_time < 0.0 or ramp_steps < 1 or hold_steps < 1:
        raise InputError("ramp-hold: expected ramp time > 0 s, hold time >= 0 s and step counts >= 1")
    ramp = np.linspace(0.0, ramp_time, ramp_steps + 1)
    if hold_time == 0.0:
        return ramp, strain * ramp / ramp_time
    first = ramp_time / ramp_steps
    hold = ramp_time + np.geomspace(min(first, hold_time), hold_time, hold_steps)
    times = np.concatenate([ramp, hold])
    return times, np.where(times < ramp_time, strain * times / ramp_time, strain)


def parse_strain_history(text: str) -> tuple[np.ndarray, np.ndarray]:
    """``ramp-hold:STRAIN,RAMP_S,HOLD_S[,RAMP_STEPS,HOLD_STEPS]`` or a CSV file with columns time_s,strain."""
    if text.startswith("ramp-hold:"):
        parts = text.removeprefix("ramp-hold:").split(",")
        try:
            if len(parts) not in (3, 5):
                raise ValueError
            values = [float(v) for v in parts[:3]] + [int(v) for v in parts[3:]]
        except ValueError:
            raise InputError(f"--strain {text!r}: expected ramp-hold:STRAIN,RAMP_S,HOLD_S[,RAMP_STEPS,HOLD_STEPS], "
                             "e.g. ramp-hold:0.05,1,10000") from None
        return ramp_hold(*values)
    from corneasim.data import read_table

    if not Path(text).is_file():
        raise InputError(f"--strain {text!r}: not ramp-hold:... and no such CSV file (columns time_s,strain)")
    table = read_table(text, required=("time_s", "strain"))
    times, strains = table["time_s"], table["strain"]
    if times.size < 2 or np.any(np.diff(times) <= 0.0):
        raise InputError(f"{text}: column time_s must increase, with at least two rows")
    if times[0] != 0.0 or strains[0] != 0.0:
        times, strains = np.concatenate([[0.0], times]), np.concatenate([[0.0], strains])
    return times, strains


def prony_reading(material: MaterialSpec) -> str | None:
    """One line on how the Prony series is read when its absolute moduli are not the law's, else None."""
    series = material.viscoelastic
    if series is None:
        return None
    total = sum(series.prony_moduli) + series.long_term_modulus
    for modulus in (material.youngs_modulus, material.initial_shear_modulus):
        if abs(total / modulus - 1.0) <= CONSISTENT_MODULUS:
            return None
    weights = ", ".join(f"{g:.4g}" for g in series.weights())
    return (f"material {material.name!r}: the Prony series is read as weights g_i = E_i / (sum E_j + E_inf) = "
            f"{weights} of the instantaneous response of its {material.hyperelastic.model} law (small-strain "
            f"E = {material.youngs_modulus:.4g} MPa, mu = {material.initial_shear_modulus:.4g} MPa); its absolute "
            f"moduli (sum E_i + E_inf = {total:.4g} MPa) are not used")


def _gradient(history: str, strain: float, lateral: float) -> np.ndarray:
    if history == "shear":
        F = np.eye(3)
        F[0, 1] = strain
        return F
    stretch = 1.0 + strain
    if history == "uniaxial":
        return np.diag([stretch, lateral, lateral])
    return np.diag([stretch, stretch, lateral])


def material_point_test(material: MaterialSpec, history: str, times, strains) -> dict[str, np.ndarray]:
    """Integrate ``material`` through a homogeneous test (module notes); columns :data:`COLUMNS`.

    Parameters
    ----------
    material : MaterialSpec
    history : str
        ``uniaxial``, ``equibiaxial`` or ``shear``.
    times : array_like
        Increasing times, s, from 0.
    strains : array_like
        Prescribed strain at each time: lambda - 1 (uniaxial, equibiaxial) or gamma (shear).
    """
    if history not in HISTORIES:
        raise InputError(f"--history: expected one of {', '.join(HISTORIES)}, got {history!r}")
    times, strains = np.asarray(times, dtype=float), np.asarray(strains, dtype=float)
    if history != "shear" and np.any(strains <= -1.0):
        raise InputError("strain: a stretch 1 + strain must stay > 0")
    record = material.kernel_form().as_array()
    state = new_history()
    rows = np.zeros((times.size, len(COLUMNS)))
    lateral = 1.0
    for n, (t, strain) in enumerate(zip(times, strains)):
        dt = t - times[n - 1] if n else 0.0

        def stress(lateral_stretch, strain=strain, dt=dt):
            return viscoelastic_stress(_gradient(history, strain, lateral_stretch), state, dt, record)

        if history != "shear":
            lateral = _free_stretch(lambda s: stress(s)[0][2, 2], lateral)
        sigma, state_new = stress(lateral)
        F = _gradient(history, strain, lateral)
        P = np.linalg.det(F) * sigma @ np.linalg.inv(F).T
        rows[n] = (t, strain, F[0, 0], F[1, 1], F[2, 2], F[0, 1], sigma[0, 0], sigma[1, 1], sigma[2, 2],
                   sigma[0, 1], P[0, 1] if history == "shear" else P[0, 0])
        state = state_new
    return {name: rows[:, k] for k, name in enumerate(COLUMNS)}


def _free_stretch(free_stress, guess: float) -> float:
    """The stretch at which the free stress component (a function of it, MPa) vanishes (bracketed root)."""
    low, high = guess / 1.05, guess * 1.05
    for _ in range(60):
        if free_stress(low) < 0.0 < free_stress(high):
            return brentq(free_stress, low, high, xtol=1e-15, rtol=4 * np.finfo(float).eps)
        low, high = low / 1.2, high * 1.2
    raise InputError("material test: no lateral stretch frees the lateral stress (an unstable law?)")


def to_csv(columns: dict[str, np.ndarray]) -> str:
    """The driver's columns as CSV text."""
    lines = [",".join(COLUMNS)]
    lines += [",".join(f"{v:.10g}" for v in row) for row in zip(*(columns[name] for name in COLUMNS))]
    return "\n".join(lines) + "\n"
