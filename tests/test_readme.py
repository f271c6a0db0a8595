"""The README's commands work as written.

Convention for README.md:

* a ```bash block is run: each line is one shell command (lines starting with ``#`` are
  comments) and must start with ``corneasim``; each block is one test that runs its lines in
  order in a temporary folder of its own, so a later line may use an earlier line's results
  (never another block's). Every command must exit 0. The blocks are tests of their own so
  that they run side by side on the suite's workers (``tests/conftest.py``).
  A line that redirects its output (``corneasim show needle > my-needle.toml``) runs in a
  shell with the installed ``corneasim`` script; the others run in this process through the
  command's parser and error path (:func:`corneasim.cli.main.dispatch`), which is what the
  script calls, without a new interpreter loading the kernels again for each line.
  The README keeps these at coarse size (coarse meshes, short end times): about 40 s of CPU
  here, most of it four coarse needle runs and 5 s of the coarse trephine.
* a ```python block is run as a script (``__main__``) in a temporary folder, in this process.
* a ```console block lists commands too long for a test (``make demo`` runs the default
  needle, 164,000 steps, about a minute; ``make test`` is this suite): they are checked, not
  run: the ``make`` target must exist and the ``corneasim`` command of its recipe must parse.
* every inline ``corneasim ...`` command (the tables, the prose: the paper-size runs, minutes
  each) must parse with the command-line parser, and every ``python PATH`` names a file of
  the repository; they are not run, for the same reason.
"""

import contextlib
import io
import os
import re
import runpy
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from cli_helpers import corneasim_here

from corneasim.cli.main import build_parser

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
BLOCKS = re.findall(r"```(\w+)\n(.*?)```", README, re.S)


def block_lines(kind: str) -> list[str]:
    """The command lines of every block of one kind, in order, comments and blank lines left out."""
    return [line.strip() for language, text in BLOCKS if language == kind
            for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")]


def parses(command: str) -> None:
    """Parse a ``corneasim ...`` command line (without running it); argparse errors exit."""
    words = shlex.split(command.split(" > ")[0])
    assert words[0] == "corneasim", command
    arguments = build_parser().parse_args(words[1:])
    assert callable(arguments.handler), command


def corneasim_command() -> list[str]:
    """The installed console script next to this interpreter, else the module entry point."""
    script = Path(sys.executable).parent / "corneasim"
    return [str(script)] if script.exists() else [sys.executable, "-c", "from corneasim.cli.main import main; main()"]


def test_the_readme_has_blocks_of_each_kind():
    kinds = {language for language, _ in BLOCKS}
    assert {"bash", "console", "python"} <= kinds
    assert set(kinds) <= {"bash", "console", "python"}, "a block of another kind is neither run nor checked"


RUN = [(index, language) for index, (language, _) in enumerate(BLOCKS) if language in ("bash", "python")]
"""The blocks that run: (position among all blocks, language)."""


def test_a_bash_line_runs_in_a_shell_and_every_line_is_a_corneasim_command():
    lines = block_lines("bash")
    assert any(" > " in line for line in lines), "no line of the README runs in a shell"
    for line in lines:
        assert line.startswith("corneasim "), f"a bash block runs corneasim commands only: {line}"
        parses(line)


@pytest.mark.parametrize("index", [index for index, _ in RUN], ids=[f"{language}-{index}" for index, language in RUN])
def test_block_runs(index, tmp_path, monkeypatch):
    language, text = BLOCKS[index]
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("COLUMNS", "100")
    if language == "python":
        script = tmp_path / "readme_block.py"
        script.write_text(text)
        with contextlib.redirect_stdout(io.StringIO()):
            runpy.run_path(str(script), run_name="__main__")
        return
    environment = dict(os.environ, COLUMNS="100")
    environment["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), environment.get("PATH", "")])
    prefix = " ".join(shlex.quote(word) for word in corneasim_command())
    lines = [line.strip() for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")]
    for line in lines:
        assert line.startswith("corneasim "), f"a bash block runs corneasim commands only: {line}"
        if " > " in line:
            done = subprocess.run(prefix + line.removeprefix("corneasim"), shell=True, cwd=tmp_path,
                                  env=environment, capture_output=True, text=True, timeout=300)
        else:
            done = corneasim_here(*shlex.split(line)[1:])
        assert done.returncode == 0, f"{line}\n{done.stderr[-2000:]}"


def test_console_blocks_name_make_targets_whose_commands_parse():
    makefile = (ROOT / "Makefile").read_text()
    lines = block_lines("console")
    assert lines
    for line in lines:
        words = line.split()
        assert words[0] == "make" and len(words) == 2, line
        recipe = re.search(rf"^{words[1]}:.*\n((?:\t.*\n)+)", makefile, re.M)
        assert recipe, f"no target {words[1]} in the Makefile"
        for step in recipe.group(1).split("\n"):
            if "corneasim " in step:
                parses("corneasim " + step.split("corneasim ", 1)[1])


INLINE = re.findall(r"`((?:corneasim|python) [^`]+)`", README)


@pytest.mark.parametrize("command", INLINE)
def test_inline_commands_parse_or_name_a_file(command):
    if command.startswith("corneasim "):
        parses(command)
        return
    words = command.split()
    path = words[3] if words[1:3] == ["-m", "pytest"] else words[1]
    assert (ROOT / path).is_file(), command
