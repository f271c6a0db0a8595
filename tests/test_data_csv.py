"""read_table: good tables parse exactly, every malformation is one InputError naming file and line."""

import numpy as np
import pytest

from corneasim.data import read_table
from corneasim.errors import InputError


def write(tmp_path, text, name="table.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_reads_columns_with_comments_and_blank_lines(tmp_path):
    path = write(
        tmp_path,
        "# Source: a paper\n\nstretch,nominal_stress_MPa\n1.0,0\n# mid-table note\n1.5, 2.5e-1\n\n",
    )
    table = read_table(path, required=("stretch",))
    assert list(table) == ["stretch", "nominal_stress_MPa"]
    np.testing.assert_array_equal(table["stretch"], [1.0, 1.5])
    np.testing.assert_array_equal(table["nominal_stress_MPa"], [0.0, 0.25])
    assert table["stretch"].dtype == np.float64


def test_text_argument_skips_the_file(tmp_path):
    table = read_table(tmp_path / "absent.csv", text="a,b\n1,2\n")
    assert table["b"][0] == 2.0


@pytest.mark.parametrize(
    "text, fragments",
    [
        ("x,y\n1,2\n3\n", ["line 3", "1 cells, expected 2"]),
        ("x,y\n1,2\n3,4,5\n", ["line 3", "3 cells"]),
        ("# c\nx,y\n1,abc\n", ["line 3", "column y", "'abc'"]),
        ("x,y\n1,nan\n", ["line 2", "finite"]),
        ("x,y\n1,\n", ["line 2", "column y"]),
        ("", ["empty table"]),
        ("# only a comment\n", ["empty table"]),
        ("x,y\n", ["no data rows", "line 1"]),
        ("1,2\n3,4\n", ["line 1", "header"]),
        ("x,x\n1,2\n", ["line 1", "duplicate", "x"]),
        ("x,\n1,2\n", ["line 1", "column 2 has no name"]),
    ],
)
def test_malformed_tables_name_file_and_line(tmp_path, text, fragments):
    path = write(tmp_path, text, "bad.csv")
    with pytest.raises(InputError) as caught:
        read_table(path)
    message = str(caught.value)
    assert "bad.csv" in message and "\n" not in message
    for fragment in fragments:
        assert fragment in message


def test_missing_required_column(tmp_path):
    path = write(tmp_path, "# c\nstretch,stress\n1,2\n")
    with pytest.raises(InputError, match=r"table.csv: line 2: missing column\(s\) nominal_stress_MPa"):
        read_table(path, required=("stretch", "nominal_stress_MPa"))


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="nope.csv: file not found"):
        read_table(tmp_path / "nope.csv")
