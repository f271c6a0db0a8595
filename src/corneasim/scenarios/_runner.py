"""Run a scenario: preload, procedure, results folder, checkpoints, interruption and resume.

:func:`simulate` is the one call behind ``corneasim run`` and the Python API. Without
``out_dir`` it touches no file and returns the history as arrays and the summary as a
dict. With ``out_dir`` it keeps a results folder that is valid at every moment:

* ``scenario.toml``: the fully resolved input (written first);
* ``history.csv``: one flushed row per history step (procedure time, t = 0 when the
  instrument starts);
* ``deletions.csv``: every deleted element (time_s, element, block);
* ``fields/fields.pvd`` + VTU frames; ``checkpoint.npz``: the last good state;
* ``summary.json``: written at the end, and also when the run fails or is interrupted
  (``status`` says which), so the history so far is never lost;
* ``reference.npz``: the stress-free reference and its iteration (``preload.stress_free_reference``,
  :mod:`corneasim.scenarios._prestress`);
* ``report.html``: the run on one page (:mod:`corneasim.output._run_report`), after the summary.

The folder belongs to the run (:class:`~corneasim.output.ResultsFolder`:
locked while it runs; an earlier run's files are refused or, with ``overwrite``, cleared),
and it is claimed only once every input has been checked (the scenario's meaning,
:mod:`corneasim.scenarios._meaning`; the mesh, the materials and a reused preload, while
building). Any exception during the run ends with ``status: failed`` and its one-line
reason in the summary.

Ctrl-C (SIGINT), SIGTERM and SIGHUP set a flag (:mod:`corneasim.scenarios._stopping`); the
loop stops at the next history step, where the state is consistent, writes a checkpoint and
the partial summary, and raises :class:`KeyboardInterrupt`. ``simulate(..., resume=True)``
continues from the checkpoint (from the start when the run stopped before its first one).
"""

from __future__ import annotations

import sys
import time as wallclock
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from corneasim.errors import InputError
from corneasim.output import HistoryWriter, OrphanNodes, ResultsFolder, TimeSeriesWriter, atomic_write_text, track
from corneasim.output import cached_for_this_machine, process_age, trim_table, write_json, write_run_report
from corneasim.scenarios._build import Setup, build, place_on_tissue
from corneasim.scenarios._meaning import check_scenario, check_setup
from corneasim.scenarios._postprocess import preload_report, procedure_row
from corneasim.scenarios._preload_reuse import load_preload, preload_key, save_preload
from corneasim.scenarios._prestress import preloaded_points, reference_report, stress_free_reference, wants_reference
from corneasim.scenarios._quasi_static import finish as finish_quasi_static
from corneasim.scenarios._quasi_static import prepare as prepare_quasi_static
from corneasim.scenarios._report import write_plots
from corneasim.scenarios._run_record import failure_reason, restore_run_record, safe_summary, save_run_checkpoint
from corneasim.scenarios._stopping import StopRequest
from corneasim.solver import (
    SimulationError, field_output, load_checkpoint, new_state, preload, run)
from corneasim.solver.elements import FORCE_KERNELS

CHECKPOINT = "checkpoint.npz"
INSTANT_TOLERANCE = 0.01
"""A field frame within this time (s) after a figure instant is that instant's snapshot."""
COMPILING = ("compiling the solver's kernels for this processor, once: about a minute before the first "
             "step (later runs load them from Numba's cache)")
"""The line a terminal shows when the element-force kernel has no cached code for this machine."""


@dataclass
class Result:
    """What a run returns.

    Attributes
    ----------
    history : dict of str to ndarray
        History columns (units in the names), procedure time ``time_s`` from 0.
    summary : dict
        The summary (as in ``summary.json``).
    deletions : list of (float, int, str)
        Deleted elements: (procedure time s, element index, block).
    out_dir : Path or None
        The results folder, if one was written.
    """

    history: dict
    summary: dict
    deletions: list = field(default_factory=list)
    out_dir: Path | None = None


def half_model_image(setup: Setup) -> tuple[float, float, float] | None:
    """The diagonal of the symmetry that completes a 3D half model (field output written whole,
    ``TimeSeriesWriter``): (-1, -1, 1) for cyclic symmetry about z, -1 on the normal of a single
    symmetry plane; None for an axisymmetric or whole model, or one with several planes."""
    if setup.mesh.axisymmetric or setup.mesh.dim != 3:
        return None
    halves = [c for c in setup.scenario.constraints if c.cyclic is not None or c.symmetry in ("x", "y", "z")]
    if len(halves) != 1:
        return None
    if halves[0].cyclic == "z":
        return (-1.0, -1.0, 1.0)
    return tuple(-1.0 if axis == halves[0].symmetry else 1.0 for axis in "xyz")


class _Recorder:
    """Collects history rows and deletions in memory and, with a folder, on disk."""

    def __init__(self, setup: Setup, out_dir: Path | None, resume_time: float | None):
        self.setup = setup
        self.out_dir = out_dir
        self.resume_time = resume_time
        self.rows: list[dict] = []
        self.last_raw_row: dict | None = None  # as the time loop gave it (solver time)
        self.deletions: list = []
        self.snapshots: dict = {}
        self.first_step_clock: float | None = None  # perf_counter at the end of the run's first step
        instants = setup.kind.figure_instants(setup.scenario)
        self.instants = {name: t for name, t in instants.items() if resume_time is None or t > resume_time}
        self.history_writer = None
        self.fields = None
        self.orphans = OrphanNodes(setup.mesh.cells, setup.mesh.n_nodes, setup.mesh.points.shape[1])
        if out_dir is not None:
            mesh = setup.mesh
            self.fields = TimeSeriesWriter(out_dir / "fields", mesh.points, mesh.cells, mesh.cell_type,
                                           resume_time=resume_time, image=half_model_image(setup),
                                           block_names=mesh.block_names)
            self.deletion_writer = HistoryWriter(out_dir / "deletions.csv", ["time_s", "element", "block"],
                                                 resume=resume_time is not None, resume_time=resume_time)
        if resume_time is not None and out_dir is not None and (out_dir / "history.csv").exists() \
                and trim_table(out_dir / "history.csv", resume_time) > 0:  # a torn row and later ones dropped
            from corneasim.data import read_table

            kept = read_table(out_dir / "history.csv")
            columns = list(kept)
            for index in range(len(kept[columns[0]])):
                if kept["time_s"][index] <= resume_time * (1 + 1e-12):
                    self.rows.append({name: kept[name][index] for name in columns})

    def history(self, raw: dict) -> None:
        self.last_raw_row = raw
        row = procedure_row(self.setup, raw)
        self.rows.append(row)
        if self.out_dir is None:
            return
        if self.history_writer is None:
            columns = [c for c in self.setup.kind.lead_columns if c in row]
            columns += [c for c in row if c not in columns]
            self.history_writer = HistoryWriter(self.out_dir / "history.csv", columns,
                                                resume=self.resume_time is not None,
                                                resume_time=self.resume_time)
        self.history_writer.append(row)

    def restore_deletions(self, state) -> None:
        """Take the deletions made before a checkpoint from the resumed state (for the summary)."""
        self.deletions = [(self.setup.procedure_time(float(t)), int(e), self.setup.model.block_of(int(e)))
                          for e, t in zip(state.deleted_element, state.deleted_time)]
        self.orphans.deleted(state.deleted_element, state.deleted_time)
        self.orphans.update(state.time, state.u, state.v, state.node_active)

    def deleted(self, events, state=None) -> None:
        """Record deletions (solver time, element, block); with the frame's ``state``, freeze the
        nodes they released (:mod:`corneasim.output._orphans`)."""
        self.orphans.deleted([e for _, e, _ in events], [t for t, _, _ in events])
        if state is not None:
            self.orphans.update(state.time, state.u, state.v, state.node_active)
        for time, element, block in events:
            time = self.setup.procedure_time(time)
            self.deletions.append((time, element, block))
            if self.out_dir is not None:
                self.deletion_writer.append({"time_s": time, "element": element, "block": block})

    def field(self, time: float, fields: dict) -> None:
        for name, instant in self.instants.items():  # the first frame in [instant, instant + 0.01 s]
            if name not in self.snapshots and instant - 1e-6 <= time <= instant + INSTANT_TOLERANCE:
                self.snapshots[name] = (time, fields)
        if self.fields is None:
            return
        point_keys = ("displacement", "velocity", "node_active")
        self.orphans.update(self.setup.solver_time(time), fields["displacement"], fields["velocity"],
                            fields["node_active"])
        fields = dict(fields, displacement=self.orphans.apply(fields["displacement"]))
        self.fields.write(time, {k: fields[k] for k in point_keys if k in fields},
                          {k: v for k, v in fields.items() if k not in point_keys})

    def arrays(self) -> dict:
        if not self.rows:
            return {}
        columns = list(self.rows[-1])
        return {name: np.array([row.get(name, np.nan) for row in self.rows], dtype=float) for name in columns}

    def close(self) -> None:
        if self.history_writer is not None:
            self.history_writer.close()
        if self.out_dir is not None:
            self.deletion_writer.close()


def simulate(scenario, *, out_dir: str | Path | None = None, base_dir: str | Path = ".",
             resume: bool = False, progress: bool = True, preload_from: str | Path | None = None,
             overwrite: bool = False, record: str | None = None, plots: bool = True) -> Result:
    """Run ``scenario`` (a validated :class:`~corneasim.scenarios._format.Scenario`).

    Parameters
    ----------
    scenario : Scenario
    out_dir : path-like, optional
        Results folder; None writes nothing. A run with a preload also writes its settled
        state there (``preload.npz``, :mod:`corneasim.scenarios._preload_reuse`).
    base_dir : path-like
        Folder that relative paths in the scenario refer to.
    resume : bool
        Continue from ``out_dir/checkpoint.npz``.
    progress : bool
        Show a progress bar with ETA on stderr.
    preload_from : path-like, optional
        Start from the settled preload of an earlier run of the same eye (its results folder
        or its ``preload.npz``) instead of settling again; the results are the same bit for bit.
    overwrite : bool
        Replace the files of an earlier run in ``out_dir`` (refused without it).
    record : str, optional
        The text of ``scenario.toml`` (the resolved input) to write into a new results folder.
    plots : bool
        Write ``plots/`` and ``report.html`` at the end (False: the data files only, as the
        cases of a study do unless asked; 1-2 s of matplotlib per run).

    Returns
    -------
    Result

    Raises
    ------
    InputError
        Bad input, found before the results folder is touched.
    SimulationError
        When the run blows up (the partial results are written first); any other exception
        during the run is also recorded as ``failed`` before it propagates.
    KeyboardInterrupt
        On Ctrl-C, SIGTERM or SIGHUP, after writing a checkpoint and the partial results.
    """
    started = wallclock.perf_counter()
    check_scenario(scenario)
    scenario, quasi_static = prepare_quasi_static(scenario, base_dir)
    physical = scenario  # in physical time, as build takes it
    setup = build(scenario, base_dir)
    check_setup(setup)
    scenario = setup.scenario  # in solver time (solver.time_scaling)
    model, solver = setup.model, scenario.solver
    _set_threads(solver.threads, model.n_elements)
    if progress:
        _announce_compilation(model.elements.kind)
    out_path = Path(out_dir) if out_dir is not None else None
    if preload_from is not None and (resume or scenario.preload is None):
        raise InputError("--preload-from: needs a scenario with a preload, and not --resume (a resumed "
                         "run continues from its own checkpoint)")
    measured = reference = loaded = None
    if wants_reference(scenario):  # built on the stress-free geometry whose preload gives the mesh's
        measured, reference_key = setup.mesh.points, preload_key(setup)
        if preload_from is not None:
            reference, _ = stress_free_reference(physical, base_dir, measured, reference_key, source=Path(preload_from))
            setup = build(physical, base_dir, reference.points)
            model = setup.model
    saves_or_reuses = scenario.preload is not None and (out_path is not None or preload_from is not None)
    key = preload_key(setup) if saves_or_reuses else None  # before a checkpoint softens rows
    reused = load_preload(preload_from, setup, key) if preload_from is not None else None
    settled_here = False  # the preload was settled by the reference's last solve
    if resume and out_path is None:
        raise InputError("resume: needs the results folder of the interrupted run")
    folder = ResultsFolder.claim(out_path, resume=resume, overwrite=overwrite) if out_path is not None else None
    try:
        if record is not None and not resume:
            atomic_write_text(out_path / "scenario.toml", record)
        resume = resume and (out_path / CHECKPOINT).is_file()  # stopped before its first checkpoint: start over
        if measured is not None and reference is None:
            reference, settled = _reference_or_summary(physical, base_dir, setup, measured, reference_key,
                                                       out_path, progress, started)
            if settled is None:  # saved by the interrupted run
                setup = build(physical, base_dir, reference.points)
                key = preload_key(setup) if saves_or_reuses else None
            else:  # the run starts from the preload of the solve that converged
                setup, key, reused, settled_here = settled.setup, settled.key, (settled.state, settled.last_row), True
            model = setup.model
        if resume:
            state = load_checkpoint(out_path / CHECKPOINT, model, setup.hooks)
            restore_run_record(setup, out_path / CHECKPOINT)
            setup.steps_before = state.step
            resume_time = setup.procedure_time(state.time)
        else:
            state = new_state(model)
            resume_time = None
        recorder = _Recorder(setup, out_path, resume_time)
        if resume:
            recorder.restore_deletions(state)
    except BaseException:
        if folder is not None:
            folder.release()
        raise
    status, error = "completed", None
    procedure_end = setup.preload_duration + solver.end_time
    options = dict(checkpoint_every=solver.checkpoint_every, deletion_every=solver.deletion_every,
                   hooks=setup.hooks)
    interrupt = StopRequest()
    try:
        with interrupt.installed():
            preloading = scenario.preload is not None and state.time < setup.preload_duration
            if preloading and reused is not None:
                state, last_row = reused
                recorder.deleted([(float(t), int(e), model.block_of(int(e)))  # as the preload logged them
                                  for e, t in zip(state.deleted_element, state.deleted_time)])
                if last_row is not None:
                    recorder.history(last_row)
                preload_report(setup, state)
                if settled_here and out_path is not None:
                    save_preload(out_path, setup, state, key, recorder.last_raw_row)
                elif not settled_here:
                    setup.steps_before = state.step
                    setup.preload_end["reused_from"] = str(preload_from)
            elif preloading:
                stage = preload(model, state, setup.preload_duration - state.time, scenario.preload.damping,
                                history_every=solver.history_every, relaxed=scenario.preload.relaxed,
                                **options)
                _consume(stage, setup, recorder, out_path, interrupt, record=False, record_last=True,
                         progress=progress, end=setup.preload_duration, label="preload")
                preload_report(setup, state)
                if out_path is not None:
                    save_preload(out_path, setup, state, key, recorder.last_raw_row)
            if preloading and reference is not None:
                loaded = preloaded_points(setup.mesh, state.u)
            if preloading and setup.instrument is not None:
                place_on_tissue(setup.mesh, setup.instrument, scenario.instrument.start_gap, state.u)
            start = field_output(model, state)
            if "0.0s" in recorder.instants:
                recorder.snapshots["0.0s"] = (setup.procedure_time(state.time), start)
            if solver.field_count and (resume_time is None or resume_time < 0.0):  # the frame at t = 0
                recorder.field(setup.procedure_time(state.time), start)
            field_times = setup.preload_duration + np.linspace(0.0, solver.end_time, solver.field_count) \
                if solver.field_count else ()
            scale = solver.time_scaling
            field_times = sorted({*field_times, *(setup.preload_duration + t / scale
                                                  for t in recorder.instants.values())})
            field_times = [t for t in field_times if t > state.time]
            stage = run(model, state, procedure_end, history_every=solver.history_every,
                        field_times=field_times, damping=solver.damping, events=setup.events, **options)
            _consume(stage, setup, recorder, out_path, interrupt, record=True, progress=progress,
                     end=procedure_end, label=scenario.name)
    except SimulationError as failure:
        status, error = "failed", str(failure)
        raise
    except KeyboardInterrupt:
        status, error = "interrupted", interrupt.reason()
        if out_path is not None and not interrupt.forced:
            save_run_checkpoint(out_path / CHECKPOINT, setup, state)
        raise
    except Exception as failure:  # a crash is a failed run, never a completed one
        status, error = "failed", failure_reason(failure)
        raise
    finally:
        try:
            recorder.close()
            history = recorder.arrays()
            wall = wallclock.perf_counter() - started
            if quasi_static is not None:
                quasi_static = finish_quasi_static(quasi_static, history, setup.warnings)
            distortion = setup.distortion.report(setup.procedure_time, setup.warnings) if setup.distortion else None
            summary = safe_summary(setup, history, recorder.deletions, state, wall, status, error)
            if "run" in summary:
                summary["run"]["startup_s"] = startup_time(recorder.first_step_clock)
            if quasi_static is not None:
                summary["quasi_static"] = quasi_static
            if reference is not None:
                summary["stress_free_reference"] = reference_report(reference, measured, loaded,
                                                                    scenario.preload.reference_tolerance)
            if distortion is not None:
                summary["distortion"] = distortion
            if out_path is not None:
                write_json(out_path / "summary.json", summary)
                if plots:
                    if status == "completed":
                        _finish(setup, model, state, history, summary, recorder, out_path)
                    write_run_report(out_path)
        finally:
            if folder is not None:
                folder.release()
            global _previous_run_end
            _previous_run_end = wallclock.perf_counter()
    result = Result(history, summary, recorder.deletions, out_path)
    return result


_previous_run_end: float | None = None
"""``time.perf_counter()`` when the previous run of this process ended (None before the first)."""


def startup_time(first_step_clock: float | None) -> float | None:
    """The run's start-up, s: from the start of the process (or, for a later run in the same
    process, from the end of the previous run) to the end of the run's first time step
    (``first_step_clock``, :attr:`corneasim.solver.Frame.first_step_clock`): imports, the
    scenario's validation, mesh, model and the kernels loaded from the Numba cache. None for a
    run that took no step, or where the process's start time is not readable."""
    age = process_age()
    if first_step_clock is None or age is None:
        return None
    now = wallclock.perf_counter()
    start = now - age if _previous_run_end is None else max(now - age, _previous_run_end)
    return first_step_clock - start


PARALLEL_MIN_ELEMENTS = 5000
"""Below this many elements a run uses one thread by default: the per-step thread
synchronisation costs more than it saves, and on a loaded machine it can cost 100x."""


def _set_threads(threads: int | None, n_elements: int) -> None:
    """Numba threads for the element kernels: as configured, else all cores for large models."""
    import numba

    available = numba.config.NUMBA_NUM_THREADS
    if threads is None:
        threads = available if n_elements >= PARALLEL_MIN_ELEMENTS else 1
    numba.set_num_threads(min(threads, available))


def _announce_compilation(element_kind: str) -> None:
    """Print :data:`COMPILING` to a terminal's stderr when the model's force kernel is not in
    Numba's cache for this machine (a first run after installing: the bar would stand still)."""
    kernel = FORCE_KERNELS[0] if element_kind == "quad" else FORCE_KERNELS[1]
    if sys.stderr.isatty() and cached_for_this_machine(kernel) is False:
        print(COMPILING, file=sys.stderr)


def _reference_or_summary(scenario, base_dir, setup, measured, key, out_path, progress, started):
    """:func:`~corneasim.scenarios._prestress.stress_free_reference` in the claimed results folder;
    when it fails or is stopped, the summary says so (``status``, ``error``) before it propagates."""
    interrupt = StopRequest()
    try:
        with interrupt.installed():
            return stress_free_reference(scenario, base_dir, measured, key, folder=out_path, interrupt=interrupt,
                                         progress=progress)
    except BaseException as failure:
        if isinstance(failure, KeyboardInterrupt):
            status, error = "interrupted", interrupt.reason()
        else:
            status = "failed"
            error = str(failure) if isinstance(failure, SimulationError) else failure_reason(failure)
        if out_path is not None:
            summary = safe_summary(setup, {}, [], new_state(setup.model), wallclock.perf_counter() - started,
                                   status, error)
            write_json(out_path / "summary.json", summary)
        raise


def _consume(frames, setup, recorder, out_path, interrupt, *, record, progress, end, label,
             record_last=False):
    """Hand the frames of one stage to the recorder; checkpoint; honour Ctrl-C at a consistent point.

    ``record_last``: keep the history row of the stage's last frame even when not recording (the
    preload's last row is the procedure's first, at t = 0: the table's zero depth or time is then
    inside the simulated range that the validation interpolates)."""
    for frame in track(frames, end, description=label, enabled=progress):
        time = setup.procedure_time(frame.time)
        if recorder.first_step_clock is None:
            recorder.first_step_clock = frame.first_step_clock
        if frame.history and (record or record_last and frame.done):
            recorder.history(frame.history)
        if record and frame.fields:
            recorder.field(time, frame.fields)
        if frame.deletions:
            recorder.deleted(frame.deletions, frame.state)
        for event in frame.events:  # recorded where the time loop reports it: a field snapshot
            fields = field_output(setup.model, frame.state)
            recorder.snapshots[event] = (time, fields)
            recorder.field(time, fields)
        if out_path is not None and frame.checkpoint_due:
            save_run_checkpoint(out_path / CHECKPOINT, setup, frame.state)
        if interrupt.requested:
            raise KeyboardInterrupt


def _finish(setup, model, state, history, summary, recorder, out_path: Path) -> None:
    """The end's field frame and the plots of a completed run; a failure there fails the run."""
    try:
        recorder.snapshots["end"] = (setup.procedure_time(state.time), field_output(model, state))
        write_plots(setup, history, summary, recorder.snapshots, out_path)
    except Exception as failure:
        summary.update(status="failed", error=f"writing the plots: {failure_reason(failure)}")
        write_json(out_path / "summary.json", summary)
        raise
