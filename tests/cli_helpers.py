"""Running the ``corneasim`` command as a user does: in a subprocess (exit codes, signals, the
entry point) or, where the process adds nothing, in this one through the same parser and error path."""

import contextlib
import io
import subprocess
import sys

from corneasim.cli.main import build_parser, dispatch


def command(*arguments) -> list[str]:
    """The argument vector of ``corneasim ARGUMENTS`` with this interpreter."""
    return [sys.executable, "-m", "corneasim.cli.main", *arguments]


def corneasim(*arguments, timeout: float = 600) -> subprocess.CompletedProcess:
    """Run ``corneasim ARGUMENTS`` in a subprocess; text stdout and stderr captured."""
    return subprocess.run(command(*arguments), capture_output=True, text=True, timeout=timeout)


def corneasim_here(*arguments) -> subprocess.CompletedProcess:
    """Run ``corneasim ARGUMENTS`` in this process: the parser and :func:`corneasim.cli.main.dispatch`,
    the error path :func:`corneasim.cli.main.main` ends in (its exit code is the return code here);
    text stdout and stderr captured. The signal handlers that ``main`` installs are left alone."""
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        try:
            parsed = build_parser().parse_args([str(argument) for argument in arguments])
            code = dispatch(parsed.handler, parsed)
        except SystemExit as exit_:  # the parser's own errors and --help, --version
            code = exit_.code if isinstance(exit_.code, int) else 1 if exit_.code else 0
    return subprocess.CompletedProcess(["corneasim", *map(str, arguments)], code, stdout.getvalue(),
                                       stderr.getvalue())
