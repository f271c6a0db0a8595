"""Errors that reach the user as one line and exit code 2.

Every check of user input (configuration keys, material constants, meshes, CSV
files, command-line values) raises :class:`InputError` with a message that names
the offending key, file, line or element and says what was expected. The CLI
prints ``corneasim: error: <message>`` and exits with status 2, without a
traceback. Errors that are not input errors (bugs, a run that blows up) keep
their traceback or their own handling.
"""

from __future__ import annotations

EXIT_FAILED = 1
"""Exit code of a simulation that failed (its reason in summary.json and on stderr)."""
EXIT_INPUT_ERROR = 2
"""Exit code of bad input: nothing was run."""
EXIT_INTERRUPTED = 130
"""Exit code of a run stopped by SIGINT, SIGTERM or SIGHUP (resumable)."""


class InputError(ValueError):
    """Bad user input: the message is one line naming the culprit."""

    def __init__(self, message: str):
        super().__init__(" ".join(str(message).split()))


def format_validation_error(error, source: str | None = None) -> str:
    """One line from a pydantic ``ValidationError``: first problem, with its key path.

    Parameters
    ----------
    error : pydantic.ValidationError
        The validation error.
    source : str, optional
        File the data came from, prefixed to the message.

    Returns
    -------
    str
        For example ``"needle.toml: material.c10: Input should be a valid number"``.
    """
    problems = error.errors()
    first = problems[0]
    key = ".".join(str(part) for part in first.get("loc", ())) or "<root>"
    message = first.get("msg", "invalid value").removeprefix("Value error, ")  # a validator's own sentence
    if first.get("type") == "extra_forbidden":
        message = "unknown key"
    elif isinstance(first.get("input"), (bool, int, float, str)) and len(repr(first["input"])) <= 40:
        message += f", got {_toml_value(first['input'])}"
    text = f"{key}: {message}"
    if len(problems) > 1:
        text += f" (and {len(problems) - 1} more problem{'s' if len(problems) > 2 else ''})"
    return f"{source}: {text}" if source else text


def _toml_value(value) -> str:
    """A scalar as TOML writes it (``true``, ``"20"``, ``inf``)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    return repr(value)
