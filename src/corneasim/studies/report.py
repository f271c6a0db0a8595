"""``corneasim study report DIR``: plots and a Markdown summary of a study's table.

Written to ``DIR/report/``:

* ``report.md``: cases by status, the spread of every scalar output over the completed cases
  (min / median / max, mean and standard deviation), the sensitivity indices of a Morris or
  Sobol' design (:mod:`corneasim.studies.sensitivity`) with their confidence intervals;
* ``<output>-vs-parameters.png``: each scalar output against each parameter (one panel per
  parameter; a failed case is not drawn);
* ``<output>-band.png``: a curve output's median over the cases with the min-max band and the
  10-90% band (and each case's curve, for at most :data:`FEW_CASES` cases);
* ``<output>-morris.png`` / ``<output>-sobol.png``: the indices as bars with their intervals.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np

from corneasim.output import atomic_write_text
from corneasim.studies import table as results
from corneasim.studies.designs import list_keys, unit_sample
from corneasim.studies.outputs import abscissa
from corneasim.studies.sensitivity import CONFIDENCE, morris_indices, sobol_indices
from corneasim.studies.spec import CurveOutput, read_study


FEW_CASES = 12
"""Up to this many cases, a curve's band plot also draws each case's curve."""


def _figure(panels: int):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    columns = min(panels, 3)
    rows = math.ceil(panels / columns)
    figure, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 3.3 * rows), squeeze=False)
    for extra in axes.flat[panels:]:
        extra.set_visible(False)
    return plt, figure, axes.flat


def _save(plt, figure, path: Path) -> str:
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)
    return path.name


def _scalar(table, name: str) -> np.ndarray:
    return np.array([float(v) if isinstance(v, (int, float, np.number)) and not isinstance(v, bool) else math.nan
                     for v in table[name]], dtype=float)


def _number(value: float) -> str:
    return "nan" if not np.isfinite(value) else f"{value:.4g}"


def scatter(table, output: str, parameters: list[str], folder: Path) -> str:
    """The output against each parameter (completed cases)."""
    plt, figure, axes = _figure(len(parameters))
    done = table[table["status"] == "completed"]
    y = _scalar(done, output)
    for axis, parameter in zip(axes, parameters):
        values = list(done[parameter])
        if all(isinstance(v, (int, float, np.number)) and not isinstance(v, bool) for v in values):
            axis.plot(np.asarray(values, dtype=float), y, "o", markersize=4, alpha=0.7)
        else:
            labels = sorted({str(v) for v in values})
            axis.plot([labels.index(str(v)) for v in values], y, "o", markersize=4, alpha=0.7)
            axis.set_xticks(range(len(labels)), labels)
        axis.set_xlabel(parameter, fontsize=8)
        axis.set_ylabel(output)
        axis.grid(alpha=0.3)
    return _save(plt, figure, folder / f"{output}-vs-parameters.png")


def band(table, name: str, curve: CurveOutput, folder: Path) -> str | None:
    """Median, 10-90% and min-max of a curve output over the completed cases."""
    done = table[table["status"] == "completed"]
    curves = [np.asarray(v, dtype=float) for v in done[name] if isinstance(v, np.ndarray)]
    if not curves:
        return None
    stack = np.vstack(curves)
    x = abscissa(curve)
    plt, figure, axes = _figure(1)
    axis = next(iter(axes))
    with warnings.catch_warnings():  # an abscissa value no case reached is NaN in every row
        warnings.simplefilter("ignore", RuntimeWarning)
        low, p10, median, p90, high = np.nanpercentile(stack, [0, 10, 50, 90, 100], axis=0)
    axis.fill_between(x, low, high, alpha=0.2, label="min-max")
    axis.fill_between(x, p10, p90, alpha=0.35, label="10-90%")
    axis.plot(x, median, "k-", label=f"median of {len(curves)} cases")
    if len(curves) <= FEW_CASES:
        for case, values in zip(done["case"], curves):
            axis.plot(x, values, linewidth=0.8, label=case)
    axis.set_xlabel(curve.x)
    axis.set_ylabel(curve.curve)
    axis.legend(fontsize=8)
    axis.grid(alpha=0.3)
    return _save(plt, figure, folder / f"{name}-band.png")


def _bars(indices: dict, pairs: list[tuple[str, str]], output: str, path: Path) -> str:
    plt, figure, axes = _figure(1)
    axis = next(iter(axes))
    names = indices["names"]
    width = 0.8 / len(pairs)
    for k, (key, label) in enumerate(pairs):
        axis.bar(np.arange(len(names)) + (k - (len(pairs) - 1) / 2) * width, indices[key], width,
                 yerr=indices[f"{key}_conf"], capsize=3, label=label)
    axis.set_xticks(range(len(names)), names, rotation=20, ha="right", fontsize=7)
    axis.set_title(output)
    axis.legend(fontsize=8)
    axis.grid(alpha=0.3, axis="y")
    return _save(plt, figure, path)


def write_report(directory: str | Path) -> Path:
    """Write ``DIR/report/`` (module notes) and return the path of ``report.md``."""
    directory = Path(directory)
    study, _, _ = read_study(directory / "study.toml")
    table = results.read(directory)
    if table is None:
        from corneasim.errors import InputError

        raise InputError(f"{directory}: no results.parquet yet (run the study first)")
    folder = directory / "report"
    folder.mkdir(exist_ok=True)
    varied = set(study.parameters) | set(list_keys(study)) | (
        {"instrument.start_gap"} if study.design.kind == "realizations" else set())
    parameters = [p for p in table.columns if p in varied]
    counts = table["status"].value_counts().to_dict()
    completed = table[table["status"] == "completed"]
    lines = [f"# Study report: {directory.name}", "", study.description or "", "",
             f"Scenario `{study.scenario}`, design `{study.design.kind}`, {len(table)} cases: "
             + ", ".join(f"{counts[s]} {s}" for s in sorted(counts)) + ".",
             f"Case wall time: {_number(np.nansum(table['wall_s']))} s in all, "
             f"median {_number(np.nanmedian(table['wall_s'])) if len(table) else 'nan'} s.", ""]
    failed = table[table["status"] == "failed"]
    if len(failed):
        lines += ["Failed cases:", ""] + [f"- {r['case']}: {r['error']}" for _, r in failed.head(20).iterrows()] + [""]
    scalars = [name for name, output in study.outputs.items() if not isinstance(output, CurveOutput)
               and np.isfinite(_scalar(table, name)).any()]
    if scalars:
        lines += ["## Spread of the outputs (completed cases)", "",
                  "| output | min | median | max | mean | std | cases |", "|---|---|---|---|---|---|---|"]
        for name in scalars:
            y = _scalar(completed, name)
            y = y[np.isfinite(y)]
            lines.append(f"| {name} | " + " | ".join(_number(f(y)) if y.size else "nan" for f in (
                np.min, np.median, np.max, np.mean, np.std)) + f" | {y.size} |")
        lines.append("")
    if parameters and scalars:
        lines += ["## Outputs against the parameters", ""]
        for name in scalars:
            lines.append(f"![{name}]({scatter(table, name, parameters, folder)})")
        lines.append("")
    curves = {name: output for name, output in study.outputs.items() if isinstance(output, CurveOutput)}
    for name, curve in curves.items():
        image = band(table, name, curve, folder)
        if image:
            lines += [f"## Curve {name}: {curve.curve} against {curve.x}", "", f"![{name}]({image})", ""]
    lines += _sensitivity(study, table, scalars, folder)
    path = folder / "report.md"
    atomic_write_text(path, "\n".join(lines) + "\n")
    return path


def _sensitivity(study, table, scalars: list[str], folder: Path) -> list[str]:
    kind = study.design.kind
    if kind not in ("morris", "sobol"):
        return []
    size = len(unit_sample(study))
    index = np.array([int(name[1:]) for name in table["case"]])
    percent = f"{100 * CONFIDENCE:.0f}%"
    lines = [f"## Sensitivity ({kind}; +- {percent} confidence half-widths)", ""]
    for name in scalars:
        y = np.full(size, np.nan)  # design order; a case not run or not completed is NaN
        y[index] = np.where(table["status"] == "completed", _scalar(table, name), np.nan)
        if kind == "morris":
            indices = morris_indices(study, y, seed=study.design.seed)
            if indices is None:
                lines += [f"{name}: fewer than two complete trajectories.", ""]
                continue
            lines += [f"### {name} ({indices['trajectories']} complete trajectories; per unit of the normalised "
                      "input)", "", "| parameter | mu* | sigma |", "|---|---|---|"]
            lines += [f"| {p} | {_number(m)} +- {_number(mc)} | {_number(s)} +- {_number(sc)} |" for p, m, mc, s, sc in
                      zip(indices["names"], indices["mu_star"], indices["mu_star_conf"], indices["sigma"],
                          indices["sigma_conf"])]
            image = _bars(indices, [("mu_star", "mu*"), ("sigma", "sigma")], name, folder / f"{name}-morris.png")
        else:
            indices = sobol_indices(study, y, seed=study.design.seed)
            if indices is None:
                lines += [f"{name}: Sobol' indices need every case; some failed.", ""]
                continue
            lines += [f"### {name}", "", "| parameter | S1 | ST |", "|---|---|---|"]
            lines += [f"| {p} | {_number(a)} +- {_number(ac)} | {_number(b)} +- {_number(bc)} |" for p, a, ac, b, bc in
                      zip(indices["names"], indices["S1"], indices["S1_conf"], indices["ST"], indices["ST_conf"])]
            image = _bars(indices, [("S1", "S1"), ("ST", "ST")], name, folder / f"{name}-sobol.png")
        lines += ["", f"![{name}]({image})", ""]
    return lines
