"""Every leaf command's ``--help`` states its purpose in one line and gives an example that parses."""

import argparse
import shlex

import pytest

from corneasim.cli.main import build_parser


def leaf_parsers(parser: argparse.ArgumentParser, path: tuple[str, ...] = ()):
    """(command path, parser) of every parser without sub-commands, found by walking the tree."""
    subcommands = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if not subcommands:
        yield path, parser
        return
    for action in subcommands:
        for name, child in action.choices.items():
            yield from leaf_parsers(child, path + (name,))


LEAVES = list(leaf_parsers(build_parser()))


def test_the_tree_has_every_command_group():
    names = {" ".join(path) for path, _ in LEAVES}
    assert {"run", "show", "mesh", "compare-meshes", "material check", "data show"} <= names


@pytest.mark.parametrize("path,parser", LEAVES, ids=[" ".join(p) for p, _ in LEAVES])
def test_help_has_a_purpose_line_and_an_example(path, parser):
    description = (parser.description or "").strip()
    assert description, f"corneasim {' '.join(path)}: no description"
    purpose = description.splitlines()[0]
    assert purpose.endswith(".") and len(purpose) <= 110, purpose
    examples = [line for line in (parser.epilog or "").splitlines() if line.startswith("example: ")]
    assert len(examples) == 1, f"corneasim {' '.join(path)}: expected one 'example:' line in the epilog"
    command = shlex.split(examples[0].removeprefix("example: ").split(">")[0])
    assert command[0] == "corneasim" and tuple(command[1:1 + len(path)]) == path
    arguments = build_parser().parse_args(command[1:])
    assert callable(arguments.handler)
    text = parser.format_help()
    assert purpose in text and examples[0] in text
