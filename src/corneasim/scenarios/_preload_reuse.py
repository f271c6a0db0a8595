"""A settled preload reused: another run of the same eye starts where this one's preload ended.

The preload (docs/solver.md, "Preload stage") settles the eye under its loads before the
instrument moves; it is 24,000 of the default needle run's 164,000 steps. It depends on the
eye and the numerics only, so runs that differ after it (insertion speed or depth, outputs,
the procedure's damping) can share it. A run with a results
folder writes its settled state to ``preload.npz`` (a checkpoint, :mod:`corneasim.solver`,
with the key below); ``corneasim run ... --preload-from DIR`` (``simulate(...,
preload_from=DIR)``) starts from it instead of settling again. The result is the same bit
for bit as a run that settles its own preload: every quantity the next step depends on
is in the checkpoint, and the preload's last history row is replayed as it was recorded.

The **key** says what the preload depended on: the resolved scenario without the keys that
act only after it (:data:`AFTER_PRELOAD`), a digest of the material constants (a material
file edited under the same name changes it), of the reference mesh and of corneasim's own
source code. A state whose key differs is refused with the first difference named.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np

from corneasim.errors import InputError
from corneasim.solver import load_checkpoint, save_checkpoint
from corneasim.solver import model_fingerprint

PRELOAD_FILE = "preload.npz"
AFTER_PRELOAD = ("name", "description", "validation", "presets", "instrument.motion", "instrument.start_gap",
                 "solver.end_time", "solver.damping", "solver.history_every", "solver.field_count",
                 "solver.checkpoint_every", "solver.threads")
"""Scenario keys that act only after the preload (dotted paths): they may differ between the runs
that share one. The instrument is placed ``start_gap`` above the settled eye after the preload and
moves only then; the solver's ``damping`` is the procedure's (the preload has its own); the
element kernels give the same result on any number of threads."""


def _source_digest() -> str:
    """SHA-1 of corneasim's source files (``*.py`` and the built-in ``*.toml``), in path order."""
    package = Path(__file__).resolve().parents[1]
    digest = hashlib.sha1()
    for path in sorted([*package.rglob("*.py"), *package.rglob("*.toml")]):
        digest.update(str(path.relative_to(package)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


def preload_key(setup) -> dict:
    """What the preload of ``setup`` depends on (module notes); call before the first step
    (softening rewrites material rows during a run)."""
    scenario = setup.scenario.model_dump(mode="json")
    for dotted in AFTER_PRELOAD:
        *parents, leaf = dotted.split(".")
        table = scenario
        for name in parents:
            table = table.get(name) or {}
        table.pop(leaf, None)
    model = setup.model
    constants = hashlib.sha1(np.ascontiguousarray(model.elements.material_table).tobytes()).hexdigest()
    return {"scenario": scenario, "material constants": constants, "mesh": model_fingerprint(model),
            "corneasim source": _source_digest()}


def save_preload(folder: Path, setup, state, key: dict, last_row: dict | None) -> None:
    """Write the settled state, its key and the preload's last history row to ``folder/preload.npz``."""
    row = None if last_row is None else {  # NumPy scalars as Python numbers, for JSON
        name: value.item() if isinstance(value, np.generic) else value for name, value in last_row.items()}
    save_checkpoint(folder / PRELOAD_FILE, setup.model, state, setup.hooks,
                    extra={"preload_key": np.array(json.dumps(key, sort_keys=True)),
                           "preload_last_row": np.array(json.dumps(row))})


def _first_difference(saved, now, path: str = "") -> str | None:
    """The dotted path of the first entry where two JSON-like values differ (None if equal)."""
    if isinstance(saved, dict) and isinstance(now, dict):
        for name in sorted(set(saved) | set(now)):
            where = f"{path}.{name}" if path else name
            if name not in saved or name not in now:
                return where
            found = _first_difference(saved[name], now[name], where)
            if found is not None:
                return found
        return None
    if isinstance(saved, list) and isinstance(now, list) and len(saved) == len(now):
        for index, (a, b) in enumerate(zip(saved, now)):
            found = _first_difference(a, b, f"{path}[{index}]")
            if found is not None:
                return found
        return None
    return None if saved == now else path


def load_preload(source, setup, key: dict):
    """The settled state saved by a run whose preload had the same ``key``, and its last history row.

    ``source`` is that run's results folder or its ``preload.npz``. InputError (one line) when
    there is none, or when the key differs (naming the first difference).
    """
    path = Path(source)
    if path.is_dir():
        path = path / PRELOAD_FILE
    if not path.is_file():
        raise InputError(f"--preload-from: no settled preload at {path} (a run with a preload and a results "
                         "folder writes one)")
    try:
        with np.load(path, allow_pickle=False) as data:
            saved_key = json.loads(str(data["preload_key"]))
            last_row = json.loads(str(data["preload_last_row"]))
    except (KeyError, OSError, ValueError) as error:
        raise InputError(f"--preload-from: {path} is not a corneasim preload ({error})") from None
    now = json.loads(json.dumps(key, sort_keys=True))
    difference = _first_difference(saved_key.get("scenario"), now["scenario"])
    if difference is not None:
        raise InputError(f"--preload-from: {path} was settled with another value of {difference} (only "
                         f"keys that act after the preload may differ: {', '.join(AFTER_PRELOAD)})")
    for name, what in (("material constants", "with other material constants"), ("mesh", "on another mesh"),
                       ("corneasim source", "by another version of corneasim's source code")):
        if saved_key.get(name) != now[name]:
            raise InputError(f"--preload-from: {path} was settled {what}")
    return load_checkpoint(path, setup.model, setup.hooks), last_row
