"""Running the ``corneasim`` command in a subprocess, as a user does: exit codes and stderr."""

import subprocess
import sys


def command(*arguments) -> list[str]:
    """The argument vector of ``corneasim ARGUMENTS`` with this interpreter."""
    return [sys.executable, "-m", "corneasim.cli.main", *arguments]


def corneasim(*arguments, timeout: float = 600) -> subprocess.CompletedProcess:
    """Run ``corneasim ARGUMENTS``; text stdout and stderr captured."""
    return subprocess.run(command(*arguments), capture_output=True, text=True, timeout=timeout)
