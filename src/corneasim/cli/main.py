"""Entry point of the ``corneasim`` command.

Every command group lives in its own module (``material``, ``data``, ``mesh``)
with a ``register(commands)`` function that adds its sub-parsers; each leaf
sub-parser sets ``handler`` (a function of the parsed arguments). :func:`main`
turns input errors (bad arguments, :class:`~corneasim.errors.InputError`) into
one line on stderr and exit code 2, so no user mistake ends in a traceback.
"""

from __future__ import annotations

import argparse
import sys

from corneasim import __version__
from corneasim.cli import compare, data, material, mesh, run, study, surrogate
from corneasim.errors import EXIT_INPUT_ERROR, InputError

GROUPS = (run, material, data, mesh, compare, study, surrogate)


class OneLineErrorParser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line and exit code 2."""

    def error(self, message: str) -> None:  # noqa: D102 - argparse API
        fail(f"{self.prog}: {message}")


def fail(message: str) -> None:
    """Print one error line on stderr and exit with status 2."""
    print(f"corneasim: error: {message}", file=sys.stderr)
    raise SystemExit(EXIT_INPUT_ERROR)


def build_parser() -> argparse.ArgumentParser:
    """The full command-line parser (all groups registered)."""
    parser = OneLineErrorParser(
        prog="corneasim",
        description="Simulate needle insertion and trephination of the cornea "
        "(units: mm, s, N, MPa, tonne/mm^3).",
        epilog="example: corneasim run needle --preset coarse --out results/needle-coarse\n\n"
               "exit codes: 0 ok, 1 failed simulation (reason in summary.json), 2 bad input, 130 interrupted",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"corneasim {__version__}")
    commands = parser.add_subparsers(
        dest="command", metavar="COMMAND", required=True, parser_class=OneLineErrorParser
    )
    for group in GROUPS:
        group.register(commands)
    return parser


def main(argv: list[str] | None = None) -> None:
    """Run the CLI; input errors exit 2 with one line, Ctrl-C exits 130."""
    arguments = build_parser().parse_args(argv)
    try:
        status = arguments.handler(arguments)
    except InputError as error:
        fail(str(error))
    except KeyboardInterrupt:
        print("corneasim: interrupted", file=sys.stderr)
        raise SystemExit(130) from None
    raise SystemExit(status or 0)


if __name__ == "__main__":
    main()
