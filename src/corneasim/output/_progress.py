"""A progress bar with ETA over simulated time, for any frame generator.

The solver's time loop is a generator of frames; :func:`track` wraps it and
advances a rich progress bar by the simulated time of each frame (so the ETA is
wall time per simulated second, which is what a user waits for), measured from the
stage's first frame (a procedure stage starts where the preload ended). The bar goes to
stderr and disappears when output is not a terminal (CI, pipes), where a plain
line every ``plain_interval`` seconds of wall time is printed instead.
"""

from __future__ import annotations

import sys
import time as wallclock
from collections.abc import Iterable, Iterator


def track(frames: Iterable, end_time: float, description: str = "simulating",
          time_of=lambda frame: frame.time, enabled: bool = True, plain_interval: float = 30.0) -> Iterator:
    """Yield the frames unchanged while showing progress towards ``end_time`` (s)."""
    if not enabled:
        yield from frames
        return
    from rich.console import Console  # imported here: a run without a bar (a study case, a script) never needs rich

    console = Console(file=sys.stderr)
    if not console.is_terminal:
        last = wallclock.monotonic()
        start, start_time = last, None
        for frame in frames:
            now = wallclock.monotonic()
            if start_time is None:
                start, start_time = now, time_of(frame)
            elif now - last >= plain_interval:
                span = end_time - start_time
                fraction = min((time_of(frame) - start_time) / span, 1.0) if span > 0 else 1.0
                remaining = (now - start) * (1 - fraction) / fraction if fraction > 0 else float("nan")
                print(f"{description}: {100 * fraction:5.1f}% of the stage (t = {time_of(frame):.4g} of "
                      f"{end_time:g} s), about {remaining:.0f} s left", file=sys.stderr)
                last = now
            yield frame
        return
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

    columns = (
        TextColumn("{task.description}"),
        BarColumn(),
        TextColumn("{task.completed:.4g}/{task.total:.4g} s"),
        TimeElapsedColumn(),
        TextColumn("ETA"),
        TimeRemainingColumn(),
    )
    with Progress(*columns, console=console, transient=False) as progress:
        task = progress.add_task(description, total=end_time)
        for frame in frames:
            progress.update(task, completed=min(time_of(frame), end_time))
            yield frame
