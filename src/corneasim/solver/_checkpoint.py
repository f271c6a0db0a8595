"""Checkpoints: the whole :class:`State` (and the hooks' own state) in one ``.npz`` file.

Written atomically (temporary file in the same folder, then :func:`os.replace`), so a run
killed at any moment leaves either the previous checkpoint or the new one, never a torn
file. A checkpoint records the mesh size and a fingerprint of the reference mesh and
refuses to load into a different model. Restarting from a checkpoint continues bit for bit:
every quantity the step depends on (including the next time step and the energy
accumulators) is in the file.
"""

from __future__ import annotations

import hashlib
import io
import zipfile
from dataclasses import fields
from pathlib import Path

import numpy as np

from corneasim.errors import InputError
from corneasim.output import atomic_write_bytes
from corneasim.solver._mass_scaling import set_density_scale
from corneasim.solver._softening import restore_softening_rows
from corneasim.solver._state import State

FORMAT = "corneasim-checkpoint-1"
HOOK_PREFIX = "hook:"


def model_fingerprint(model) -> str:
    """SHA-1 of the reference points, cells and blocks of the model's mesh."""
    digest = hashlib.sha1()
    for array in (model.mesh.points, model.mesh.cells, model.mesh.element_block):
        digest.update(np.ascontiguousarray(array).tobytes())
    return digest.hexdigest()


def save_checkpoint(path, model, state: State, hooks=(), extra: dict | None = None) -> None:
    """Write ``state`` (and each hook's ``checkpoint()`` arrays) to ``path`` atomically.

    ``extra``: more named arrays to store (a caller's own records; :func:`load_checkpoint`
    ignores them).

    The model's element density scales are saved too (and the softening elements' material
    rows are rebuilt from the saved damage on loading): variable mass scaling changes them
    during a run, and :func:`load_checkpoint` gives them (and the masses) back to the model.
    """
    arrays = {"format": np.array(FORMAT), "fingerprint": np.array(model_fingerprint(model)),
              "model_density_scale": model.density_scale}
    for item in fields(State):
        arrays[item.name] = np.asarray(getattr(state, item.name))
    for hook in hooks:
        for key, value in getattr(hook, "checkpoint", dict)().items():
            arrays[f"{HOOK_PREFIX}{hook.name}:{key}"] = np.asarray(value)
    arrays.update(extra or {})
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    atomic_write_bytes(path, buffer.getvalue())


def load_checkpoint(path, model, hooks=()) -> State:
    """Read a checkpoint written by :func:`save_checkpoint` for the same model.

    Hooks with a ``restore(arrays)`` method get their saved arrays back (keys without prefix).
    InputError if the file is missing, unreadable or from another model.
    """
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {key: data[key] for key in data.files}
    except FileNotFoundError:
        raise InputError(f"{path}: checkpoint not found") from None
    except (OSError, ValueError, zipfile.BadZipFile) as error:
        raise InputError(f"{path}: not a readable checkpoint ({error})") from None
    if str(arrays.get("format", "")) != FORMAT:
        raise InputError(f"{path}: not a corneasim checkpoint (expected format {FORMAT})")
    if str(arrays["fingerprint"]) != model_fingerprint(model):
        raise InputError(f"{path}: checkpoint belongs to a different mesh than this model")
    values = {}
    for item in fields(State):
        if item.name not in arrays:
            raise InputError(f"{path}: checkpoint lacks '{item.name}'")
        value = arrays[item.name]
        values[item.name] = value.item() if value.ndim == 0 else np.array(value)
    values["step"] = int(values["step"])
    set_density_scale(model, arrays["model_density_scale"])
    state = State(**values)
    restore_softening_rows(model, state)
    for hook in hooks:
        prefix = f"{HOOK_PREFIX}{hook.name}:"
        saved = {key[len(prefix):]: value for key, value in arrays.items() if key.startswith(prefix)}
        if hasattr(hook, "restore"):
            hook.restore(saved)
    return state
