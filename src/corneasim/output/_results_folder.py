"""A results folder belongs to one run: an exclusive lock, the files a run writes, clearing them.

Two runs writing into one folder would leave one run's input beside the other's summary and
a history of both. :meth:`ResultsFolder.claim` therefore

* checks the path: a folder or a path that can become one (never a file, nor under one),
  writable, each problem one :class:`~corneasim.errors.InputError` line;
* takes an advisory exclusive lock (:func:`fcntl.flock` on :data:`LOCK_NAME` in the folder)
  for as long as the run lasts; the operating system releases it on any exit, even SIGKILL,
  so a stale lock file never blocks a later run. A second run into a folder in use is refused;
* refuses a new run into a folder that holds an earlier run's files (:func:`run_files`),
  naming ``--overwrite`` (which deletes those files, and only those: files the folder held
  besides them are left alone) and ``--resume``; a resumed run keeps them.

The files a run writes are known by name (:data:`RUN_FILES`, and in the folders of
:data:`RUN_FOLDERS` the suffixes listed there), with the temporary files of interrupted
atomic writes (``.NAME.*.tmp``).
"""

from __future__ import annotations

import errno
import fcntl
import os
from pathlib import Path

from corneasim.errors import InputError

LOCK_NAME = ".corneasim.lock"
RUN_FILES = ("scenario.toml", "history.csv", "deletions.csv", "summary.json", "checkpoint.npz", "preload.npz",
             "reference.npz", "report.html")
RUN_FOLDERS = {"fields": (".vtu", ".pvd"), "plots": (".png", ".svg", ".pdf", ".html", ".csv", ".json")}
"""Subfolders a run writes, with the suffixes of the files it writes in them."""


def _temporary(path: Path) -> bool:
    """An atomic write's temporary file (``.NAME.*.tmp`` or ``.NAME.tmp``)."""
    return path.name.startswith(".") and path.name.endswith(".tmp")


def run_files(folder: Path) -> list[Path]:
    """The files an earlier run wrote in ``folder`` (its lock file not counted), sorted."""
    found = [folder / name for name in RUN_FILES if (folder / name).is_file()]
    found += [path for path in folder.glob(".*.tmp") if path.is_file()]
    for name, suffixes in RUN_FOLDERS.items():
        sub = folder / name
        if sub.is_dir():
            found += [path for path in sub.iterdir()
                      if path.is_file() and (path.suffix in suffixes or _temporary(path))]
    return sorted(found)


def check_output_path(folder: Path) -> None:
    """InputError (one line) unless ``folder`` is a folder or can be created as one, and is writable."""
    if folder.exists() and not folder.is_dir():
        raise InputError(f"{folder}: is a file, not a results folder; choose a folder with --out")
    for parent in folder.parents:
        if parent.exists():
            if not parent.is_dir():
                raise InputError(f"{folder}: {parent} is a file, so no folder can be made under it")
            break
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise InputError(f"{folder}: cannot create the results folder ({_reason(error)})") from None
    if not os.access(folder, os.W_OK | os.X_OK):
        raise InputError(f"{folder}: the results folder is not writable")


def _reason(error: OSError) -> str:
    return error.strerror or errno.errorcode.get(error.errno, type(error).__name__)


class ResultsFolder:
    """A results folder held by this process (:meth:`claim`) until :meth:`release`.

    Attributes
    ----------
    path : Path
        The folder.
    """

    def __init__(self, path: Path, handle):
        self.path = path
        self._handle = handle

    @classmethod
    def claim(cls, folder: str | Path, *, resume: bool = False, overwrite: bool = False) -> ResultsFolder:
        """Check, create and lock ``folder`` for one run (module notes).

        Parameters
        ----------
        folder : path-like
        resume : bool
            The run continues the one whose files are there: keep them.
        overwrite : bool
            Delete an earlier run's files (:func:`run_files`) instead of refusing.

        Raises
        ------
        InputError
            A bad path, a folder in use by another run, or (without ``resume`` or
            ``overwrite``) a folder holding an earlier run's files.
        """
        path = Path(folder)
        check_output_path(path)
        try:
            handle = open(path / LOCK_NAME, "a+")
        except OSError as error:
            raise InputError(f"{path}: cannot create the lock file {LOCK_NAME} ({_reason(error)})") from None
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.seek(0)
            holder = handle.read().strip()
            handle.close()
            raise InputError(f"{path}: in use by another run{f' (process {holder})' if holder else ''}; "
                             "wait for it to end or choose another --out") from None
        handle.seek(0)
        handle.truncate()
        handle.write(f"{os.getpid()}\n")
        handle.flush()
        claimed = cls(path, handle)
        if not resume:
            earlier = run_files(path)
            if earlier and not overwrite:
                claimed.release()
                names = ", ".join(str(p.relative_to(path)) for p in earlier[:3]) + (", ..." if len(earlier) > 3 else "")
                raise InputError(f"{path}: holds the results of an earlier run ({names}); give --overwrite to "
                                 "replace them, --resume DIR to continue that run, or another --out")
            for stale in earlier:
                stale.unlink(missing_ok=True)
        return claimed

    def release(self) -> None:
        """Unlock the folder (the lock file stays: removing it would race with a run taking it)."""
        if self._handle is not None:
            self._handle.close()
            self._handle = None
