"""The command line: help works, bad input is one line and exit code 2."""

from cli_helpers import corneasim


def test_help_and_version():
    assert corneasim("--help").returncode == 0
    result = corneasim("--version")
    assert result.returncode == 0 and "corneasim" in result.stdout


def test_unknown_command_is_one_line_exit_2():
    result = corneasim("no-such-command")
    assert result.returncode == 2
    assert result.stderr.strip().count("\n") == 0
    assert "no-such-command" in result.stderr
    assert "Traceback" not in result.stderr
