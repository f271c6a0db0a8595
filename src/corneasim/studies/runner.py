"""Run a study: check everything, run the cases that are not done, grow the table.

Everything the study file says is checked before the first case runs (the study's keys,
the base scenario with the fixed overrides, every output path against the scenario kind's
summary), so a mistake costs no simulation. A case whose own values are invalid (the
scenario schema refuses them) is recorded as failed with the schema's one-line message,
without being run. The other cases run on Dask (:mod:`corneasim.studies.engine`); each
finished case rewrites the table (:mod:`corneasim.studies.table`).

Resuming: the same study into the same folder skips every case whose row is ``completed``
or ``failed`` (``retry_failed`` runs the failed ones again) and runs the rest, including the
ones that were ``interrupted`` (running when the study was stopped) from the start.
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from corneasim.errors import InputError
from corneasim.output import atomic_write_text
from corneasim.studies import table as results
from corneasim.studies.case import case_overrides, run_case
from corneasim.studies.designs import Case, cases, list_keys
from corneasim.studies.outputs import check_path
from corneasim.studies.spec import CurveOutput, read_study, scenario_reference

STUDY_FILE = "study.toml"
CASES = "cases"


class Plan:
    """A validated study and its cases: what :func:`run_study` and ``corneasim calibrate`` run.

    Attributes
    ----------
    study : Study
    scenario : str
        The base scenario (built-in name or absolute path).
    kind : str
        The scenario's kind (needle, trephine, general).
    base_dir : Path
        Folder that relative paths of the study refer to.
    tables : dict
        The study's raw tables.
    """

    def __init__(self, spec):
        from corneasim.scenarios import load_scenario

        self.study, self.base_dir, self.tables = read_study(spec)
        self.source = spec if not isinstance(spec, dict) else None
        self.scenario = scenario_reference(self.study, self.base_dir)
        base, _, _ = load_scenario(self.scenario, self.overrides({}), self.study.unset)
        self.kind = base.kind
        for name, output in self.study.outputs.items():
            if isinstance(output, str):
                check_path(output, self.kind, f"outputs.{name}")

    def overrides(self, values: dict) -> list[str]:
        """The ``KEY=VALUE`` overrides of a case with these parameter values."""
        return case_overrides(self.study.overrides, values)

    def cases(self) -> list[Case]:
        """The design's cases."""
        return cases(self.study, self.scenario)

    def columns(self) -> list[str]:
        """The table's columns."""
        parameters = list(self.study.parameters) + list_keys(self.study)
        if self.study.design.kind == "realizations":
            parameters += [key for key in ("instrument.start_gap", "solver.threads") if key not in parameters]
        return results.columns(parameters, list(self.study.outputs), self.study.design.kind == "realizations")

    def invalid(self, case: Case) -> str | None:
        """The one-line message of the schema if the case's values are refused, else None.

        A parameter key that the scenario does not have is a mistake of the study, not of a case:
        it raises :class:`InputError`.
        """
        from corneasim.scenarios import load_scenario

        try:
            load_scenario(self.scenario, self.overrides(case.values), self.study.unset)
        except InputError as error:
            message = str(error)
            if message.endswith("unknown key") or ": unknown key (and" in message:
                raise InputError(f"parameters: {message}") from None
            return message
        return None

    def job(self, case: Case, out: Path) -> tuple:
        """(function, arguments) of a case for the engine."""
        return run_case, (self.scenario, self.overrides(case.values), str(out / CASES / case.name),
                          self.study.outputs, case.fresh_kernels, self.study.unset, self.study.case_plots)

    def empty_outputs(self) -> dict:
        """Outputs of a case that did not run: NaN (NaN arrays for curves)."""
        from corneasim.studies.outputs import abscissa

        return {name: np.full(abscissa(output).shape, np.nan) if isinstance(output, CurveOutput) else math.nan
                for name, output in self.study.outputs.items()}

    def row(self, case: Case, outcome: dict) -> dict:
        """A table row: the case, its values and the outcome (outputs, status, error, wall_s, worker)."""
        row = {"case": case.name, **case.values}
        if case.realization is not None:
            row["realization"] = case.realization
        return {**row, **outcome}


def check_folder(plan: Plan, out: Path) -> None:
    """Refuse a results folder that holds another study."""
    copy = out / STUDY_FILE
    if copy.exists():
        from corneasim.schema import load_toml

        if load_toml(copy) != plan.tables:
            raise InputError(f"{out}: holds the results of another study ({copy} differs); choose another --out")


def prepare_folder(plan: Plan, out: Path) -> None:
    """Create ``out`` with the study file's copy (:func:`check_folder` first)."""
    import tomli_w

    check_folder(plan, out)
    out.mkdir(parents=True, exist_ok=True)
    copy = out / STUDY_FILE
    if copy.exists():
        return
    text = Path(plan.source).read_text() if plan.source is not None else tomli_w.dumps(plan.tables)
    atomic_write_text(copy, text)


def run_study(spec, out=None, client=None, workers: int | None = None, scheduler: str | None = None,
              progress: bool = False, retry_failed: bool = False) -> pd.DataFrame:
    """Run a study and return its results table.

    Parameters
    ----------
    spec : path-like or dict
        Study TOML file or its tables (``docs/studies.md``).
    out : path-like, optional
        Results folder (``study.toml``, ``cases/``, ``results.parquet``, ``results.csv``);
        default ``results/<study file name>`` (``results/study`` for a dict).
    client : distributed.Client, optional
        Run on this client's cluster (left open).
    workers : int, optional
        Workers of the local cluster started when neither ``client`` nor ``scheduler`` is given
        (default: one per core).
    scheduler : str, optional
        Address of a running Dask scheduler, e.g. ``tcp://10.0.0.5:8786``.
    progress : bool
        Progress bar over cases (with ETA) on stderr.
    retry_failed : bool
        Run cases recorded as failed again.

    Returns
    -------
    pandas.DataFrame
        One row per case (:mod:`corneasim.studies.table`).
    """
    from corneasim.studies.engine import connect

    plan = Plan(spec)
    out = Path(out) if out is not None else Path("results") / (
        Path(spec).stem if not isinstance(spec, dict) else "study")
    check_folder(plan, out)
    order = plan.columns()
    all_cases = plan.cases()
    rows = results.rows_of(results.read(out))
    rows = {name: row for name, row in rows.items() if name in {case.name for case in all_cases}}
    done = {"completed"} if retry_failed else {"completed", "failed"}
    todo = [case for case in all_cases if rows.get(case.name, {}).get("status") not in done]
    refused = {case.name: plan.invalid(case) for case in todo}
    prepare_folder(plan, out)
    jobs = {}
    for case in todo:
        if refused[case.name] is not None:
            rows[case.name] = plan.row(case, {**plan.empty_outputs(), "status": "failed",
                                              "error": refused[case.name], "wall_s": 0.0, "worker": ""})
        else:
            jobs[case.name] = plan.job(case, out)
    by_name = {case.name: case for case in all_cases}
    results.write(out, results.frame(rows, order))
    if not jobs:
        return results.frame(rows, order)
    bar = CaseProgress(len(all_cases), len(all_cases) - len(jobs), enabled=progress)

    def finished(name: str, outcome: dict) -> None:
        rows[name] = plan.row(by_name[name], outcome)
        results.write(out, results.frame(rows, order))
        bar.advance(outcome["status"])

    def lost(name: str, message: str) -> dict:
        return {**plan.empty_outputs(), "status": "failed", "error": message, "wall_s": math.nan, "worker": ""}

    try:
        with bar, connect(client, scheduler, workers) as engine:
            from corneasim.studies.engine import execute

            execute(engine, jobs, finished, lost)
    except BaseException:
        for name in jobs:
            if name not in rows or rows[name].get("status") not in ("completed", "failed"):
                rows[name] = plan.row(by_name[name], {**plan.empty_outputs(), "status": "interrupted",
                                                      "error": "study stopped while the case ran or waited",
                                                      "wall_s": math.nan, "worker": ""})
        results.write(out, results.frame(rows, order))
        raise
    return results.frame(rows, order)


class CaseProgress:
    """A rich progress bar over cases with ETA (stderr); plain lines when stderr is not a terminal."""

    PLAIN_INTERVAL = 30.0
    """Seconds between plain progress lines."""

    def __init__(self, total: int, done: int, enabled: bool):
        self.total, self.done, self.enabled = total, done, enabled
        self.failed = 0
        self.progress = None
        self.start = self.last = time.monotonic()
        self.started_with = done

    def __enter__(self):
        if self.enabled and sys.stderr.isatty():
            from rich.console import Console
            from rich.progress import (BarColumn, MofNCompleteColumn, Progress, TextColumn,
                                       TimeElapsedColumn, TimeRemainingColumn)

            self.progress = Progress(TextColumn("cases"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                                     TextColumn("ETA"), TimeRemainingColumn(), TextColumn("{task.fields[failed]}"),
                                     console=Console(file=sys.stderr))
            self.progress.__enter__()
            self.task = self.progress.add_task("cases", total=self.total, completed=self.done, failed="")
        return self

    def advance(self, status: str) -> None:
        self.done += 1
        self.failed += status != "completed"
        if self.progress is not None:
            self.progress.update(self.task, completed=self.done,
                                 failed=f"{self.failed} failed" if self.failed else "")
            return
        now = time.monotonic()
        if self.enabled and (now - self.last >= self.PLAIN_INTERVAL or self.done == self.total):
            ran = self.done - self.started_with
            left = (now - self.start) / ran * (self.total - self.done) if ran else float("nan")
            print(f"cases: {self.done}/{self.total} ({self.failed} failed), about {left:.0f} s left",
                  file=sys.stderr)
            self.last = now

    def __exit__(self, *exc):
        if self.progress is not None:
            self.progress.__exit__(*exc)
        return False
