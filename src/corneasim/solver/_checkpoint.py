"""Checkpoints: the whole :class:`State` (and the hooks' own state) in one ``.npz`` file.

The model is static (:func:`~corneasim.solver.build_model` makes it from the scenario, and
the run does not change it), so a checkpoint is the state: with the scenario that built the
model, it is all a resumed run needs.

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
from pathlib import Path

import numpy as np

from corneasim.errors import InputError
from corneasim.output import atomic_write_bytes
from corneasim.solver._state import State, attach_derived, saved_fields

FORMAT = "corneasim-checkpoint-2"
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
    ignores them). The state's derived fields are not saved: :func:`load_checkpoint` rebuilds
    them (the softening elements' material rows from the saved damage).
    """
    arrays = {"format": np.array(FORMAT), "fingerprint": np.array(model_fingerprint(model))}
    for name in saved_fields():
        arrays[name] = np.asarray(getattr(state, name))
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
    for name in saved_fields():
        if name not in arrays:
            raise InputError(f"{path}: checkpoint lacks '{name}'")
        value = arrays[name]
        values[name] = value.item() if value.ndim == 0 else np.array(value)
    values["step"] = int(values["step"])
    state = attach_derived(model, State(**values))
    for hook in hooks:
        prefix = f"{HOOK_PREFIX}{hook.name}:"
        saved = {key[len(prefix):]: value for key, value in arrays.items() if key.startswith(prefix)}
        if hasattr(hook, "restore"):
            hook.restore(saved)
    return state
