"""Result plots: force curves against experiment (needle paper Figs. 8-9); the stress maps are
:mod:`corneasim.output._stress_maps`.

Figures are ``matplotlib.figure.Figure`` objects rendered to PNG (Agg) and written
atomically into ``plots/``. Neither pyplot nor a backend switch is involved, so running a
scenario from a notebook leaves the user's matplotlib backend and figures alone.
"""

from __future__ import annotations

import io
import re
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from corneasim.output._files import atomic_write_bytes


def save(figure: Figure, path: Path) -> None:
    """Save a figure as PNG atomically."""
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=130, bbox_inches="tight")
    atomic_write_bytes(path, buffer.getvalue())


def experiment_label(column: str) -> str:
    """The legend entry of an experimental force column: its speed when the name has one.

    >>> experiment_label("experiment_1mm_s_N")
    'experiment (1 mm/s)'
    """
    speed = re.search(r"(\d+(?:\.\d+)?)mm_s", column)
    return f"experiment ({speed.group(1)} mm/s)" if speed else "experiment"


def draw_instrument(axes, section) -> None:
    """Fill the instrument's section (X, Z, D) of ``instruments._outline.instrument_section`` in
    grey: where the signed distance D < 0 (nothing for None)."""
    if section is None:
        return
    X, Z, D = section
    if np.any(D < 0.0):
        axes.contourf(X, Z, D, levels=[D.min() - 1.0, 0.0], colors=["0.55"], zorder=3)
        axes.contour(X, Z, D, levels=[0.0], colors=["0.2"], linewidths=0.6, zorder=3)


def force_plot(x, force, fit, experiment, punctures, *, x_label: str, title: str, path: Path,
               force_label: str = "force, N", range_fit=None) -> None:
    """Raw simulated force, its Gaussian fit, the experiment and the puncture points.

    Parameters
    ----------
    x, force : ndarray
        Abscissa (depth mm or time s) and simulated force, N.
    fit : callable or None
        Fitted curve (x -> N).
    experiment : tuple (x, y, label) or None
        Experimental table.
    punctures : list of (label, x, force)
        Puncture events to mark.
    range_fit : tuple (callable, (x0, x1)) or None
        The fit the experiment was compared with when it covers only part of the run, and
        that part (drawn dashed over it).
    """
    figure = Figure(figsize=(6.4, 4.2))
    axes = figure.subplots()
    axes.plot(x, force, color="0.55", lw=0.8, label="simulation (raw)")
    if fit is not None:
        axes.plot(x, fit(x), color="C0", lw=2.0, label="simulation (Gaussian fit)")
    if range_fit is not None:
        curve, (x0, x1) = range_fit
        part = x[(x >= x0) & (x <= x1)]
        axes.plot(part, curve(part), "--", color="C2", lw=1.6,
                  label=f"simulation (Gaussian fit to {x1:g}, validated)")
    if experiment is not None:
        exp_x, exp_y, label = experiment
        axes.plot(exp_x, exp_y, "o-", color="C3", ms=4, label=label)
    near = 0.02 * (float(np.max(x)) - float(np.min(x))) if len(x) else 0.0
    for k, (label, event_x, event_force) in enumerate(punctures):
        axes.plot([event_x], [event_force], "kv", ms=7)
        # events at (nearly) one depth share a marker: stack their labels instead of overprinting
        rank = sum(abs(event_x - other[1]) <= near for other in punctures[:k])
        axes.annotate(label, (event_x, event_force), textcoords="offset points", xytext=(4, 6 + 10 * rank),
                      fontsize=8)
    axes.set_xlabel(x_label)
    axes.set_ylabel(force_label)
    axes.set_title(title, fontsize=10)
    axes.grid(alpha=0.3)
    axes.legend(fontsize=8, loc="upper left")
    save(figure, path)
