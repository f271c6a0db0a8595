"""``corneasim material``: Material laws: stability checks, curves, fitting, presets."""

from __future__ import annotations

import argparse

HELP = "Material laws: stability checks, curves, fitting, presets."


def register(commands: argparse._SubParsersAction) -> None:
    """Add the ``material`` command group and its sub-commands."""
    group = commands.add_parser("material", help=HELP, description=HELP)
    group.add_subparsers(dest="material_command", metavar="COMMAND", required=True)
