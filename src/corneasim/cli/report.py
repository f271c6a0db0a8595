"""``corneasim report``: a results folder's ``report.html``, one self-contained page."""

from __future__ import annotations

import argparse
from pathlib import Path

HELP = "Write report.html, the run on one self-contained page, into a results folder."

DESCRIPTION = """RESULTS_DIR/report.html holds the scenario's key inputs, the force plots with the
experiment, the validation scores against their targets, the punctures, the energies over time,
the stress maps and the run's platform and wall time, with every figure embedded (one file, no
external assets). `corneasim run` writes it at the end of every run; this command makes it again,
e.g. for a folder written by an older version."""


def register(commands: argparse._SubParsersAction) -> None:
    """Add the ``report`` command."""
    parser = commands.add_parser("report", help=HELP, description=HELP + "\n\n" + DESCRIPTION,
                                 epilog="example: corneasim report results/needle",
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("results_dir", type=Path, metavar="RESULTS_DIR",
                        help="results folder of a run (holds summary.json)")
    parser.set_defaults(handler=run)


def run(arguments) -> int:
    """Write the report and print its path."""
    from corneasim.output import write_run_report

    print(f"written: {write_run_report(arguments.results_dir)}")
    return 0
