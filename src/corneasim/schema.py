"""Base for every configuration model: unknown keys and wrong types are errors.

Configuration (scenario TOML files, material files) is validated with pydantic.
Every model derives from :class:`StrictModel`, so a misspelt key is reported as
``unknown key`` instead of being silently ignored, and types are strict: numbers are
not accepted for strings (or the reverse), nor booleans for numbers (``end_time =
true`` is no 1.0 s), and an integer is written without quotes (``"20"`` is refused); a
float accepts an integer. Numbers must be finite (TOML's ``inf`` and ``nan`` are refused). :func:`load_toml` reads a TOML file and turns a
syntax error into an :class:`~corneasim.errors.InputError` naming the file and line.
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import TypeVar

import pydantic

from corneasim.errors import InputError, format_validation_error

Model = TypeVar("Model", bound=pydantic.BaseModel)


class StrictModel(pydantic.BaseModel):
    """Forbid unknown keys, coercion between types and non-finite numbers; keep instances immutable."""

    model_config = pydantic.ConfigDict(extra="forbid", frozen=True, strict=True, allow_inf_nan=False)


def load_toml(path: str | Path) -> dict:
    """Read a TOML file; syntax errors become one-line :class:`InputError`."""
    path = Path(path)
    try:
        with path.open("rb") as handle:
            return tomllib.load(handle)
    except FileNotFoundError:
        raise InputError(f"{path}: file not found") from None
    except UnicodeDecodeError as error:
        raise InputError(f"{path}: not a TOML text file (not UTF-8 at byte {error.start})") from None
    except tomllib.TOMLDecodeError as error:
        raise InputError(f"{path}: invalid TOML: {error}") from None
    except OSError as error:
        raise InputError(f"{path}: cannot read ({error.strerror or type(error).__name__})") from None


def validate(model: type[Model], data: dict, source: str | None = None) -> Model:
    """Validate ``data`` against ``model``; failures become one-line :class:`InputError`."""
    try:
        return model.model_validate(data)
    except pydantic.ValidationError as error:
        raise InputError(format_validation_error(error, source)) from None
