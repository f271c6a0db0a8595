"""The needle scenario's speed option: one speed sets the motion, the duration and the validation column.

The experiment was run at 1 and 5 mm/s to the same depth of 0.7 mm (needle paper sec. 2.4,
Table 2), so a speed v means insertion rate v, procedure time 0.7 / v and, where the paper
has it, the experimental column at that speed.
"""

from __future__ import annotations

DEPTH = 0.7
"""Insertion depth of the paper's experiments and simulations, mm."""

EXPERIMENT_COLUMNS = {1.0: "experiment_1mm_s_N", 5.0: "experiment_5mm_s_N"}
"""Needle paper Table 2 columns by insertion speed (mm/s)."""


def speed_overrides(speed: float, depth: float = DEPTH) -> list[str]:
    """``--set`` overrides for an insertion at ``speed`` (mm/s) to ``depth`` (mm)."""
    overrides = [f"instrument.motion.insertion.rate={speed!r}", f"solver.end_time={depth / speed!r}"]
    if speed in EXPERIMENT_COLUMNS:
        overrides.append(f"validation.y_column={EXPERIMENT_COLUMNS[speed]}")
    return overrides
