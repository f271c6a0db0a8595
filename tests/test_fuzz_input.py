"""Fuzzed input through the command line: every case is a valid run start or one line with exit 2.

The built-in scenarios' values and types are mutated, their TOML bytes and a small mesh
file's bytes corrupted, and ``--set``, ``--speed`` and ``--depth`` given odd values (hypothesis,
derandomized: the same cases on every run). Each case goes through the CLI's parser and
error path (:func:`corneasim.cli.main.dispatch`) up to the start of the run
(:func:`corneasim.cli.run.prepare_run`: everything is checked, nothing is run) or, for a
mesh file, through ``corneasim mesh FILE``. Required of every case: exit 0 or 2; with 2 one
line on stderr; no traceback (any other exception fails the test); no file written; a
default results folder inside the results root.
"""

import contextlib
import io
import os
import tomllib
from collections import Counter
from pathlib import Path

import pytest
import tomli_w
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from corneasim.cli.main import build_parser, dispatch
from corneasim.cli.run import RESULTS_ROOT, prepare_run
from corneasim.scenarios._registry import scenario_text

OUTCOMES = Counter()
FUZZ = settings(derandomize=True, deadline=None, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
BUILTIN = ("needle", "trephine")
TABLES = {name: tomllib.loads(scenario_text(name)) for name in BUILTIN}
DELETE = object()

INP = b"""*NODE
1, 0.0, 0.0
2, 1.0, 0.0
3, 2.0, 0.0
4, 0.0, 1.0
5, 1.0, 1.0
6, 2.0, 1.0
*ELEMENT, TYPE=CAX4R, ELSET=tissue
1, 1, 2, 5, 4
2, 2, 3, 6, 5
*NSET, NSET=bottom
1, 2, 3
*SURFACE, TYPE=ELEMENT, NAME=top
1, S3
2, S3
"""


def _leaves(table, path=()):
    """Dotted paths of every value of nested tables (list entries by index)."""
    for key, value in table.items():
        here = (*path, key)
        if isinstance(value, dict):
            yield from _leaves(value, here)
        elif isinstance(value, list) and value and all(isinstance(item, dict) for item in value):
            for index, item in enumerate(value):
                yield from _leaves(item, (*here, index))
        else:
            yield here


LEAVES = {name: sorted(_leaves(TABLES[name]), key=str) for name in BUILTIN}
KEYS = sorted({".".join(str(p) for p in leaf) for name in BUILTIN for leaf in LEAVES[name] if
               all(isinstance(p, str) for p in leaf)})

values = st.one_of(
    st.booleans(), st.integers(-10**6, 10**6), st.sampled_from([0, -1, 2**62, -2**62]),
    st.floats(allow_nan=True, allow_infinity=True), st.sampled_from([0.0, -0.0, 1e-300, 1e300, float("inf")]),
    st.text(max_size=12), st.sampled_from(["20", "../../x", "/abs/path", "", "true", "inf"]),
    st.lists(st.one_of(st.integers(-5, 5), st.floats(-5, 5)), max_size=3),
    st.dictionaries(st.text(max_size=4), st.integers(-3, 3), max_size=2), st.just(DELETE))


@pytest.fixture(scope="module")
def place(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz")


def _files(folder: Path) -> set:
    return {str(path.relative_to(folder)) for path in folder.rglob("*")}


def _prepare_only(arguments) -> int:
    plan = prepare_run(arguments)
    if arguments.out is None:  # the default folder never leaves the results root
        assert plan.out_dir.parent == RESULTS_ROOT and not plan.out_dir.name.startswith("."), plan.out_dir
    return 0


def outcome(place: Path, argv: list[str], kind: str) -> int:
    """The exit code of ``corneasim ARGV`` (a run only prepared), checked as the module notes say."""
    before = _files(place)
    previous = os.getcwd()
    stderr = io.StringIO()
    os.chdir(place)
    try:
        with contextlib.redirect_stderr(stderr), contextlib.redirect_stdout(io.StringIO()):
            try:
                arguments = build_parser().parse_args(argv)
                handler = _prepare_only if arguments.command == "run" else arguments.handler
                code = dispatch(handler, arguments)
            except SystemExit as exit_:  # the parser's own errors
                code = exit_.code
    finally:
        os.chdir(previous)
    assert _files(place) == before, "a case wrote a file"
    text = stderr.getvalue()
    assert code in (0, 2), (argv, code, text)
    if code == 2:
        assert text.startswith("corneasim: error: ") and text.count("\n") == 1, (argv, text)
    OUTCOMES[(kind, "valid" if code == 0 else "exit 2")] += 1
    return code


def _set(table, path, value):
    for part in path[:-1]:
        table = table[part]
    if value is DELETE:
        del table[path[-1]]
    else:
        table[path[-1]] = value


@settings(FUZZ, max_examples=250)
@given(name=st.sampled_from(BUILTIN), data=st.data())
def test_mutated_values_and_types(place, name, data):
    tables = tomllib.loads(scenario_text(name))
    for _ in range(data.draw(st.integers(1, 3))):
        leaf = data.draw(st.sampled_from(LEAVES[name]))
        try:
            _set(tables, leaf, data.draw(values))
        except (KeyError, IndexError, TypeError):
            pass  # a parent changed by an earlier mutation
    if data.draw(st.booleans()):
        tables[data.draw(st.text(min_size=1, max_size=6))] = data.draw(values.filter(lambda v: v is not DELETE))
    try:
        text = tomli_w.dumps(tables)
    except (TypeError, ValueError):
        assume(False)
    (place / "case.toml").write_text(text)
    outcome(place, ["run", "case.toml", "--no-progress"], "values")


@settings(FUZZ, max_examples=150)
@given(name=st.sampled_from(BUILTIN), where=st.floats(0, 1), cut=st.integers(0, 40), chunk=st.binary(max_size=12))
def test_corrupted_toml_bytes(place, name, where, cut, chunk):
    original = scenario_text(name).encode()
    position = int(where * len(original))
    (place / "case.toml").write_bytes(original[:position] + chunk + original[position + cut:])
    outcome(place, ["run", "case.toml", "--no-progress"], "toml bytes")


@settings(FUZZ, max_examples=60)
@given(name=st.sampled_from(BUILTIN), key=st.sampled_from(KEYS), raw=st.text(max_size=10),
       number=st.floats(allow_nan=True, allow_infinity=True), option=st.sampled_from(["--speed", "--depth", None]))
def test_odd_command_line_values(place, name, key, raw, number, option):
    argv = ["run", name, "--no-progress", "--set", f"{key}={raw}"]
    if option is not None:
        argv += [option, repr(number)]
    outcome(place, argv, "options")


@settings(FUZZ, max_examples=150)
@given(suffix=st.sampled_from([".inp", ".vtu"]), where=st.floats(0, 1), cut=st.integers(0, 30),
       chunk=st.binary(max_size=10))
def test_corrupted_mesh_bytes(place, vtu_bytes, suffix, where, cut, chunk):
    original = INP if suffix == ".inp" else vtu_bytes
    position = int(where * len(original))
    path = place / f"mesh{suffix}"
    path.write_bytes(original[:position] + chunk + original[position + cut:])
    outcome(place, ["mesh", path.name], "mesh bytes")


@pytest.fixture(scope="module")
def vtu_bytes(place):
    from corneasim.mesh._io import read_mesh, write_mesh

    (place / "base.inp").write_bytes(INP)
    write_mesh(read_mesh(place / "base.inp"), place / "base.vtu")
    data = (place / "base.vtu").read_bytes()
    for name in ("base.inp", "base.vtu"):
        (place / name).unlink()
    return data


def test_the_uncorrupted_inputs_are_valid_and_enough_cases_ran(place, vtu_bytes):
    (place / "mesh.vtu").write_bytes(vtu_bytes)
    assert outcome(place, ["mesh", "mesh.vtu"], "check") == 0
    for name in BUILTIN:
        assert outcome(place, ["run", name, "--no-progress"], "check") == 0
    total = sum(count for (kind, _), count in OUTCOMES.items() if kind != "check")
    print(dict(OUTCOMES), total)
    if total:  # the whole module ran (not a -k selection)
        assert total >= 500, dict(OUTCOMES)
