"""``corneasim data``: Experimental datasets from the papers."""

from __future__ import annotations

import argparse

HELP = "Experimental datasets from the papers."


def register(commands: argparse._SubParsersAction) -> None:
    """Add the ``data`` command group and its sub-commands."""
    group = commands.add_parser("data", help=HELP, description=HELP)
    group.add_subparsers(dest="data_command", metavar="COMMAND", required=True)
