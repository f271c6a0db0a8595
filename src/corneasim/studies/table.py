"""The results table of a study: one row per case, rewritten atomically as cases finish.

``DIR/results.parquet`` and ``DIR/results.csv`` hold the same rows, in case order:

``case`` (``c0000``, ...), one column per parameter named by its dotted scenario key (unit of
the key), ``realization`` (realizations designs only), one column per output named as in
``[outputs]``, ``status`` (completed | failed | interrupted), ``error`` (one line, empty if
none), ``wall_s`` (s) and ``worker`` (Dask worker address). A curve output is an array of
float64 in the Parquet file (one value per abscissa value of the study) and a JSON array
(``null`` for NaN) in the CSV file.

Each rewrite goes to a temporary file that replaces the old one (:func:`os.replace`), so
the table on disk is always complete: a study stopped at any moment keeps every case
that had finished.
"""

from __future__ import annotations

import io
import json
import math
from pathlib import Path

import numpy as np
import pandas as pd

from corneasim.output import atomic_write_bytes, atomic_write_text

PARQUET = "results.parquet"
CSV = "results.csv"
TRAILING = ("status", "error", "wall_s", "worker")


def columns(parameters: list[str], outputs: list[str], realizations: bool) -> list[str]:
    """The table's columns in order."""
    return ["case", *parameters, *(["realization"] if realizations else []), *outputs, *TRAILING]


def frame(rows: dict, order: list[str]) -> pd.DataFrame:
    """The table of ``rows`` ({case: row dict}), sorted by case, in the column order ``order``."""
    records = [rows[name] for name in sorted(rows, key=lambda name: int(name[1:]))]
    table = pd.DataFrame.from_records(records, columns=order) if records else pd.DataFrame(columns=order)
    for name in ("case", "status", "error", "worker"):
        table[name] = table[name].fillna("").astype(str)
    table["wall_s"] = table["wall_s"].astype(float)
    return table


def _csv_cell(value):
    if isinstance(value, (np.ndarray, list)):
        return json.dumps([None if not math.isfinite(v) else float(v) for v in np.asarray(value, dtype=float)])
    return value


def write(directory: Path, table: pd.DataFrame) -> None:
    """Replace ``results.parquet`` and ``results.csv`` in ``directory`` atomically."""
    buffer = io.BytesIO()
    stored = table.copy()
    for name in stored.columns:
        if stored[name].map(lambda v: isinstance(v, np.ndarray)).any():
            stored[name] = stored[name].map(lambda v: np.asarray(v, dtype=float) if isinstance(
                v, (np.ndarray, list)) else v)
    stored.to_parquet(buffer, index=False)
    atomic_write_bytes(directory / PARQUET, buffer.getvalue())
    text = table.map(_csv_cell) if len(table) else table
    atomic_write_text(directory / CSV, text.to_csv(index=False))


def read(directory: Path) -> pd.DataFrame | None:
    """The table in ``directory`` (curves as float arrays), or None if there is none yet."""
    path = Path(directory) / PARQUET
    if not path.exists():
        return None
    table = pd.read_parquet(path)
    for name in table.columns:
        if table[name].dtype == object:
            table[name] = table[name].map(lambda v: np.asarray(v, dtype=float) if isinstance(v, np.ndarray) else v)
    return table


def rows_of(table: pd.DataFrame | None) -> dict:
    """{case: row dict} of a table read back."""
    if table is None:
        return {}
    return {record["case"]: record for record in table.to_dict(orient="records")}
