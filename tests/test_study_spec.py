"""Study files: bad input is one line naming the key, exit code 2, before any case runs."""

from __future__ import annotations

from pathlib import Path

import pytest

from corneasim.cli.main import main as cli_main
from corneasim.errors import InputError
from corneasim.studies.outputs import check_path
from corneasim.studies.spec import LogUniform, TruncatedNormal, ValueRange, read_study

MINIMAL = """\
scenario = "needle"
overrides = { "mesh.preset" = "coarse", "solver.end_time" = 0.3 }

[design]
kind = "grid"            # grid | latin-hypercube | sobol | morris | realizations

[parameters]
"instrument.motion.insertion.rate" = [1.0, 5.0]
"instrument.shape.diameter" = [0.15, 0.2]

[outputs]
peak_force_N = "peak_force_N"
"""


def test_the_minimal_study_file_reads_as_written(tmp_path):
    path = tmp_path / "minimal.toml"
    path.write_text(MINIMAL)
    study, base_dir, tables = read_study(path)
    assert study.design.kind == "grid"
    assert study.parameters["instrument.shape.diameter"] == [0.15, 0.2]
    assert study.outputs == {"peak_force_N": "peak_force_N"}
    assert base_dir == tmp_path.resolve()
    assert tables["overrides"]["solver.end_time"] == 0.3


def test_parameters_of_every_form_are_parsed():
    study, _, _ = read_study({
        "scenario": "needle", "design": {"kind": "latin-hypercube", "samples": 4},
        "parameters": {"a.b": {"low": 1.0, "high": 2.0, "steps": 3, "scale": "log"},
                       "a.c": {"distribution": "log-uniform", "low": 0.1, "high": 1.0},
                       "a.d": {"distribution": "truncated-normal", "mean": 1.0, "std": 0.2, "low": 0.5, "high": 1.5}},
        "outputs": {"peak": "peak_force_N"}})
    assert isinstance(study.parameters["a.b"], ValueRange)
    assert isinstance(study.parameters["a.c"], LogUniform)
    assert isinstance(study.parameters["a.d"], TruncatedNormal)


@pytest.mark.parametrize("tables, expected", [
    ({"bogus": 1}, "bogus: unknown key"),
    ({"design": {"kind": "grid", "stepz": 2}}, "design.stepz: unknown key"),
    ({"parameters": {"a.b": {"distribution": "uniform", "low": 2.0, "high": 1.0}}, "design": {"kind": "morris",
      "samples": 2}}, "parameters.a.b: uniform distribution needs low < high"),
    ({"parameters": {"a.b": {"distribution": "log-uniform", "low": 0.0, "high": 1.0}}},
     "parameters.a.b: log-uniform distribution needs 0 < low < high"),
    ({"parameters": {"a.b": {"distribution": "normal", "mean": 1.0, "std": -1.0}}}, "needs std > 0"),
    ({"parameters": {"a.b": {"distribution": "cauchy", "low": 0.0, "high": 1.0}}}, "parameters.a.b"),
    ({"parameters": {"a.b": {"low": 0.0, "high": 1.0, "stepz": 3}}}, "parameters.a.b.stepz: unknown key"),
    ({"design": {"kind": "sobol", "samples": 6}, "parameters": {"a.b": {"low": 0.0, "high": 1.0}}},
     "sobol needs a power of 2"),
    ({"parameters": {"a.b": [1, 2]}, "design": {"kind": "latin-hypercube", "samples": 3}}, "not a list of values"),
    ({"outputs": {"peak": {"curve": "force_N", "x": "depth_mm", "at": [0.2, 0.1]}}}, "outputs.peak.at"),
    ({"design": {"kind": "list"}}, "design: cases: a list design needs its cases"),
    ({"design": {"kind": "grid", "cases": [{"a.b": 1}]}}, "only a list design takes them"),
    ({"design": {"kind": "list", "cases": []}}, "a list design needs at least one case"),
    ({"design": {"kind": "list", "cases": [{"a.b": 1}]}, "parameters": {"a.c": [1, 2]}},
     "parameters: a list design takes its values from design.cases"),
    ({"design": {"kind": "list", "cases": [{"a.b": 1}]}, "overrides": {"a.b": 2}},
     "design.cases[0].a.b: also a fixed override"),
])
def test_bad_study_tables_are_one_line_naming_the_key(tables, expected):
    base = {"scenario": "needle", "outputs": {"peak": "peak_force_N"}}
    with pytest.raises(InputError) as error:
        read_study({**base, **tables})
    message = str(error.value)
    assert expected in message and "\n" not in message


@pytest.mark.parametrize("path, kind", [("peak_force_N", "needle"), ("validation.rmse_N", "needle"),
                                        ("punctures.0.depth_mm", "needle"), ("run.preload.out_of_balance", "needle"),
                                        ("peak_fc_N", "trephine"), ("reactions.base_force_N", "general")])
def test_summary_paths_that_a_kind_writes_are_accepted(path, kind):
    check_path(path, kind, "outputs.x")


@pytest.mark.parametrize("path, kind, expected", [
    ("peak_forse_N", "needle", "'peak_forse_N' is not in a needle scenario's summary.json"),
    ("validation.rmse", "needle", "validation has"),
    ("punctures.depth_mm", "needle", "punctures is a list"),
    ("peak_force_N", "trephine", "not in a trephine"),
])
def test_summary_paths_that_do_not_exist_are_refused(path, kind, expected):
    with pytest.raises(InputError, match=expected):
        check_path(path, kind, "outputs.x")


@pytest.mark.parametrize("change, expected", [
    (MINIMAL.replace('kind = "grid"', 'kind = "grid"\nlevls = 3'), "design.levls: unknown key"),
    (MINIMAL.replace('[1.0, 5.0]', '{ distribution = "uniform", low = 5.0, high = 1.0 }').replace(
        'kind = "grid"', 'kind = "latin-hypercube"\nsamples = 4').replace('[0.15, 0.2]', '{ low = 0.15, high = 0.2 }'),
     "parameters.instrument.motion.insertion.rate: uniform distribution needs low < high"),
    (MINIMAL.replace('peak_force_N = "peak_force_N"', 'peak = "validation.rmse_mN"'), "outputs.peak: 'validation.rmse_mN'"),
    (MINIMAL.replace('"instrument.shape.diameter"', '"instrument.shape.diametre"'), "diametre"),
])
def test_the_command_refuses_a_bad_study_with_one_line_and_exit_2_before_any_case(tmp_path, capsys, change,
                                                                                   expected):
    path = tmp_path / "study.toml"
    path.write_text(change)
    out = tmp_path / "out"
    with pytest.raises(SystemExit) as stop:
        cli_main(["study", "run", str(path), "--out", str(out)])
    assert stop.value.code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and expected in lines[0], lines
    assert not (out / "cases").exists() and not (out / "results.parquet").exists()


@pytest.mark.parametrize("arguments", [["study", "run"], ["study", "report"], ["calibrate"]])
def test_every_study_command_has_a_purpose_and_an_example(capsys, arguments):
    with pytest.raises(SystemExit):
        cli_main([*arguments, "--help"])
    text = capsys.readouterr().out
    assert "example: corneasim " + " ".join(arguments) in text


def test_the_studies_in_validation_are_valid():
    folder = Path(__file__).resolve().parents[1] / "validation" / "studies"
    files = sorted(folder.glob("*.toml"))
    assert files
    for path in files:
        read_study(path)
