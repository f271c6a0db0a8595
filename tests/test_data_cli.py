"""``corneasim data``: every sub-command runs; bad input is one line on stderr and exit code 2."""

import subprocess
import sys
from types import SimpleNamespace

import pytest

from corneasim.cli.main import main


@pytest.fixture
def run_cli(capsys):
    """Run ``corneasim data ARGS`` in-process; returns returncode, stdout, stderr."""

    def run(*arguments):
        try:
            main(["data", *arguments])
        except SystemExit as exit_:
            code = exit_.code
        else:
            code = 0
        captured = capsys.readouterr()
        return SimpleNamespace(returncode=code, stdout=captured.out, stderr=captured.err)

    return run


def test_entry_point_subprocess():
    result = subprocess.run([sys.executable, "-m", "corneasim.cli.main", "data", "show", "nope"],
                            capture_output=True, text=True)
    assert result.returncode == 2 and result.stderr.startswith("corneasim: error: unknown dataset 'nope'")
    assert result.stderr.strip().count("\n") == 0 and result.stdout == ""


def assert_one_line_error(result, *fragments):
    assert result.returncode == 2, result.stderr
    assert result.stdout == "" and "Traceback" not in result.stderr
    assert result.stderr.strip().count("\n") == 0
    for fragment in fragments:
        assert fragment in result.stderr


def test_list_names_every_dataset(run_cli):
    result = run_cli("list")
    assert result.returncode == 0, result.stderr
    for name in ("needle-insertion-force", "needle-insertion-gaussian-fit", "trephination-force",
                 "trephination-gaussian-fit", "porcine-eye-geometry"):
        assert name in result.stdout
    assert "15x5" in result.stdout


def test_show_prints_units_source_and_values(run_cli):
    result = run_cli("show", "trephination-force")
    assert result.returncode == 0, result.stderr
    assert "source: trephination paper" in result.stdout and "10^-2 N" in result.stdout
    assert "simulation_Fz_N [N]" in result.stdout and "time_s [s]" in result.stdout
    assert "0.144" in result.stdout  # 14.40e-2 N at 62.5 s


def test_show_csv_prints_the_raw_file(run_cli):
    result = run_cli("show", "porcine-eye-geometry", "--csv")
    assert result.returncode == 0
    assert result.stdout.startswith("# title:") and "26.50,11.20" in result.stdout


def test_show_a_user_file(run_cli, tmp_path):
    path = tmp_path / "curve.csv"
    path.write_text("depth_mm,force_N\n0,0\n0.1,0.02\n")
    result = run_cli("show", str(path))
    assert result.returncode == 0 and "force_N [N]" in result.stdout


def test_fit_recovers_eq14_from_its_own_samples(run_cli, tmp_path):
    import numpy as np

    from corneasim.analysis import gaussian_sum

    time = np.linspace(0.0, 70.0, 71)
    force = gaussian_sum(time, [0.10, 0.06], [62.36, 33.86], [22.04, 18.63])
    path = tmp_path / "fz.csv"
    path.write_text("time_s,Fz_N\n" + "".join(f"{float(t)!r},{float(f)!r}\n" for t, f in zip(time, force)))
    result = run_cli("fit", str(path), "--x", "time_s", "--y", "Fz_N", "--terms", "2", "--nonnegative")
    assert result.returncode == 0, result.stderr
    assert "a [N]  b [s]  c [s]" in result.stdout
    assert "0.06  33.86  18.63" in result.stdout and "0.1  62.36  22.04" in result.stdout


def test_compare_and_drops_run(run_cli):
    result = run_cli("compare", "needle-insertion-force", "--x", "depth_mm", "--y", "simulation_1mm_s_N",
                     "--against", "needle-insertion-force", "--exp-x", "depth_mm", "--exp-y", "experiment_1mm_s_N")
    assert result.returncode == 0, result.stderr
    # largest |simulation - experiment| in Table 2 at 1 mm/s: 0.53 vs 0.63 N at 0.7 mm
    assert "max_abs_error: 0.1 N at depth_mm = 0.7" in result.stdout and "n_points: 15" in result.stdout
    result = run_cli("drops", "needle-insertion-force", "--x", "depth_mm", "--force", "experiment_5mm_s_N",
                     "--noise-factor", "2")
    assert result.returncode == 0, result.stderr
    # the 5 mm/s experimental mean falls from 0.38 N (0.40 mm) to 0.15 N (0.45 mm)
    assert "at depth_mm = 0.4 mm: force 0.38 N falls by 0.23 N" in result.stdout


@pytest.mark.parametrize(
    "arguments, fragments",
    [
        (("show", "no-such-data"), ["unknown dataset 'no-such-data'", "needle-insertion-force"]),
        (("fit", "trephination-force", "--x", "time_s", "--y", "Fz"), ["unknown column 'Fz'"]),
        (("show", "missing.csv"), ["missing.csv: file not found"]),
        (("fit", "trephination-force", "--x", "time_s", "--y", "simulation_Fz_N", "--terms", "0"), ["n_terms"]),
        (("fit", "trephination-force", "--x", "time_s"), ["--y"]),
    ],
)
def test_bad_input_is_one_line_exit_2(run_cli, arguments, fragments):
    assert_one_line_error(run_cli(*arguments), *fragments)


def test_malformed_csv_names_file_and_line(run_cli, tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("# a comment\nstretch,nominal_stress_MPa\n1.0,0.0\n1.1\n")
    assert_one_line_error(run_cli("show", str(path)), "bad.csv: line 4", "expected 2")
    path.write_text("depth_mm,force_N\n0,zero\n")
    assert_one_line_error(run_cli("drops", str(path), "--x", "depth_mm", "--force", "force_N"),
                          "bad.csv: line 2", "column force_N", "'zero'")
