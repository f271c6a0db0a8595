"""What a run keeps about itself for a resume and for a truthful summary.

A checkpoint holds the solver's state; a resumed run rebuilds everything else from the
scenario, except what happened before the checkpoint and is not in the state: the report
of the preload's end (``summary.json`` ``run.preload``) and the warnings met so far.
:func:`save_run_checkpoint` stores them with the checkpoint (entry :data:`RUN_RECORD`) and
:func:`restore_run_record` gives them back to the resumed run.

:func:`failure_reason` and :func:`safe_summary` make the summary of any run truthful: an
unexpected exception is named in one line, and a state too broken to be summarised still
gives a summary with its status and reason.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from corneasim.scenarios._postprocess import summarise
from corneasim.solver import save_checkpoint

RUN_RECORD = "run_record"
"""Checkpoint entry (JSON): the preload's end report and the warnings of the run so far."""


def save_run_checkpoint(path: Path, setup, state) -> None:
    """Save the checkpoint of ``state`` at ``path``, with the run record (:data:`RUN_RECORD`)."""
    record = {"preload": setup.preload_end, "warnings": setup.warnings}
    save_checkpoint(path, setup.model, state, setup.hooks,
                    extra={RUN_RECORD: np.array(json.dumps(record, default=float))})


def restore_run_record(setup, path: Path) -> None:
    """Give ``setup`` the preload report and the warnings of the run that wrote the checkpoint at ``path``."""
    with np.load(path, allow_pickle=False) as data:
        if RUN_RECORD not in data:
            return
        record = json.loads(str(data[RUN_RECORD]))
    if setup.preload_end is None:
        setup.preload_end = record.get("preload")
    setup.warnings.extend(warning for warning in record.get("warnings", []) if warning not in setup.warnings)


def failure_reason(failure: BaseException) -> str:
    """One line naming an unexpected exception: ``LinAlgError: Array must not contain infs or NaNs.``"""
    text = " ".join(str(failure).split())
    return f"{type(failure).__name__}: {text}" if text else type(failure).__name__


def safe_summary(setup, history, deletions, state, wall, status, error) -> dict:
    """:func:`~corneasim.scenarios._postprocess.summarise`; for a run so broken that it cannot be
    summarised, its status and reasons only."""
    try:
        return summarise(setup, history, deletions, state, wall, status, error)
    except Exception as failure:
        return {"scenario": setup.scenario.name, "kind": setup.scenario.kind,
                "status": "failed" if status == "completed" else status,
                "error": error or f"the summary failed: {failure_reason(failure)}"}
