"""Entry point of the ``corneasim`` command.

Every command group lives in its own module (``material``, ``data``, ``mesh``)
with a ``register(commands)`` function that adds its sub-parsers; each leaf
sub-parser sets ``handler`` (a function of the parsed arguments). :func:`main`
turns input errors (bad arguments, :class:`~corneasim.errors.InputError`, a file
that cannot be read or written) into one line on stderr and exit code 2, so no user
mistake ends in a traceback; Ctrl-C, SIGTERM and SIGHUP end it with exit code 130.
"""

from __future__ import annotations

import argparse
import sys

from corneasim import __version__
from corneasim.cli import compare, data, material, mesh, report, run, study, surrogate
from corneasim.errors import EXIT_INPUT_ERROR, EXIT_INTERRUPTED, InputError
from corneasim.scenarios._stopping import stop_signals_interrupt

GROUPS = (run, material, data, mesh, compare, report, study, surrogate)


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
    """Run the CLI; input errors exit 2 with one line, Ctrl-C, SIGTERM and SIGHUP exit 130."""
    stop_signals_interrupt()
    arguments = build_parser().parse_args(argv)
    raise SystemExit(dispatch(arguments.handler, arguments))


def dispatch(handler, arguments) -> int:
    """``handler(arguments)`` through the CLI's error path; returns the exit code.

    An :class:`InputError` or a file that cannot be read or written (:class:`OSError`) is one
    line on stderr and 2; an interruption is 130.
    """
    try:
        return handler(arguments) or 0
    except InputError as error:
        message = str(error)
    except OSError as error:
        where = f"{error.filename}: " if error.filename else ""
        message = f"{where}{error.strerror or type(error).__name__}"
    except KeyboardInterrupt:
        print("corneasim: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    print(f"corneasim: error: {' '.join(message.split())}", file=sys.stderr)
    return EXIT_INPUT_ERROR


if __name__ == "__main__":
    main()
