"""Result files under faults: a torn last row cut anywhere is dropped, line endings are LF, modes follow the umask."""

import os
import stat

import pytest

from corneasim.output._files import HistoryWriter, atomic_write_text, file_mode, trim_table, write_json

HEADER = "time_s,depth_mm,force_N"
ROWS = ["0.0,0.0,0.0", "0.5,0.25,0.0123", "1.0,0.5,0.0456"]


def _table(rows, last=""):
    return (HEADER + "\n" + "".join(row + "\n" for row in rows) + last).encode()


@pytest.mark.parametrize("cut", range(len("1.5,0.75,0.0789")))
def test_a_row_torn_at_any_character_is_dropped_and_the_rest_kept_byte_for_byte(tmp_path, cut):
    path = tmp_path / "history.csv"
    path.write_bytes(_table(ROWS, "1.5,0.75,0.0789"[:cut]))  # killed while writing the fourth row
    assert trim_table(path, None) == len(ROWS)
    assert path.read_bytes() == _table(ROWS)


def test_rows_after_the_resume_time_go_and_crlf_becomes_lf(tmp_path):
    path = tmp_path / "history.csv"
    path.write_bytes((HEADER + "\r\n" + "".join(row + "\r\n" for row in ROWS)).encode())
    assert trim_table(path, 0.5) == 2
    assert path.read_bytes() == _table(ROWS[:2])


def test_a_row_with_a_field_missing_or_a_torn_header_is_repaired(tmp_path):
    path = tmp_path / "history.csv"
    path.write_bytes(_table(ROWS[:2] + ["1.0,0.5"]))  # complete line, one field short
    assert trim_table(path, None) == 2
    path.write_bytes(b"time_s,dep")  # killed while writing the header
    assert trim_table(path, None, HEADER.split(",")) == 0
    assert path.read_bytes() == (HEADER + "\n").encode()


def test_history_writer_uses_lf_and_resumes_onto_a_torn_file(tmp_path):
    path = tmp_path / "history.csv"
    with HistoryWriter(path, HEADER.split(",")) as writer:
        for row in ROWS[:2]:
            writer.append(dict(zip(HEADER.split(","), map(float, row.split(",")))))
    assert b"\r" not in path.read_bytes()
    with path.open("ab") as handle:
        handle.write(b"0.7")  # a kill inside the first field of the next row
    with HistoryWriter(path, HEADER.split(","), resume=True, resume_time=0.5) as writer:
        writer.append({"time_s": 1.0, "depth_mm": 0.5, "force_N": 0.0456})
    assert path.read_bytes() == _table(ROWS)


@pytest.mark.parametrize("umask, expected", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_atomic_writes_get_the_mode_the_umask_gives(tmp_path, umask, expected):
    previous = os.umask(umask)
    try:
        assert file_mode() == expected
        atomic_write_text(tmp_path / "scenario.toml", "x = 1\n")
        write_json(tmp_path / "summary.json", {"status": "completed"})
        plain = tmp_path / "plain.txt"
        plain.write_text("y")  # what an ordinary open gives
    finally:
        os.umask(previous)
    for name in ("scenario.toml", "summary.json", "plain.txt"):
        assert stat.S_IMODE((tmp_path / name).stat().st_mode) == expected, name


def test_an_atomic_write_under_a_file_names_the_target(tmp_path):
    (tmp_path / "afile").write_text("")
    with pytest.raises(NotADirectoryError) as caught:
        atomic_write_text(tmp_path / "afile" / "curve.csv", "x")
    assert caught.value.filename == str(tmp_path / "afile" / "curve.csv")
