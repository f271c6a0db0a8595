"""The prestressed reference of a scenario (``preload.stress_free_reference``): the eye's stress-free geometry.

The eye's mesh is its geometry measured at its intraocular pressure. With
``stress_free_reference = true`` the model is built instead on the stress-free geometry X
whose preload gives the mesh's geometry back, found by backward displacement
(:func:`corneasim.solver.backward_displacement`): each iteration builds the scenario on X
and runs its preload as the run does (the same stage, damping, relaxation and hooks), so
the procedure starts from the measured eye, loaded and prestressed: the run starts from the
preload of the solve that converged (its setup and state), as from its own. The fibre frames stay
the measured mesh's (``scenarios._build``): the fibres lie along the measured lamellae.

The iteration is cached in the results folder as ``reference.npz`` (the current X, the
nodal errors so far, whether it converged, and the key of what it depends on, as the
reused preload's, :mod:`corneasim.scenarios._preload_reuse`): it is saved after each
solve, so a resumed run continues it or, once converged, builds on it at once; a run with
``--preload-from DIR`` takes it from DIR. docs/solver.md, "Prestressed reference".
"""

from __future__ import annotations

import io
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from corneasim.errors import InputError
from corneasim.output import atomic_write_bytes, track
from corneasim.scenarios._preload_reuse import preload_key
from corneasim.solver import SimulationError, StressFreeReference, backward_displacement, new_state, preload

REFERENCE_FILE = "reference.npz"


def wants_reference(scenario) -> bool:
    """Whether ``scenario`` (validated) is built on a stress-free reference."""
    return scenario.preload is not None and scenario.preload.stress_free_reference


def save_reference(path: Path, reference: StressFreeReference, key: dict) -> None:
    """Write the iteration's state and its key to ``path`` (atomically)."""
    buffer = io.BytesIO()
    np.savez(buffer, points=reference.points, errors=np.asarray(reference.errors, dtype=float),
             converged=np.array(reference.converged), key=np.array(json.dumps(key, sort_keys=True)))
    atomic_write_bytes(path, buffer.getvalue())


def load_reference(path: Path, key: dict, n_nodes: int) -> StressFreeReference | None:
    """The iteration saved at ``path`` by a run of the same key (None when there is none or the key differs)."""
    if not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            if json.loads(str(data["key"])) != json.loads(json.dumps(key, sort_keys=True)):
                return None
            points = np.array(data["points"], dtype=float)
            reference = StressFreeReference(points, [float(e) for e in data["errors"]], bool(data["converged"]))
    except (KeyError, OSError, ValueError) as error:
        raise InputError(f"{path}: not a corneasim stress-free reference ({error})") from None
    return reference if points.shape[0] == n_nodes else None


def preloaded_points(mesh, displacement: np.ndarray) -> np.ndarray:
    """The geometry (n_nodes, dim), mm, of ``mesh`` displaced by ``displacement`` (mm), the axis
    nodes of an axisymmetric mesh kept on the axis: a penalty that holds them there (the cut
    band's, ``fracture._cut_band``) leaves them a radial displacement of round-off size, which
    the iteration would otherwise take to a negative radius."""
    points = mesh.points + displacement
    if mesh.axisymmetric:
        points[mesh.points[:, 0] == 0.0, 0] = 0.0
    return points


@dataclass
class SettledPreload:
    """The preload of a scenario built on some reference points, run to its end.

    Attributes
    ----------
    setup : Setup
        Built on the points (its hooks as the preload left them).
    state : State
        At the end of the preload.
    last_row : dict or None
        The preload's last history row (solver time), as the runner records it.
    key : dict
        :func:`~corneasim.scenarios._preload_reuse.preload_key` of the setup, taken before the
        first step.
    """

    setup: object
    state: object
    last_row: dict | None
    key: dict


def settle(scenario, base_dir, points: np.ndarray, *, interrupt=None, progress: bool = False,
           label: str = "reference") -> SettledPreload:
    """The preload of ``scenario`` built on ``points`` (n_nodes, dim), mm, run to its end.

    ``scenario`` is in physical time (as :func:`corneasim.scenarios._build.build` takes it); the
    preload is the runner's (stage, damping, relaxation, hooks, history interval), so the run can
    start from its end as from its own preload. ``interrupt`` (a :class:`StopRequest`) stops it
    between frames.
    """
    from corneasim.scenarios._build import build

    try:
        setup = build(scenario, base_dir, reference_points=points)
    except InputError as error:  # an iterate folded an element: the iteration failed, not the input
        raise SimulationError(f"stress-free reference: {label}: {error}", 0.0) from None
    key = preload_key(setup)
    model, solved = setup.model, setup.scenario
    state = new_state(model)
    stage = preload(model, state, setup.preload_duration, solved.preload.damping,
                    history_every=solved.solver.history_every, relaxed=solved.preload.relaxed,
                    checkpoint_every=solved.solver.checkpoint_every, deletion_every=solved.solver.deletion_every,
                    hooks=setup.hooks)
    last_row = None
    for frame in track(stage, setup.preload_duration, description=label, enabled=progress):
        if frame.history and frame.done:
            last_row = frame.history
        if interrupt is not None and interrupt.requested:
            raise KeyboardInterrupt
    return SettledPreload(setup, state, last_row, key)


def stress_free_reference(scenario, base_dir, measured: np.ndarray, key: dict, *, folder: Path | None = None,
                          source: Path | None = None, interrupt=None, progress: bool = False
                          ) -> tuple[StressFreeReference, SettledPreload | None]:
    """The converged stress-free reference of ``scenario`` (physical time) whose mesh is ``measured``,
    and the preload of its last solve (None when the reference was saved by an earlier run).

    Parameters
    ----------
    scenario : Scenario
        Validated, physical time, with ``preload.stress_free_reference``.
    base_dir : path-like
        Folder of the scenario's relative paths.
    measured : ndarray (n_nodes, dim), mm
        The mesh's points (the geometry under the preload's loads).
    key : dict
        What the reference depends on (:func:`corneasim.scenarios._preload_reuse.preload_key`
        of the setup built on ``measured``).
    folder : Path, optional
        Results folder: the iteration is continued from its ``reference.npz`` and saved there.
    source : Path, optional
        Results folder (or its ``preload.npz``) of a run whose converged reference is taken
        (``--preload-from``); InputError when it has none of this key.
    interrupt : StopRequest, optional
    progress : bool

    Returns
    -------
    (StressFreeReference, SettledPreload or None)
        The preload of the solve that converged is the run's own: the run starts from it.

    Raises
    ------
    SimulationError
        Not converged within ``preload.reference_iterations`` solves.
    """
    if source is not None:
        path = source if source.is_dir() else source.parent
        reference = load_reference(path / REFERENCE_FILE, key, measured.shape[0])
        if reference is None or not reference.converged:
            raise InputError(f"--preload-from: {path / REFERENCE_FILE} holds no converged stress-free reference "
                             "of this scenario (preload.stress_free_reference)")
        return reference, None
    start = load_reference(folder / REFERENCE_FILE, key, measured.shape[0]) if folder is not None else None
    settings = scenario.preload
    solves = [len(start.errors) if start is not None else 0]
    last: list[SettledPreload | None] = [None]

    def solve(points):
        solves[0] += 1
        last[0] = settle(scenario, base_dir, points, interrupt=interrupt, progress=progress,
                         label=f"reference {solves[0]}")
        return preloaded_points(last[0].setup.mesh, last[0].state.u)

    def save(reference):
        if folder is not None:
            save_reference(folder / REFERENCE_FILE, reference, key)

    reference = backward_displacement(measured, solve, settings.reference_tolerance, settings.reference_iterations,
                                      start=start, on_iteration=save)
    return reference, last[0]


def reference_report(reference: StressFreeReference, measured: np.ndarray, loaded: np.ndarray | None,
                     tolerance: float) -> dict:
    """``summary.json`` ``stress_free_reference``: the iteration's errors (mm), how far the
    reference lies from the mesh (mm), and the largest nodal distance between the run's own
    preloaded geometry ``loaded`` and the mesh (mm; None when this process did not run the preload)."""
    offset = np.sqrt(((reference.points - measured) ** 2).sum(axis=1))
    return {"iterations": len(reference.errors), "errors_mm": reference.errors, "tolerance_mm": tolerance,
            "largest_offset_mm": float(offset.max()),
            "loaded_error_mm": None if loaded is None else float(np.sqrt(((loaded - measured) ** 2).sum(axis=1)).max())}
