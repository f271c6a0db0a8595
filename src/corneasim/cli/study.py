"""``corneasim study run|report`` and ``corneasim calibrate``: studies of many cases on Dask."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from corneasim.errors import InputError


def _positive(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive whole number, got {text!r}")
    return value


def _engine_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--workers", type=_positive, metavar="N",
                        help="Worker processes of the local Dask cluster (default: one per core); each gets "
                             "cores // N Numba threads.")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="Run on the Dask scheduler at ADDRESS (e.g. tcp://10.0.0.5:8786, a dask-jobqueue "
                             "cluster on SLURM/PBS) instead of a local cluster.")
    parser.add_argument("--no-progress", action="store_true", help="No progress bar.")


def register(commands: argparse._SubParsersAction) -> None:
    """Add the ``study`` group (``run``, ``report``) and the ``calibrate`` command."""
    formatter = argparse.RawDescriptionHelpFormatter
    study = commands.add_parser("study", help="Run many cases of a scenario on Dask and report on them.",
                                description="Sweeps, ensembles and sensitivity studies of a scenario (docs/studies.md).",
                                epilog="example: corneasim study run validation/studies/needle_speed.toml "
                                "--out results/needle-speed", formatter_class=formatter)
    actions = study.add_subparsers(dest="study_command", metavar="ACTION", required=True)
    run = actions.add_parser("run", help="Run a study's cases in parallel and grow its results table.",
                             description="Run a study's cases in parallel on Dask and grow its results table.\n\n"
                             "A results folder per case under DIR/cases/, one row per case in DIR/results.parquet "
                             "and DIR/results.csv;\nresumable: the same command skips the finished cases.",
                             epilog="example: corneasim study run validation/studies/needle_speed.toml "
                             "--out results/needle-speed --workers 2", formatter_class=formatter)
    run.add_argument("study", type=Path, help="Study TOML file.")
    run.add_argument("--out", type=Path, required=True, metavar="DIR", help="Results folder of the study.")
    run.add_argument("--retry-failed", action="store_true", help="Run the cases recorded as failed again.")
    _engine_options(run)
    run.set_defaults(handler=run_command)

    report = actions.add_parser("report", help="Plots, sensitivity indices and a Markdown summary of a study.",
                                description="Write plots, sensitivity indices and a Markdown summary of a study.\n\n"
                                "DIR/report/: outputs against each parameter, Morris or Sobol' indices with "
                                "confidence intervals,\nthe ensemble's spread, report.md.",
                                epilog="example: corneasim study report results/needle-speed",
                                formatter_class=formatter)
    report.add_argument("directory", type=Path, metavar="DIR", help="Results folder of a study.")
    report.set_defaults(handler=report_command)

    calibrate = commands.add_parser(
        "calibrate", help="Fit a study's parameters to a measured curve (RMSE), candidates run in parallel.",
        description="Fit a study's parameters to a measured curve by minimising its RMSE.\n\n"
        "optuna over the parameters' bounds, candidates in parallel on Dask; prints the calibrated values "
        "as TOML\nand writes the fit plot.",
        epilog="example: corneasim calibrate validation/studies/calibrate_needle.toml --out results/calibration",
        formatter_class=formatter)
    calibrate.add_argument("study", type=Path, help="Study TOML file with a [calibration] table.")
    calibrate.add_argument("--out", type=Path, metavar="DIR",
                           help="Results folder (default results/<study file name>).")
    _engine_options(calibrate)
    calibrate.set_defaults(handler=calibrate_command)


def run_command(arguments) -> int:
    """Run the study; print the folder and the count of cases by status."""
    from corneasim.studies.runner import run_study

    try:
        table = run_study(arguments.study, arguments.out, workers=arguments.workers, scheduler=arguments.scheduler,
                          progress=not arguments.no_progress, retry_failed=arguments.retry_failed)
    except KeyboardInterrupt:
        print(f"corneasim: study interrupted; finished cases are in {arguments.out}; the same command "
              "resumes it", file=sys.stderr)
        return 130
    counts = table["status"].value_counts().to_dict()
    print(f"results: {arguments.out}/results.parquet ({len(table)} cases: "
          + ", ".join(f"{counts[status]} {status}" for status in sorted(counts)) + ")")
    for _, row in table[table["status"] == "failed"].head(5).iterrows():
        print(f"  {row['case']} failed: {row['error']}")
    return 0 if counts.get("failed", 0) == 0 else 1


def report_command(arguments) -> int:
    """Write the report of a study folder."""
    from corneasim.studies.report import write_report

    if not (arguments.directory / "study.toml").exists():
        raise InputError(f"{arguments.directory}: not a study folder (no study.toml)")
    path = write_report(arguments.directory)
    print(f"report: {path}")
    return 0


def calibrate_command(arguments) -> int:
    """Calibrate; print the TOML block of the calibrated values."""
    from corneasim.studies.calibrate import calibrate

    out = arguments.out or Path("results") / arguments.study.stem
    result = calibrate(arguments.study, out, workers=arguments.workers, scheduler=arguments.scheduler,
                       progress=not arguments.no_progress)
    print(result.toml, end="")
    print(f"fit plot: {result.plot}", file=sys.stderr)
    return 0
