"""The papers' datasets: self-describing CSV files shipped with the package.

Each dataset is one CSV file in this directory, named ``<dataset-name>.csv``, in
the format of :func:`corneasim.data.read_table`. Its ``#`` comment lines carry
its metadata as ``key: value`` pairs:

* ``# title: ...`` one line saying what the table is, with units;
* ``# source: ...`` the paper, table or equation it comes from;
* ``# note: ...`` any number of notes (corrections, conversions, inconsistencies).

Units are the last ``_``-separated token of each column name
(``depth_mm`` -> mm, ``simulation_Fz_N`` -> N); a column without a unit suffix
(``term``) is dimensionless.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np

from corneasim.data._csv import read_csv_text, read_table
from corneasim.errors import InputError

#: Unit suffixes recognised in column names (mm, s, N, MPa system plus um for micrometres).
UNIT_SUFFIXES = ("mm", "um", "s", "N", "mN", "MPa", "kPa", "mJ", "rad", "deg")

_METADATA_KEYS = ("title", "source", "note")


@dataclass(frozen=True)
class Dataset:
    """One experimental or published table.

    Attributes
    ----------
    name : str
        Registry name (the CSV file's stem), e.g. ``"needle-insertion-force"``.
    title : str
        What the table is, with units.
    source : str
        Paper and table or equation it was taken from.
    notes : tuple of str
        Corrections, unit conversions and inconsistencies found in the source.
    columns : dict of str to numpy.ndarray
        One float64 array of shape ``(n_rows,)`` per column, in file order.
    units : dict of str to str
        Unit of each column (``""`` for dimensionless columns).
    text : str
        The raw CSV text, comments included.
    """

    name: str
    title: str
    source: str
    notes: tuple[str, ...]
    columns: dict[str, np.ndarray] = field(repr=False)
    units: dict[str, str]
    text: str = field(repr=False)

    def __getitem__(self, column: str) -> np.ndarray:
        """The column named ``column`` (its unit is ``self.units[column]``)."""
        try:
            return self.columns[column]
        except KeyError:
            raise InputError(
                f"dataset {self.name}: unknown column {column!r} (columns: {', '.join(self.columns)})"
            ) from None

    @property
    def n_rows(self) -> int:
        """Number of data rows."""
        return len(next(iter(self.columns.values())))


def list_datasets() -> list[str]:
    """Names of the shipped datasets, sorted.

    Examples
    --------
    >>> "needle-insertion-force" in list_datasets()
    True
    """
    directory = resources.files("corneasim.data")
    return sorted(entry.name[:-4] for entry in directory.iterdir() if entry.name.endswith(".csv"))


def load_dataset(name: str) -> Dataset:
    """Load a shipped dataset by name.

    Parameters
    ----------
    name : str
        One of :func:`list_datasets`.

    Returns
    -------
    Dataset

    Raises
    ------
    corneasim.errors.InputError
        Unknown name (the message lists the known ones).
    """
    names = list_datasets()
    if name not in names:
        raise InputError(f"unknown dataset {name!r} (expected one of: {', '.join(names)})")
    text = resources.files("corneasim.data").joinpath(f"{name}.csv").read_text(encoding="utf-8")
    return parse_dataset(name, text, origin=f"{name}.csv")


def load_dataset_file(path: str | Path) -> Dataset:
    """Load a user CSV file in the same format as a dataset (metadata optional).

    Parameters
    ----------
    path : str or pathlib.Path
        CSV file with a header row of column names carrying their units.

    Raises
    ------
    corneasim.errors.InputError
        Missing or malformed file (see :func:`corneasim.data.read_table`).
    """
    return parse_dataset(Path(path).stem, read_csv_text(path), origin=str(path))


def parse_dataset(name: str, text: str, origin: str) -> Dataset:
    """Build a :class:`Dataset` from CSV text: columns, units and comment metadata."""
    columns = read_table(origin, text=text)
    metadata = _comment_metadata(text)
    return Dataset(
        name=name,
        title=" ".join(metadata["title"]),
        source=" ".join(metadata["source"]),
        notes=tuple(metadata["note"]),
        columns=columns,
        units={column: column_unit(column) for column in columns},
        text=text,
    )


def column_unit(column: str) -> str:
    """Unit encoded as the last ``_`` token of a column name, or ``""``.

    Examples
    --------
    >>> column_unit("experiment_1mm_s_N"), column_unit("depth_mm"), column_unit("term")
    ('N', 'mm', '')
    """
    head, _, suffix = column.rpartition("_")
    return suffix if head and suffix in UNIT_SUFFIXES else ""


def _comment_metadata(text: str) -> dict[str, list[str]]:
    """``# key: value`` comment lines grouped by key; other comment lines extend the previous entry."""
    metadata: dict[str, list[str]] = {key: [] for key in _METADATA_KEYS}
    last: str | None = None
    for line in text.splitlines():
        stripped = line.strip()
        if not stripped.startswith("#"):
            continue
        body = stripped.lstrip("#").strip()
        key, colon, value = body.partition(":")
        if colon and key.strip().lower() in metadata:
            last = key.strip().lower()
            metadata[last].append(value.strip())
        elif last is not None and body:
            metadata[last][-1] += " " + body
    return metadata
