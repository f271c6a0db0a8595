"""Strict reader for numeric CSV tables with a header row and ``#`` comments.

The format shared by the package data and by user files (for example the
stress-stretch data given to ``corneasim material fit``)::

    # Source: Author et al. (2020), Table 2. Lines starting with '#' are comments.
    stretch,nominal_stress_MPa
    1.00,0.000
    1.05,0.012

* the first non-blank, non-comment line is the header: comma-separated column
  names, which carry their unit (``depth_mm``, ``force_N``, ``nominal_stress_MPa``);
* every other non-blank, non-comment line is a row of floats, as many as there
  are columns;
* ``#`` comment lines may appear anywhere (sources, notes); blank lines are skipped.

Any problem raises :class:`corneasim.errors.InputError` with one line naming the
file, the line number (1-based) and what was expected.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from corneasim.errors import InputError


def read_csv_text(path) -> str:
    """The text of a CSV file; a missing or unreadable file is an InputError naming it."""
    try:
        return Path(path).read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise InputError(f"{path}: file not found (expected a CSV table)") from None
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(f"{path}: cannot read the file ({error})") from None


def read_table(
    path: str | Path, required: Iterable[str] = (), *, text: str | None = None
) -> dict[str, np.ndarray]:
    """Read a numeric CSV table into a dict of float columns.

    Parameters
    ----------
    path : str or pathlib.Path
        The CSV file. Used for the error messages only when ``text`` is given.
    required : iterable of str, optional
        Column names that must be present (exact, case-sensitive match).
    text : str, optional
        The file's content, if already read (package data read through
        :mod:`importlib.resources`); the file is then not opened.

    Returns
    -------
    dict of str to numpy.ndarray
        One float64 array of shape ``(n_rows,)`` per column, in header order.

    Raises
    ------
    corneasim.errors.InputError
        Missing or unreadable file, no header, duplicate or empty column name,
        missing required column, a row with the wrong number of cells, a cell
        that is not a finite number, or a table without data rows.

    Examples
    --------
    >>> table = read_table("t.csv", text="# note\\nx_mm,F_N\\n0,0.5\\n1,1.5\\n")
    >>> table["F_N"]
    array([0.5, 1.5])
    """
    name = str(path)
    if text is None:
        text = read_csv_text(path)

    header: list[str] | None = None
    header_line = 0
    rows: list[list[float]] = []
    for line_number, line in enumerate(io.StringIO(text), start=1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        cells = [cell.strip() for cell in next(csv.reader([stripped]))]
        if header is None:
            header, header_line = _parse_header(cells, name, line_number), line_number
            continue
        if len(cells) != len(header):
            raise InputError(
                f"{name}: line {line_number}: {len(cells)} cells, expected {len(header)} "
                f"({','.join(header)})"
            )
        rows.append([_parse_cell(cell, column, name, line_number) for cell, column in zip(cells, header)])

    if header is None:
        raise InputError(f"{name}: empty table (expected a header row of column names)")
    missing = [column for column in required if column not in header]
    if missing:
        raise InputError(
            f"{name}: line {header_line}: missing column(s) {', '.join(missing)} "
            f"(header has {','.join(header)})"
        )
    if not rows:
        raise InputError(f"{name}: no data rows after the header on line {header_line}")
    values = np.array(rows, dtype=np.float64)  # (n_rows, n_columns)
    return {column: values[:, index].copy() for index, column in enumerate(header)}


def _parse_header(cells: list[str], name: str, line_number: int) -> list[str]:
    """Validate the header row: non-empty, unique, non-numeric column names."""
    for index, cell in enumerate(cells, start=1):
        if not cell:
            raise InputError(f"{name}: line {line_number}: header column {index} has no name")
        if _is_number(cell):
            raise InputError(
                f"{name}: line {line_number}: expected a header row of column names, got number {cell!r}"
            )
    duplicates = sorted({cell for cell in cells if cells.count(cell) > 1})
    if duplicates:
        raise InputError(f"{name}: line {line_number}: duplicate column name(s) {', '.join(duplicates)}")
    return cells


def _parse_cell(cell: str, column: str, name: str, line_number: int) -> float:
    """One finite float, or an InputError naming file, line and column."""
    try:
        value = float(cell)
    except ValueError:
        raise InputError(
            f"{name}: line {line_number}: column {column}: expected a number, got {cell!r}"
        ) from None
    if not math.isfinite(value):
        raise InputError(
            f"{name}: line {line_number}: column {column}: expected a finite number, got {cell!r}"
        )
    return value


def _is_number(cell: str) -> bool:
    try:
        float(cell)
    except ValueError:
        return False
    return True
