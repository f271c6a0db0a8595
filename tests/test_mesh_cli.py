"""``corneasim mesh``: builds, reports, writes; bad input is one line and exit code 2."""

import contextlib
import io
import subprocess
import sys
from types import SimpleNamespace

import pytest

from corneasim.cli.main import main
from corneasim.mesh._io import read_mesh


def run_cli(*arguments):
    """Run ``corneasim mesh ARGUMENTS`` in this process; returns returncode, stdout, stderr."""
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        try:
            main(["mesh", *arguments])
            code = 0
        except SystemExit as exit_:
            code = exit_.code
    return SimpleNamespace(returncode=code, stdout=stdout.getvalue(), stderr=stderr.getvalue())


def test_the_installed_command_exits_2_with_one_line():
    result = subprocess.run([sys.executable, "-m", "corneasim.cli.main", "mesh", "no-such-eye"],
                            capture_output=True, text=True)
    assert result.returncode == 2 and result.stderr.count("\n") == 1 and "no-such-eye" in result.stderr


def test_needle_mesh_report_file_and_preview(tmp_path):
    out, picture = tmp_path / "needle.inp", tmp_path / "needle.png"
    result = run_cli("needle", "--preset", "coarse", "--out", str(out), "--preview", str(picture),
                     "--wave-speed", "1e6")
    assert result.returncode == 0, result.stderr
    assert "scaled Jacobian" in result.stdout and "stable time step" in result.stdout
    assert "refined area" in result.stdout
    assert read_mesh(out).axisymmetric
    assert picture.read_bytes()[:4] == b"\x89PNG"


def test_trephine_strategy_and_reimport(tmp_path):
    out = tmp_path / "eye.vtu"
    result = run_cli("trephine", "--strategy", "vertical", "--preset", "coarse", "--out", str(out))
    assert result.returncode == 0, result.stderr
    mesh = read_mesh(out)
    assert mesh.cell_type == "hexahedron" and "symmetry_plane" in mesh.node_sets
    again = run_cli(str(out))
    assert again.returncode == 0 and f"elements {mesh.n_elements}" in again.stdout


def test_geometry_file_changes_the_eye(tmp_path):
    geometry = tmp_path / "human.toml"
    geometry.write_text("central_thickness = 0.52\nperipheral_thickness = 0.67\nanterior_radius = 7.7\n")
    out = tmp_path / "human.inp"
    assert run_cli("needle", "--preset", "coarse", "--geometry", str(geometry), "--out", str(out)).returncode == 0
    z = read_mesh(out).points[:, 1]
    assert z.max() == pytest.approx(0.0)


@pytest.mark.parametrize(
    "arguments, fragment",
    [
        (["nothing"], "nothing"),
        (["trephine", "--strategy", "diagonal"], "diagonal"),
        (["needle", "--preset", "coarse", "--out", "eye.obj"], "unknown mesh format"),
        (["inverted.inp"], "inverted"),
        (["bad-geometry.toml"], None),
    ],
)
def test_bad_input_is_one_line_and_exit_2(tmp_path, monkeypatch, arguments, fragment):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "inverted.inp").write_text("*NODE\n1,0,0\n2,1,0\n3,1,1\n4,0,1\n*ELEMENT, TYPE=CAX4R\n1, 1, 2, 4, 3\n")
    (tmp_path / "geometry.toml").write_text("anterior_radius = -1\n")
    if arguments == ["bad-geometry.toml"]:
        arguments, fragment = ["needle", "--geometry", "geometry.toml"], "anterior_radius"
    result = run_cli(*arguments)
    assert result.returncode == 2
    assert result.stderr.strip().count("\n") == 0
    assert fragment in result.stderr and "Traceback" not in result.stderr


def test_preview_of_a_foreign_mesh(tmp_path):
    from test_mesh_quality import CUBE, hex_mesh

    from corneasim.mesh._io import write_mesh

    cube = write_mesh(hex_mesh(CUBE), tmp_path / "cube.vtu")
    picture = tmp_path / "cube.png"
    result = run_cli(str(cube), "--preview", str(picture))
    assert result.returncode == 0, result.stderr
    assert "elements 1 (hexahedron)" in result.stdout and picture.stat().st_size > 1000
