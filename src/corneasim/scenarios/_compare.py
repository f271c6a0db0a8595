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

With ``realizations`` every strategy runs in each realization of the study design
``realizations`` (``corneasim.studies``: as given, the start gap moved by +1e-7, -1e-7 and
+5e-8 mm, kernels compiled anew, one thread), as one study on Dask: element deletion makes the
cut chaotic, so one run per strategy cannot rank strategies whose figures differ by less than
a run's round-off spread. The table then has one row per strategy and realization, and its
Markdown gives each figure's median and range over a strategy's completed realizations.
"""

from __future__ import annotations

import csv
import io
import math
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

FIGURES = {"wall_s": "run.wall_s", "steps": "run.steps", "peak_fz_N": "peak_fz_N",
           "fz_rmse_N": "validation.fz.rmse_N", "fz_max_abs_error_N": "validation.fz.max_abs_error_N",
           "fc_rmse_N": "validation.fc.rmse_N", "fz_pearson": "validation.fz.pearson",
           "fz_magnitude_ratio": "validation.fz.magnitude_ratio"}
"""The numeric columns of a row: summary.json paths (units: s, N; steps, r and ratio dimensionless)."""

REALIZATION_COLUMNS = ["strategy", "realization", *COLUMNS[1:]]
"""Columns of the table with realizations: one row per strategy and realization."""


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


def _figures(values: dict) -> dict:
    """:data:`FIGURES` from ``values`` ({column: float, NaN where missing}): None where missing,
    the step count as an integer."""
    figures = {column: None if value is None or math.isnan(value) else float(value)
               for column, value in values.items()}
    if figures["steps"] is not None:
        figures["steps"] = int(figures["steps"])
    return figures


def table_row(strategy: str, mesh, cutting_radius: float, summary: dict) -> dict:
    """One Table 1 row from a run's mesh, the trephine's cutting radius (mm) and the run's summary."""
    from corneasim.studies.outputs import summary_value

    figures = _figures({column: summary_value(summary, path) for column, path in FIGURES.items()})
    return _row(strategy, summary.get("status"), mesh, cutting_radius, figures)


def _row(strategy: str, status, mesh, cutting_radius: float, figures: dict) -> dict:
    """A row of :data:`COLUMNS` from a run's status and :data:`FIGURES` values."""
    trend, area = _classify(figures["fz_pearson"], figures["fz_magnitude_ratio"])
    return {"strategy": strategy, "status": status, "elements_total": mesh.n_elements,
            "elements_trephine_area": trephine_area_elements(mesh, cutting_radius), **figures,
            "variation_trend": trend, "data_area": area}


def compare_meshes(name_or_path: str = "trephine", overrides=(), out_dir: str | Path | None = None,
                   strategies=STRATEGIES, progress: bool = False, realizations: bool = False,
                   workers: int | None = None) -> list[dict]:
    """Run a trephine scenario once per meshing strategy, or in every realization, and tabulate
    (paper Table 1).

    Parameters
    ----------
    name_or_path : str
        ``"trephine"`` or a trephine scenario file (``mesh.generator = "eye-3d"``).
    overrides : list of str
        ``KEY=VALUE`` overrides applied to every run (e.g. ``mesh.preset=coarse``).
    out_dir : path-like, optional
        Writes ``<strategy>/`` results folders (with ``realizations``: the study folder
        ``realizations/``), ``table1.csv`` and ``table1.md`` there.
    strategies : sequence of str
        Subset of :data:`STRATEGIES`.
    progress : bool
        Progress bars on stderr.
    realizations : bool
        Run each strategy in every realization (module notes), as a study on a local Dask
        cluster; needs ``out_dir``.
    workers : int, optional
        Workers of that cluster (default: one per core).

    Returns
    -------
    list of dict
        One row per strategy, keys :data:`COLUMNS`; with ``realizations`` one per strategy and
        realization, keys :data:`REALIZATION_COLUMNS`. A run that fails is a row with status
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
    if realizations and out_dir is None:
        raise InputError("compare-meshes with realizations: needs a results folder (out_dir) for its study")
    loaded = {}
    for strategy in strategies:
        scenario, resolved, base_dir = load_scenario(name_or_path, [*overrides, f"mesh.strategy={strategy}"])
        if scenario.kind != "trephine" or scenario.mesh.generator != "eye-3d":
            raise InputError(f"{name_or_path}: compare-meshes needs a trephine scenario with mesh.generator "
                             "= 'eye-3d'")
        loaded[strategy] = scenario, resolved, base_dir, make_mesh(scenario, base_dir)
    if realizations:
        rows = _realization_rows(name_or_path, overrides, loaded, Path(out_dir) / "realizations", progress,
                                 workers)
    else:
        rows = []
        for strategy, (scenario, resolved, base_dir, mesh) in loaded.items():
            folder = Path(out_dir) / strategy if out_dir is not None else None
            try:
                summary = simulate(scenario, out_dir=folder, base_dir=base_dir, progress=progress,
                                   record=to_toml(resolved) if folder is not None else None).summary
            except SimulationError as failure:
                summary = {"status": "failed", "error": str(failure)}
            rows.append(table_row(strategy, mesh, scenario.instrument.shape.cutting_radius, summary))
    if out_dir is not None:
        columns = REALIZATION_COLUMNS if realizations else COLUMNS
        atomic_write_text(Path(out_dir) / "table1.csv", table_csv(rows, columns))
        atomic_write_text(Path(out_dir) / "table1.md", spread_markdown(rows) if realizations
                          else table_markdown(rows))
    return rows


def _output_name(column: str) -> str:
    """The study output of a :data:`FIGURES` column (a study table's own ``wall_s`` is the case's)."""
    return "run_wall_s" if column == "wall_s" else column


def realizations_study(name_or_path: str, overrides, strategies) -> dict:
    """The study that runs every strategy in every realization, with the ``KEY=VALUE`` overrides."""
    from corneasim.scenarios._overrides import override_table

    scenario = str(Path(name_or_path).resolve()) if Path(name_or_path).is_file() else name_or_path
    return {"scenario": scenario, "description": "The trephination paper's Table 1 with realization spread",
            "overrides": override_table(overrides),
            "design": {"kind": "realizations"}, "parameters": {"mesh.strategy": list(strategies)},
            "outputs": {_output_name(column): path for column, path in FIGURES.items()}}


def _realization_rows(name_or_path, overrides, loaded: dict, folder: Path, progress: bool, workers) -> list[dict]:
    """Run :func:`realizations_study` into ``folder`` and return its rows (:data:`REALIZATION_COLUMNS`)."""
    import corneasim.studies

    table = corneasim.studies.study(realizations_study(name_or_path, overrides, list(loaded)), out=folder,
                                    workers=workers, progress=progress)
    rows = []
    for _, case in table.iterrows():
        strategy = case["mesh.strategy"]
        scenario, _, _, mesh = loaded[strategy]
        figures = _figures({column: float(case[_output_name(column)]) for column in FIGURES})
        rows.append({"realization": case["realization"],
                     **_row(strategy, case["status"], mesh, scenario.instrument.shape.cutting_radius, figures)})
    return rows


_DEFINITIONS = (f"Trephine area: cornea elements within {TREPHINE_AREA_BAND} mm of the cutting radius. "
                "Errors, trend and magnitude: F_z (its eq. 14 fit) against the robot experiment at the Table 2 "
                f"times up to 65 s; trend similar when Pearson r >= {TREND_SIMILAR}, magnitude similar when "
                f"the simulated/experimental ratio is in [{MAGNITUDE_SIMILAR[0]}, {MAGNITUDE_SIMILAR[1]}]; "
                "wall time on this machine. Units: N, s.")


def _text(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


def table_csv(rows: list[dict], columns=COLUMNS) -> str:
    """The table as CSV text (header ``columns``: :data:`COLUMNS` or :data:`REALIZATION_COLUMNS`)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    for row in rows:
        writer.writerow([_text(row[c]) for c in columns])
    return buffer.getvalue()


def table_markdown(rows: list[dict]) -> str:
    """The table as Markdown, with the definitions of its columns."""
    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(_text(row[c]) for c in COLUMNS) + " |" for row in rows]
    lines += ["", _DEFINITIONS]
    return "\n".join(lines) + "\n"


def _range(values: list) -> str:
    """``median (min to max)`` of the values, or the one value, or nothing."""
    values = [value for value in values if value is not None]
    if not values:
        return ""
    if len(values) == 1:
        return _text(values[0])
    median = float(np.median(values))
    if all(isinstance(value, int) for value in values) and median.is_integer():
        median = int(median)
    return f"{_text(median)} ({_text(min(values))} to {_text(max(values))})"


def _similar(classes: list[str]) -> str:
    """In how many of the classified realizations a qualitative column reads ``similar``."""
    classified = [value for value in classes if value != "n/a"]
    if not classified:
        return "n/a"
    return f"similar in {classified.count('similar')} of {len(classified)}"


def spread_markdown(rows: list[dict]) -> str:
    """The table with realizations as Markdown: per strategy, the completed realizations, each
    figure's median and range over them, and in how many the trend and the data area are similar."""
    columns = ["strategy", "completed", "elements_total", "elements_trephine_area", *FIGURES,
               "variation_trend", "data_area"]
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for strategy in dict.fromkeys(row["strategy"] for row in rows):
        runs = [row for row in rows if row["strategy"] == strategy]
        done = [row for row in runs if row["status"] == "completed"]
        cells = [strategy, f"{len(done)} of {len(runs)}", _text(runs[0]["elements_total"]),
                 _text(runs[0]["elements_trephine_area"]), *(_range([row[c] for row in done]) for c in FIGURES),
                 *(_similar([row[c] for row in done]) for c in ("variation_trend", "data_area"))]
        lines.append("| " + " | ".join(cells) + " |")
    names = ", ".join(dict.fromkeys(row["realization"] for row in rows))
    lines += ["", f"Each figure: median (min to max) over the strategy's completed realizations ({names}). "
              + _DEFINITIONS]
    return "\n".join(lines) + "\n"
