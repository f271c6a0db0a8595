"""``corneasim calibrate``: fit a study's parameters to a measured curve, candidates run in parallel.

The objective is the root-mean-square error between one curve output of the study and a
dataset (a built-in one, ``corneasim data list``, or a CSV file whose header names carry the
units), over the dataset's points inside the curve's abscissa range:

    RMSE = sqrt( (1/n) sum_i (y(x_i) - y_i)^2 ),  y(x_i) linear interpolation of the curve.

The search space is the parameters' bounds (a range's or a distribution's ``low`` and
``high``; log-scaled for ``log`` ranges and log-uniform distributions); optuna's TPE sampler
(Bergstra et al. 2011, "Algorithms for Hyper-Parameter Optimization", NeurIPS) proposes
``batch`` candidates at a time (ask), which run at once on the Dask cluster, and learns
their RMSE (tell). Every evaluated case is a row of the study table (with the extra column
``rmse``, the unit of the curve); a calibration run again into the same folder tells the
optimiser the cases it finished and goes on to ``evaluations`` cases.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from corneasim.errors import InputError
from corneasim.output import atomic_write_text
from corneasim.studies import table as results
from corneasim.studies.designs import Case
from corneasim.studies.outputs import abscissa
from corneasim.studies.runner import CaseProgress, Plan, prepare_folder
from corneasim.studies.spec import LogUniform, Normal, ValueRange

RMSE = "rmse"


@dataclass
class Calibration:
    """What :func:`calibrate` found.

    Attributes
    ----------
    values : dict
        Dotted scenario key -> calibrated value (unit of the key).
    rmse : float
        RMSE of the best case, unit of the curve.
    case : str
        The best case (its folder is ``DIR/cases/<case>``).
    toml : str
        The values as a TOML block (also ``DIR/calibration.toml``).
    plot : Path
        The fit plot, ``DIR/calibration.png``.
    table : pandas.DataFrame
        Every evaluated case.
    """

    values: dict
    rmse: float
    case: str
    toml: str
    plot: Path
    table: pd.DataFrame


def measured(plan: Plan) -> tuple[np.ndarray, np.ndarray]:
    """The dataset's (x, y) columns named by the calibration table."""
    from corneasim.data import list_datasets, load_dataset, load_dataset_file

    spec = plan.study.calibration
    data = (load_dataset(spec.dataset) if spec.dataset in list_datasets()
            else load_dataset_file(plan.base_dir / spec.dataset))
    for key in ("x_column", "y_column"):
        if getattr(spec, key) not in data.columns:
            raise InputError(f"calibration.{key}: dataset {spec.dataset!r} has no column {getattr(spec, key)!r} "
                             f"(it has {', '.join(data.columns)})")
    return np.asarray(data.columns[spec.x_column], float), np.asarray(data.columns[spec.y_column], float)


def curve_rmse(curve: np.ndarray, at: np.ndarray, x: np.ndarray, y: np.ndarray) -> float:
    """RMSE of the curve (values on ``at``) against the points (x, y) inside its finite range; NaN if none."""
    curve = np.asarray(curve, dtype=float)
    finite = np.isfinite(curve)
    if finite.sum() < 2:
        return math.nan
    inside = (x >= at[finite].min()) & (x <= at[finite].max())
    if not inside.any():
        return math.nan
    return float(np.sqrt(np.mean((np.interp(x[inside], at[finite], curve[finite]) - y[inside]) ** 2)))


def search_space(plan: Plan) -> dict:
    """optuna distributions of the parameters (their bounds)."""
    import optuna

    space = {}
    for key, parameter in plan.study.parameters.items():
        if isinstance(parameter, Normal):
            raise InputError(f"parameters.{key}: calibration needs bounds; a normal distribution has none "
                             "(use a truncated-normal or a range)")
        log = (isinstance(parameter, ValueRange) and parameter.scale == "log") or isinstance(parameter, LogUniform)
        space[key] = optuna.distributions.FloatDistribution(parameter.low, parameter.high, log=log)
    return space


def calibrate(spec, out, client=None, workers: int | None = None, scheduler: str | None = None,
              progress: bool = False) -> Calibration:
    """Fit the study's parameters (module notes).

    Parameters
    ----------
    spec : path-like or dict
        Study with a ``[calibration]`` table.
    out : path-like
        Results folder (study table, ``calibration.toml``, ``calibration.png``).
    client, workers, scheduler, progress
        As :func:`corneasim.studies.runner.run_study`.

    Returns
    -------
    Calibration
    """
    import optuna

    from corneasim.studies.engine import connect, execute, worker_count

    plan = Plan(spec)
    if plan.study.calibration is None:
        raise InputError(f"{spec}: no [calibration] table (curve, dataset, x_column, y_column)")
    setting = plan.study.calibration
    x, y = measured(plan)
    at = abscissa(plan.study.outputs[setting.curve])
    space = search_space(plan)
    out = Path(out)
    prepare_folder(plan, out)
    order = plan.columns() + [RMSE]
    rows = results.rows_of(results.read(out))
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    search = optuna.create_study(direction="minimize", sampler=optuna.samplers.TPESampler(seed=setting.seed))
    for name in sorted(rows):
        row = rows[name]
        if row["status"] == "completed" and math.isfinite(row.get(RMSE, math.nan)):
            search.add_trial(optuna.trial.create_trial(params={k: float(row[k]) for k in space}, distributions=space,
                                                       value=row[RMSE], user_attrs={"case": name}))
    rows = {name: row for name, row in rows.items() if row["status"] in ("completed", "failed")}
    bar = CaseProgress(setting.evaluations, min(len(rows), setting.evaluations), enabled=progress)
    with bar, connect(client, scheduler, workers) as engine:
        while len(rows) < setting.evaluations:
            size = min(setting.batch or worker_count(engine), setting.evaluations - len(rows))
            trials, cases, jobs = {}, {}, {}
            for _ in range(size):
                trial = search.ask(space)
                case = Case(_next_index(rows, cases), dict(trial.params))
                trials[case.name], cases[case.name] = trial, case
                message = plan.invalid(case)
                if message is None:
                    jobs[case.name] = plan.job(case, out)
                else:
                    record(plan, rows, case, {**plan.empty_outputs(), "status": "failed", "error": message,
                                              "wall_s": 0.0, "worker": ""}, setting.curve, at, x, y)
                    search.tell(trial, state=optuna.trial.TrialState.FAIL)
                    bar.advance("failed")

            def finished(name, outcome):
                value = record(plan, rows, cases[name], outcome, setting.curve, at, x, y)
                trial = trials[name]
                trial.set_user_attr("case", name)
                if math.isfinite(value):
                    search.tell(trial, value)
                else:
                    search.tell(trial, state=optuna.trial.TrialState.FAIL)
                results.write(out, results.frame(rows, order))
                bar.advance(outcome["status"])

            def lost(name, message):
                return {**plan.empty_outputs(), "status": "failed", "error": message, "wall_s": math.nan,
                        "worker": ""}

            execute(engine, jobs, finished, lost)
            results.write(out, results.frame(rows, order))
    table = results.frame(rows, order)
    best = table[np.isfinite(table[RMSE].astype(float))].sort_values(RMSE)
    if best.empty:
        raise InputError(f"calibration: none of the {len(table)} cases gave a finite RMSE against "
                         f"{setting.dataset} (see the error column of {out / results.CSV})")
    top = best.iloc[0]
    values = {key: float(top[key]) for key in space}
    text = calibration_toml(values, float(top[RMSE]), top["case"], len(table), setting)
    atomic_write_text(out / "calibration.toml", text)
    plot = fit_plot(plan, table, top, at, x, y, out / "calibration.png")
    return Calibration(values, float(top[RMSE]), top["case"], text, plot, table)


def _next_index(rows: dict, pending: dict) -> int:
    taken = {int(name[1:]) for name in [*rows, *pending]}
    return next(i for i in range(len(taken) + 1) if i not in taken)


def record(plan: Plan, rows: dict, case: Case, outcome: dict, curve: str, at, x, y) -> float:
    """Store a case's row with its RMSE; return the RMSE (NaN unless completed)."""
    value = curve_rmse(outcome[curve], at, x, y) if outcome["status"] == "completed" else math.nan
    rows[case.name] = {**plan.row(case, outcome), RMSE: value}
    return value


def calibration_toml(values: dict, rmse: float, case: str, count: int, setting) -> str:
    """The calibrated values as a TOML table (paste into a study's overrides or use as --set)."""
    from corneasim.studies.case import toml_value

    lines = [f"# calibrated on {setting.dataset} ({setting.x_column}, {setting.y_column}): RMSE of "
             f"{setting.curve} {rmse:.6g} (best of {count} cases, {case})", "[calibrated]"]
    lines += [f'"{key}" = {toml_value(round(value, 6))}' for key, value in values.items()]
    return "\n".join(lines) + "\n"


def fit_plot(plan: Plan, table: pd.DataFrame, best, at, x, y, path: Path) -> Path:
    """The measured points, every completed candidate (grey) and the best one."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    setting = plan.study.calibration
    output = plan.study.outputs[setting.curve]
    figure, axis = plt.subplots(figsize=(6, 4))
    for _, row in table[table["status"] == "completed"].iterrows():
        axis.plot(at, row[setting.curve], color="0.8", linewidth=0.8)
    axis.plot(at, best[setting.curve], "C0-", linewidth=2, label=f"best ({best['case']}, RMSE {best[RMSE]:.4g})")
    axis.plot(x, y, "ko", markersize=4, label=f"{setting.dataset}: {setting.y_column}")
    axis.set_xlabel(output.x)
    axis.set_ylabel(output.curve)
    axis.legend(fontsize=8)
    axis.grid(alpha=0.3)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)
    return path
