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
"""

from __future__ import annotations

import copy
import re
import tomllib

from corneasim.errors import InputError

NAMING_KEYS = ("name", "node_set", "surface")
"""Keys of an array-of-tables entry that name it, for a path part that is a word."""

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
