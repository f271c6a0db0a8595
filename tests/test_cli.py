"""The command line: help works, bad input is one line and exit code 2."""

import subprocess
import sys


def run_cli(*arguments):
    return subprocess.run(
        [sys.executable, "-m", "corneasim.cli.main", *arguments], capture_output=True, text=True
    )


def test_help_and_version():
    assert run_cli("--help").returncode == 0
    result = run_cli("--version")
    assert result.returncode == 0 and "corneasim" in result.stdout


def test_unknown_command_is_one_line_exit_2():
    result = run_cli("no-such-command")
    assert result.returncode == 2
    assert result.stderr.strip().count("\n") == 0
    assert "no-such-command" in result.stderr
    assert "Traceback" not in result.stderr
