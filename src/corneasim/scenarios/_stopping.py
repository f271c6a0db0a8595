"""Stopping a run on request: Ctrl-C (SIGINT), a batch scheduler's SIGTERM, a closed terminal's SIGHUP.

All three mean "stop and keep what you have". During the time loop
(:class:`StopRequest`) the first signal only sets a flag; the loop stops at its next
consistent point (a history step), writes a checkpoint and the partial summary and
raises :class:`KeyboardInterrupt`, so ``corneasim run --resume DIR`` continues it. A
second signal stops at once (:attr:`StopRequest.forced`), without a new checkpoint: the
state may be half-way through a step, and the last periodic checkpoint stays valid.

Outside the time loop (reading input, building the model) :func:`stop_signals_interrupt`
makes SIGTERM and SIGHUP raise :class:`KeyboardInterrupt` as SIGINT does by default, so the
command ends with its interruption message and exit code 130 whichever of them arrived.
SIGKILL cannot be caught: what it leaves (a torn last history row) is repaired on resume
(:func:`corneasim.output.trim_table`).
"""

from __future__ import annotations

import signal
import threading
from contextlib import contextmanager

STOP_SIGNALS = tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))
"""The signals that stop a run and keep its results (SIGHUP does not exist on Windows)."""


def _raise_interrupt(signum, frame):
    raise KeyboardInterrupt


def stop_signals_interrupt() -> None:
    """Make every signal of :data:`STOP_SIGNALS` raise :class:`KeyboardInterrupt` (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        return
    for number in STOP_SIGNALS:
        if number != signal.SIGINT:
            signal.signal(number, _raise_interrupt)


class StopRequest:
    """A stop signal turned into a flag that the time loop checks at consistent points.

    Attributes
    ----------
    requested : str or None
        The name of the first stop signal received (``"SIGTERM"``), None before any.
    forced : bool
        A second signal arrived and stopped the run at once (no consistent state to save).
    """

    def __init__(self):
        self.requested: str | None = None
        self.forced = False

    @contextmanager
    def installed(self):
        """Handle :data:`STOP_SIGNALS` while the block runs (main thread only), then restore the handlers."""
        if threading.current_thread() is not threading.main_thread():
            yield self
            return
        previous = {number: signal.signal(number, self._handle) for number in STOP_SIGNALS}
        try:
            yield self
        finally:
            for number, handler in previous.items():
                signal.signal(number, handler)

    def _handle(self, signum, frame):
        if self.requested:
            self.forced = True
            raise KeyboardInterrupt
        self.requested = signal.Signals(signum).name

    def reason(self) -> str:
        """One line for the summary: which signal stopped the run."""
        name = self.requested or "SIGINT"
        return f"stopped by {name}" + (" (a second signal: no checkpoint at the stop)" if self.forced else "")
