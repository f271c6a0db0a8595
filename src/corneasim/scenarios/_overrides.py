"""``--set key=value`` overrides of a scenario's nested TOML tables.

A key is a dotted path into the scenario (``instrument.speed``); the value is read
as a TOML value (``5``, ``2.0e-5``, ``true``, ``[1, 2]``, ``"text"``), and a bare
word that is not valid TOML (``conical``) is taken as a string. Unknown keys are
not rejected here: the scenario schema rejects them, naming the full key.
"""

from __future__ import annotations

import copy
import tomllib

from corneasim.errors import InputError


def parse_override(text: str) -> tuple[list[str], object]:
    """Split ``"a.b=value"`` into (``["a", "b"]``, parsed value).

    >>> parse_override("instrument.speed=5")
    (['instrument', 'speed'], 5)
    >>> parse_override("instrument.tip=conical")
    (['instrument', 'tip'], 'conical')
    """
    key, separator, raw = text.partition("=")
    path = [part.strip() for part in key.split(".")]
    if not separator or not all(path):
        raise InputError(f"--set {text!r}: expected KEY=VALUE with a dotted key, e.g. instrument.speed=5")
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
        path = [part.strip() for part in str(key).split(".")]
        if not all(path):
            raise InputError(f"{origin}: key {key!r}: expected a dotted key, e.g. solver.target_time_step")
        _set(result, path, value, f"{origin}: {key!r}")
    return result


def _set(data: dict, path: list[str], value, origin: str) -> None:
    table = data
    for depth, part in enumerate(path[:-1]):
        child = table.setdefault(part, {})
        if not isinstance(child, dict):
            raise InputError(f"{origin}: '{'.'.join(path[: depth + 1])}' is a value, not a table")
        table = child
    table[path[-1]] = value
