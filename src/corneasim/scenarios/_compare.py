"""The trephination paper's mesh comparison (its Table 1): one run per meshing strategy.

For each strategy (umbrella, vertical, horizontal) the trephine scenario runs with the same
overrides and the row reports: elements in total and in the trephine area, wall time, and
the agreement of F_z with the robot experiment at the Table 2 times up to 65 s: RMSE and
maximum error (N), the trend (Pearson r; "similar" when r >= :data:`TREND_SIMILAR`) and the
magnitude (sum of simulated over experimental values; "similar" within
:data:`MAGNITUDE_SIMILAR`, else "smaller" / "larger"), the paper's qualitative columns made
quantitative.

The *trephine area* is the cornea (epithelium and stroma) within :data:`TREPHINE_AREA_BAND`
of the cutting circle, by element centre: the region the edge cuts and presses (the
paper's "subdivision region", its Fig. 3a, is not dimensioned).
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

from corneasim.output import atomic_write_text

STRATEGIES = ("umbrella", "vertical", "horizontal")
"""Meshing strategies of the trephination paper (Fig. 3, Table 1)."""

TREPHINE_AREA_BAND = 1.0
"""Half width of the trephine area around the cutting radius, mm."""

TREND_SIMILAR = 0.9
"""Pearson r from which the F_z trend counts as similar to the experiment's."""

MAGNITUDE_SIMILAR = (0.8, 1.25)
"""Range of the simulated / experimental F_z ratio counted as a similar magnitude."""

COLUMNS = ["strategy", "status", "elements_total", "elements_trephine_area", "wall_s", "steps",
           "peak_fz_N", "fz_rmse_N", "fz_max_abs_error_N", "fc_rmse_N", "fz_pearson", "fz_magnitude_ratio",
           "variation_trend", "data_area"]


def trephine_area_elements(mesh, cutting_radius: float, band: float = TREPHINE_AREA_BAND) -> int:
    """Cornea elements whose centre lies within ``band`` (mm) of the cutting radius (mm)."""
    centres = mesh.points[mesh.cells].mean(axis=1)
    radius = np.hypot(centres[:, 0], centres[:, 1])
    cornea = np.isin(mesh.element_block, [mesh.block_names.index(b) for b in ("epithelium", "stroma")
                                          if b in mesh.block_names])
    return int(np.sum(cornea & (np.abs(radius - cutting_radius) <= band)))


def _classify(pearson, ratio) -> tuple[str, str]:
    trend = "n/a" if pearson is None else "similar" if pearson >= TREND_SIMILAR else "different"
    if ratio is None:
        area = "n/a"
    elif ratio < MAGNITUDE_SIMILAR[0]:
        area = "smaller"
    elif ratio > MAGNITUDE_SIMILAR[1]:
        area = "larger"
    else:
        area = "similar"
    return trend, area


def table_row(strategy: str, mesh, cutting_radius: float, summary: dict) -> dict:
    """One Table 1 row from a run's mesh, the trephine's cutting radius (mm) and the run's summary."""
    run = summary.get("run", {})
    validation = summary.get("validation") or {}
    fz, fc = validation.get("fz", {}), validation.get("fc", {})
    trend, area = _classify(fz.get("pearson"), fz.get("magnitude_ratio"))
    return {"strategy": strategy, "status": summary.get("status"), "elements_total": mesh.n_elements,
            "elements_trephine_area": trephine_area_elements(mesh, cutting_radius),
            "wall_s": run.get("wall_s"), "steps": run.get("steps"), "peak_fz_N": summary.get("peak_fz_N"),
            "fz_rmse_N": fz.get("rmse_N"), "fz_max_abs_error_N": fz.get("max_abs_error_N"),
            "fc_rmse_N": fc.get("rmse_N"), "fz_pearson": fz.get("pearson"),
            "fz_magnitude_ratio": fz.get("magnitude_ratio"), "variation_trend": trend, "data_area": area}


def compare_meshes(name_or_path: str = "trephine", overrides=(), out_dir: str | Path | None = None,
                   strategies=STRATEGIES, progress: bool = False) -> list[dict]:
    """Run a trephine scenario once per meshing strategy and tabulate (paper Table 1).

    Parameters
    ----------
    name_or_path : str
        ``"trephine"`` or a trephine scenario file (``mesh.generator = "eye-3d"``).
    overrides : list of str
        ``KEY=VALUE`` overrides applied to every run (e.g. ``mesh.preset=coarse``).
    out_dir : path-like, optional
        Writes ``<strategy>/`` results folders, ``table1.csv`` and ``table1.md`` there.
    strategies : sequence of str
        Subset of :data:`STRATEGIES`.
    progress : bool
        Progress bars on stderr.

    Returns
    -------
    list of dict
        One row per strategy, keys :data:`COLUMNS`. A run that fails is a row with status
        ``failed`` and the figures up to the failure.
    """
    from corneasim.errors import InputError
    from corneasim.scenarios._build import make_mesh
    from corneasim.scenarios._registry import load_scenario, to_toml
    from corneasim.scenarios._runner import simulate
    from corneasim.solver import SimulationError

    unknown = [strategy for strategy in strategies if strategy not in STRATEGIES]
    if unknown or not strategies:
        raise InputError(f"strategies: expected some of {', '.join(STRATEGIES)}, got {', '.join(strategies)}")
    rows = []
    for strategy in strategies:
        scenario, resolved, base_dir = load_scenario(name_or_path, [*overrides, f"mesh.strategy={strategy}"])
        if scenario.kind != "trephine" or scenario.mesh.generator != "eye-3d":
            raise InputError(f"{name_or_path}: compare-meshes needs a trephine scenario with mesh.generator "
                             "= 'eye-3d'")
        folder = Path(out_dir) / strategy if out_dir is not None else None
        try:
            summary = simulate(scenario, out_dir=folder, base_dir=base_dir, progress=progress,
                               record=to_toml(resolved) if folder is not None else None).summary
        except SimulationError as failure:
            summary = {"status": "failed", "error": str(failure)}
        mesh = make_mesh(scenario, base_dir)
        rows.append(table_row(strategy, mesh, scenario.instrument.shape.cutting_radius, summary))
    if out_dir is not None:
        atomic_write_text(Path(out_dir) / "table1.csv", table_csv(rows))
        atomic_write_text(Path(out_dir) / "table1.md", table_markdown(rows))
    return rows


def _text(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


def table_csv(rows: list[dict]) -> str:
    """The table as CSV text (header :data:`COLUMNS`)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(COLUMNS)
    for row in rows:
        writer.writerow([_text(row[c]) for c in COLUMNS])
    return buffer.getvalue()


def table_markdown(rows: list[dict]) -> str:
    """The table as Markdown, with the definitions of its columns."""
    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(_text(row[c]) for c in COLUMNS) + " |" for row in rows]
    lines += ["", f"Trephine area: cornea elements within {TREPHINE_AREA_BAND} mm of the cutting radius. "
              "Errors, trend and magnitude: F_z (its eq. 14 fit) against the robot experiment at the Table 2 "
              f"times up to 65 s; trend similar when Pearson r >= {TREND_SIMILAR}, magnitude similar when "
              f"the simulated/experimental ratio is in [{MAGNITUDE_SIMILAR[0]}, {MAGNITUDE_SIMILAR[1]}]; "
              "wall time on this machine. Units: N, s."]
    return "\n".join(lines) + "\n"
