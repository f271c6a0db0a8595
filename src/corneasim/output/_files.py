"""Crash-safe result files: atomic writes and an append-only history table.

A run that fails or is interrupted must never leave a half-written file or lose
what it had already written. Whole files (``summary.json``, ``scenario.toml``,
checkpoints, VTU frames, the ``.pvd`` index) are written to a temporary file in
the same folder and moved into place with :func:`os.replace`, which is atomic on
POSIX. The history table is appended row by row and flushed, so after a crash it
holds every row up to the last output step.
"""

from __future__ import annotations

import csv
import json
import math
import os
import tempfile
from pathlib import Path

import numpy as np


def atomic_write_bytes(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically (temporary file + ``os.replace``)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    descriptor, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(descriptor, "wb") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def atomic_write_text(path: str | Path, text: str) -> None:
    """Write UTF-8 ``text`` to ``path`` atomically."""
    atomic_write_bytes(path, text.encode("utf-8"))


def _plain(value):
    """Turn numpy scalars/arrays and non-finite floats into JSON-safe Python values."""
    if isinstance(value, dict):
        return {str(key): _plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(item) for item in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.generic):
        return _plain(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def write_json(path: str | Path, data: dict) -> None:
    """Write ``data`` as indented JSON atomically (NaN and infinity become null)."""
    atomic_write_text(path, json.dumps(_plain(data), indent=2, allow_nan=False) + "\n")


class HistoryWriter:
    """Append-only CSV history: the header once, then one flushed row per output step.

    Parameters
    ----------
    path : path-like
        The CSV file. With ``resume=True`` an existing file is kept and rows with a
        time later than ``resume_time`` (written after the checkpoint being resumed)
        are dropped first, so a resumed run continues the table without duplicates.
    columns : sequence of str
        Column names, units in the name (``time_s``, ``force_N``).
    """

    def __init__(self, path: str | Path, columns, resume: bool = False, resume_time: float | None = None):
        self.path = Path(path)
        self.columns = list(columns)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        if resume and self.path.exists():
            self._truncate_after(resume_time)
            self._handle = self.path.open("a", newline="")
            self._writer = csv.writer(self._handle)
        else:
            self._handle = self.path.open("w", newline="")
            self._writer = csv.writer(self._handle)
            self._writer.writerow(self.columns)
            self._handle.flush()

    def _truncate_after(self, resume_time: float | None) -> None:
        with self.path.open(newline="") as handle:
            rows = list(csv.reader(handle))
        if not rows or rows[0] != self.columns:
            rows = [self.columns]
        kept = [rows[0]] + [
            row for row in rows[1:] if row and (resume_time is None or float(row[0]) <= resume_time * (1 + 1e-12))
        ]
        atomic_write_text(self.path, "".join(",".join(row) + "\n" for row in kept))

    def append(self, row: dict) -> None:
        """Write one row (a dict keyed by column name; missing columns stay empty) and flush."""
        self._writer.writerow([_format(row.get(column, "")) for column in self.columns])
        self._handle.flush()

    def close(self) -> None:
        """Close the file."""
        self._handle.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _format(value) -> str:
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    return str(value)
