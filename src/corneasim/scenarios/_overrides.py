"""``--set key=value`` overrides of a scenario's nested TOML tables.

A key is a dotted path into the scenario (``instrument.speed``); the value is read
as a TOML value (``5``, ``2.0e-5``, ``true``, ``[1, 2]``, ``"text"``), and a bare
word that is not valid TOML (``conical``) is taken as a string. Unknown keys are
not rejected here: the scenario schema rejects them, naming the full key.

An entry of an array of tables (``[[constraints]]``, ``[[pressures]]``, ...) is reached
by its position, counted from 0 in file order (``constraints[1].value=0.1``), or by the
set it names (``constraints.punch.value=0.1``): the entry whose ``name``, ``node_set`` or
``surface`` is that word, which must be unique in the list. A wrong part of the path is
reported by itself: an index out of range with the list's length, a name with the names
the list has.

``--unset KEY`` (and a presets table's ``unset = [KEY, ...]``, :data:`UNSET`) removes a key, so
that the scenario takes the key's default (None for an optional key: off). A key that no table
of the scenario format has is refused (:func:`check_known`), also below a table that the
scenario leaves out (checked against that table's schema); removing a key of an absent table
changes nothing.
"""

from __future__ import annotations

import copy
import re
import tomllib
import typing

import pydantic

from corneasim.errors import InputError

NAMING_KEYS = ("name", "node_set", "surface")
"""Keys of an array-of-tables entry that name it, for a path part that is a word."""

UNSET = "unset"
"""The reserved key of a ``[presets.NAME]`` table: a list of dotted keys the preset removes."""

_PART = re.compile(r"^([^\[\]]*)((?:\[\s*-?\d+\s*\])*)$")


def parse_key(key: str) -> list[str | int] | None:
    """Path parts of a dotted key: words, and list positions as ints; None if malformed.

    >>> parse_key("constraints[3].value")
    ['constraints', 3, 'value']
    """
    path: list[str | int] = []
    for piece in key.split("."):
        match = _PART.match(piece.strip())
        if match is None or not match.group(1).strip():
            return None
        path.append(match.group(1).strip())
        path.extend(int(index) for index in re.findall(r"-?\d+", match.group(2)))
    return path


def parse_override(text: str) -> tuple[list[str | int], object]:
    """Split ``"a.b=value"`` into (``["a", "b"]``, parsed value).

    >>> parse_override("instrument.speed=5")
    (['instrument', 'speed'], 5)
    >>> parse_override("instrument.tip=conical")
    (['instrument', 'tip'], 'conical')
    >>> parse_override("constraints[1].value=0.1")
    (['constraints', 1, 'value'], 0.1)
    """
    key, separator, raw = text.partition("=")
    path = parse_key(key)
    if not separator or path is None:
        raise InputError(f"--set {text!r}: expected KEY=VALUE with a dotted key, e.g. instrument.speed=5 "
                         "or constraints[0].value=0.1")
    raw = raw.strip()
    try:
        value = tomllib.loads(f"value = {raw}")["value"]
    except tomllib.TOMLDecodeError:
        value = raw
    return path, value


def override_table(texts) -> dict:
    """``KEY=VALUE`` texts as a study's ``overrides`` table: {dotted key: parsed value}, a later
    text of the same key winning.

    >>> override_table(["mesh.preset=coarse", "solver.end_time=3.6", "mesh.preset=default"])
    {'mesh.preset': 'default', 'solver.end_time': 3.6}
    """
    return {text.partition("=")[0].strip(): parse_override(text)[1] for text in texts}


def apply_overrides(data: dict, overrides: list[str]) -> dict:
    """Return a deep copy of ``data`` with every ``KEY=VALUE`` override applied."""
    result = copy.deepcopy(data)
    for text in overrides:
        path, value = parse_override(text)
        _set(result, path, value, f"--set {text!r}")
    return result


def apply_settings(data: dict, settings: dict, origin: str) -> dict:
    """Return a deep copy of ``data`` with ``settings`` ({dotted key: TOML value}) applied.

    ``origin`` names where the settings come from in error messages (e.g. ``presets.coarse``).
    """
    result = copy.deepcopy(data)
    for key, value in settings.items():
        path = parse_key(str(key))
        if path is None:
            raise InputError(f"{origin}: key {key!r}: expected a dotted key, e.g. solver.target_time_step")
        _set(result, path, value, f"{origin}: {key!r}")
    return result


def remove_keys(data: dict, keys: list[str], origin: str) -> dict:
    """Return a deep copy of ``data`` without the dotted ``keys`` (absent keys are left alone).

    ``origin`` names where the keys come from in error messages (``--unset``, ``presets.paper``).
    """
    result = copy.deepcopy(data)
    for key in keys:
        path = _unset_path(key, origin)
        container = result
        for depth, part in enumerate(path[:-1]):
            if isinstance(container, list):
                container = container[_entry_index(container, part, _spelled(path[: depth + 1]), origin)]
            elif isinstance(container, dict) and not isinstance(part, int):
                container = container.get(part)
            else:
                container = None
            if not isinstance(container, (dict, list)):
                break
        else:
            last = path[-1]
            if isinstance(container, dict) and not isinstance(last, int):
                container.pop(last, None)
            elif isinstance(container, list):
                del container[_entry_index(container, last, _spelled(path), origin)]
    return result


def check_known(scenario, keys: list[str], origin: str) -> None:
    """Refuse a removed key that no table of the validated ``scenario`` (a pydantic model) has.

    Below a table that the scenario leaves out (an optional table, None) the key is checked
    against the table's schema, the fields of its model class.

    Raises
    ------
    InputError
        One line naming the key and the keys its table has.
    """
    for key in keys:
        path = _unset_path(key, origin)
        models = [scenario]
        for depth, part in enumerate(path):
            here = _spelled(path[: depth + 1])
            fields = sorted({name for model in models if _schema(model) for name in _schema(model).model_fields})
            if isinstance(part, int) or not fields:
                tables = [model for model in models if isinstance(model, (dict, list))]
                models = [item for model in tables for item in _items(model, part)]
                if tables and not models:
                    raise InputError(f"{origin} {key!r}: '{here}': no such entry in the scenario")
            elif part in fields:
                models = [_field_value(model, part) for model in models
                          if _schema(model) and part in _schema(model).model_fields]
            else:
                raise InputError(f"{origin} {key!r}: '{here}' is not a key of the scenario format; "
                                 f"'{_spelled(path[:depth]) or '(top level)'}' has: {', '.join(fields)}")
            models = [model for model in models if model is not None]
            if depth < len(path) - 1 and not models:
                return


def _is_model(value) -> bool:
    return isinstance(value, type) and issubclass(value, pydantic.BaseModel)


def _schema(model) -> type | None:
    """The model class of a validated table or of an absent one (a class), else None."""
    if isinstance(model, pydantic.BaseModel):
        return type(model)
    return model if _is_model(model) else None


def _field_value(model, name: str):
    """The field ``name`` of a validated table, or, below an absent table (a model class), the
    model class of an optional table (``X | None``) the field holds, else None."""
    if isinstance(model, pydantic.BaseModel):
        value = getattr(model, name)
        if value is not None:
            return value
        model = type(model)
    annotation = model.model_fields[name].annotation
    classes = [annotation] if _is_model(annotation) else [kind for kind in typing.get_args(annotation)
                                                           if _is_model(kind)]
    return classes[0] if len(classes) == 1 else None


def _items(container, part) -> list:
    """The entries of a validated list or table that ``part`` (a position or a name) reaches."""
    if isinstance(container, dict):
        return [container[part]] if part in container else []
    if isinstance(container, list):
        if isinstance(part, int):
            return container[part:part + 1] if -len(container) <= part < len(container) else []
        return [entry for entry in container if any(getattr(entry, name, None) == part for name in NAMING_KEYS)]
    return []


def _unset_path(key, origin: str) -> list[str | int]:
    path = parse_key(str(key)) if isinstance(key, str) else None
    if path is None:
        raise InputError(f"{origin} {key!r}: expected a dotted key, e.g. instrument.contact.cutting_toughness")
    return path


def _spelled(path: list[str | int]) -> str:
    """``['constraints', 3, 'value']`` -> ``constraints[3].value``."""
    text = ""
    for part in path:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else part)
    return text


def _set(data: dict, path: list[str | int], value, origin: str) -> None:
    container = data
    for depth, part in enumerate(path):
        here = _spelled(path[: depth + 1])
        last = depth == len(path) - 1
        if isinstance(container, list):
            index = _entry_index(container, part, here, origin)
            if last:
                container[index] = value
                return
            container = container[index]
            if not isinstance(container, (dict, list)):
                raise InputError(f"{origin}: '{here}' is a value, not a table")
            continue
        if isinstance(part, int):
            raise InputError(f"{origin}: '{_spelled(path[:depth])}' is a table, not a list: "
                             f"use a key name instead of [{part}]")
        if last:
            container[part] = value
            return
        next_is_index = isinstance(path[depth + 1], int)
        if part not in container:
            if next_is_index:
                raise InputError(f"{origin}: '{here}' has no entries (index [{path[depth + 1]}] out of range)")
            container[part] = {}
        child = container[part]
        if not isinstance(child, (dict, list)):
            raise InputError(f"{origin}: '{here}' is a value, not a table")
        container = child


def _entry_index(entries: list, part: str | int, here: str, origin: str) -> int:
    """Position of the entry ``part`` (an index, or a name per :data:`NAMING_KEYS`) in ``entries``."""
    if isinstance(part, int):
        if not 0 <= part < len(entries):
            raise InputError(f"{origin}: '{here}': index out of range, the list has {len(entries)} "
                             f"entr{'y' if len(entries) == 1 else 'ies'} (0..{len(entries) - 1})")
        return part
    matches = [index for index, entry in enumerate(entries)
               if isinstance(entry, dict) and any(entry.get(key) == part for key in NAMING_KEYS)]
    if len(matches) == 1:
        return matches[0]
    if not matches:
        names = sorted({str(entry[key]) for entry in entries if isinstance(entry, dict)
                        for key in NAMING_KEYS if key in entry})
        raise InputError(f"{origin}: '{here}': no entry is named '{part}' (by {', '.join(NAMING_KEYS)}); "
                         f"the names are: {', '.join(names) or 'none'}")
    listed = ", ".join(f"[{index}]" for index in matches)
    raise InputError(f"{origin}: '{here}': {len(matches)} entries are named '{part}' ({listed}): "
                     "give the position instead")
