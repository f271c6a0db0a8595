"""Crash-safe result files: atomic writes and an append-only history table.

A run that fails or is interrupted must never leave a half-written file or lose
what it had already written. Whole files (``summary.json``, ``scenario.toml``,
checkpoints, VTU frames, the ``.pvd`` index) are written to a temporary file in
the same folder and moved into place with :func:`os.replace`, which is atomic on
POSIX; they get the permissions an ordinary ``open`` would give (``0o666`` less the
umask, 0644 by default), so colleagues on a shared machine can read them. The history
table is appended row by row with ``\n`` line endings and flushed, so after a crash it
holds every row up to the last output step, at most followed by one torn row, which
:func:`trim_table` removes before a resumed run appends to it.
"""

from __future__ import annotations

import csv
import errno
import json
import math
import os
import tempfile
from pathlib import Path

import numpy as np


def file_mode() -> int:
    """The permissions of a new file as the umask says: ``0o666 & ~umask`` (0o644 for umask 022).

    :func:`tempfile.mkstemp` creates files 0600 whatever the umask; an atomic write sets this
    mode on its temporary file so the result reads like any other file the user writes.
    """
    mask = os.umask(0o022)
    os.umask(mask)
    return 0o666 & ~mask


def atomic_write_bytes(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically (temporary file + ``os.replace``), mode :func:`file_mode`.

    Raises
    ------
    OSError
        When the folder cannot be made or written; its ``filename`` is ``path`` (not the
        temporary file's), so the message names what the user asked for.
    """
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        descriptor, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    except FileExistsError:  # a file where its folder should be
        raise NotADirectoryError(errno.ENOTDIR, "a file is in the way of its folder", str(path)) from None
    except OSError as error:
        raise OSError(error.errno, error.strerror or type(error).__name__, str(path)) from None
    try:
        os.fchmod(descriptor, file_mode())
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
    """Append-only CSV history: the header once, then one flushed row per output step (``\n`` endings).

    Parameters
    ----------
    path : path-like
        The CSV file. With ``resume=True`` an existing file is kept, trimmed by
        :func:`trim_table` first (a torn last row and the rows later than ``resume_time``,
        written after the checkpoint being resumed, are dropped), so a resumed run continues
        the table without duplicates and with the bytes an uninterrupted run writes.
    columns : sequence of str
        Column names, units in the name (``time_s``, ``force_N``).
    """

    def __init__(self, path: str | Path, columns, resume: bool = False, resume_time: float | None = None):
        self.path = Path(path)
        self.columns = list(columns)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        if resume and self.path.exists():
            trim_table(self.path, resume_time, self.columns)
            self._handle = self.path.open("a", newline="")
            self._writer = csv.writer(self._handle, lineterminator="\n")
        else:
            self._handle = self.path.open("w", newline="")
            self._writer = csv.writer(self._handle, lineterminator="\n")
            self._writer.writerow(self.columns)
            self._handle.flush()

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


def trim_table(path: str | Path, until: float | None, columns=None) -> int:
    """Cut a history table back to its complete rows with a first field (time, s) <= ``until``.

    A run killed while writing leaves its last row torn anywhere, even inside its first
    field; only rows that end in a newline, have the header's number of fields and a finite
    first field are complete. Those with a time up to ``until`` (all with None; with a
    relative round-off allowance of 1e-12) are kept as written, byte for byte, each ended by
    ``\n``; a missing or torn header is replaced by ``columns`` (when given). The file is
    rewritten atomically, and only when that changes it.

    Returns
    -------
    int
        The number of data rows kept.
    """
    path = Path(path)
    original = path.read_bytes()
    lines = [line.rstrip(b"\r") for line in original.split(b"\n")[:-1]]  # the last piece is torn or empty
    header = lines[0] if lines else None
    if columns is not None and (header is None or header.decode("utf-8", "replace").split(",") != list(columns)):
        header = ",".join(columns).encode()
    if header is None:
        kept = []
    else:
        width = header.count(b",") + 1
        kept = [header] + [line for line in lines[1:] if line.count(b",") + 1 == width and _in_time(line, until)]
    trimmed = b"".join(line + b"\n" for line in kept)
    if trimmed != original:
        atomic_write_bytes(path, trimmed)
    return max(len(kept) - 1, 0)


def _in_time(line: bytes, until: float | None) -> bool:
    """Whether a row's first field is a finite time <= ``until`` (any finite time when None)."""
    try:
        time = float(line.split(b",", 1)[0])
    except ValueError:
        return False
    if not math.isfinite(time):
        return False
    return until is None or time <= until + 1e-12 * abs(until)


def _format(value) -> str:
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    return str(value)
