"""A study folder written from a closed-form force law, without finite elements.

For tests, the worked example at tiny size and trying the surrogate tools: the folder has the
layout of ``corneasim study run`` (``study.toml``, ``results.csv``, ``cases/<case>/`` with
``scenario.toml``, ``history.csv``, ``summary.json``), and its truth is known.

Needle law, with insertion rate :math:`v` (mm/s) and needle diameter :math:`d` (mm): punctures at

.. math::

    \\lambda_1 = 0.20 + 0.8\\,(d - 0.2) + 0.01\\,v, \\quad \\lambda_2 = \\lambda_1 + 0.08, \\quad
    \\lambda_3 = 0.75 + 1.2\\,(d - 0.2) + 0.02\\,v \\quad \\text{(mm)},

and the force :math:`F(a) = k a^2 m(a)`, :math:`k = 4\\,(d/0.2)(1 + 0.05 v)` N/mm², with
:math:`m = 1, 0.7, 0.55` on :math:`[0, \\lambda_1), [\\lambda_1, \\lambda_2), [\\lambda_2, \\lambda_3)`
and the friction of the shaft :math:`F = 0.04\\,k` beyond :math:`\\lambda_3`.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

RATE = "instrument.motion.insertion.rate"
DIAMETER = "instrument.shape.diameter"
RANGES = {RATE: (1.0, 5.0), DIAMETER: (0.15, 0.25)}
"""Input ranges of the synthetic study: mm/s and mm."""
DEPTH = 1.0
"""Insertion depth of every case, mm."""


def punctures(rate: float, diameter: float) -> dict:
    """The law's puncture depths (mm) of the epithelium, the stroma and the whole cornea."""
    epithelium = 0.20 + 0.8 * (diameter - 0.2) + 0.01 * rate
    return {"epithelium": epithelium, "stroma": epithelium + 0.08,
            "cornea": 0.75 + 1.2 * (diameter - 0.2) + 0.02 * rate}


def needle_force(depth, rate: float, diameter: float) -> np.ndarray:
    """The law's force (N) at ``depth`` (mm)."""
    depth = np.asarray(depth, dtype=float)
    events = punctures(rate, diameter)
    stiffness = 4.0 * (diameter / 0.2) * (1.0 + 0.05 * rate)
    factor = np.select([depth < events["epithelium"], depth < events["stroma"], depth < events["cornea"]],
                       [1.0, 0.7, 0.55], 0.04 / np.maximum(depth, 1e-12) ** 2)
    return stiffness * depth**2 * factor


def write_study(directory, count: int = 16, samples: int = 400, seed: int = 0, noise: float = 0.0,
                depth: float = DEPTH) -> Path:
    """Write a synthetic needle study of ``count`` Latin-hypercube cases into ``directory``.

    Parameters
    ----------
    directory : path
        Created if missing.
    count : int
        Cases (all completed).
    samples : int
        History rows per case, evenly spaced in depth over [0, ``depth``] mm.
    seed : int
        Seed of the design and of the noise.
    noise : float
        Standard deviation of white noise added to the forces, N.
    depth : float
        Insertion depth of every case, mm; a puncture deeper than it is not in the case's
        ``summary.json``, as in a run that ends before it.

    Returns
    -------
    Path
        ``directory``.
    """
    directory = Path(directory)
    rng = np.random.default_rng(seed)
    design = (np.array([rng.permutation(count) for _ in RANGES]).T + rng.random((count, len(RANGES)))) / count
    low, high = np.array(list(RANGES.values())).T
    values = low + design * (high - low)                                   # (count, 2)
    directory.mkdir(parents=True, exist_ok=True)
    (directory / "study.toml").write_text(
        'scenario = "needle"\noverrides = { "mesh.preset" = "coarse" }\n\n[design]\nkind = "latin-hypercube"\n'
        f"count = {count}\n\n[parameters]\n"
        + "".join(f'"{key}" = {{ distribution = "uniform", low = {lo}, high = {hi} }}\n'
                  for key, (lo, hi) in RANGES.items())
        + '\n[outputs]\npeak_force_N = "peak_force_N"\n')
    rows = ["case," + ",".join(RANGES) + ",peak_force_N,status,error,wall_s,worker"]
    grid = np.linspace(0.0, depth, samples)
    for n, (rate, diameter) in enumerate(values.tolist()):
        case = directory / "cases" / f"c{n:04d}"
        case.mkdir(parents=True, exist_ok=True)
        force = needle_force(grid, rate, diameter) + noise * rng.standard_normal(samples)
        (case / "scenario.toml").write_text(f'kind = "needle"\nname = "needle"\n\n[instrument.motion]\n'
                                            f'insertion = {{ type = "linear", rate = {rate!r} }}\n')
        np.savetxt(case / "history.csv", np.c_[grid / rate, grid, force], delimiter=",",
                   header="time_s,depth_mm,force_N", comments="")
        events = punctures(rate, diameter)
        summary = {"status": "completed", "peak_force_N": float(force.max()),
                   "punctures": [{"event": e, "depth_mm": a, "time_s": a / rate,
                                  "force_N": float(needle_force(a, rate, diameter))}
                                 for e, a in events.items() if a <= depth]}
        (case / "summary.json").write_text(json.dumps(summary))
        rows.append(f"c{n:04d},{rate!r},{diameter!r},{float(force.max())!r},completed,,0.0,synthetic")
    (directory / "results.csv").write_text("\n".join(rows) + "\n")
    return directory
