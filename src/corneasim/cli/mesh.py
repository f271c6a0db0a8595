"""``corneasim mesh``: Eye geometry and meshes: build, check, export, preview."""

from __future__ import annotations

import argparse

HELP = "Eye geometry and meshes: build, check, export, preview."


def register(commands: argparse._SubParsersAction) -> None:
    """Add the ``mesh`` command group and its sub-commands."""
    group = commands.add_parser("mesh", help=HELP, description=HELP)
    group.add_subparsers(dest="mesh_command", metavar="COMMAND", required=True)
