"""Plots of a trephine run: forces against the experiment (paper Figs. 4, 7) and stress sections (Fig. 5).

``plots/forces.png``: the rotation angle, the linear cutting force F_z (raw, its eq. 14
Gaussian fit, the robot experiment) and the rotary cutting force F_c (raw, its envelope
over one rotation period, the experiment) against time.
``plots/stress-<event>.png``: von Mises stress on the deformed symmetry plane y = 0 of the
half model (the section through the trephine axis), around the cut at x = R, at the Fig. 5
instants, the puncture events and the end of the run.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from matplotlib.figure import Figure

from corneasim.instruments import instrument_section
from corneasim.output import save
from corneasim.scenarios._trephine import EXPERIMENT_COLUMNS, FIGURE_5_INSTANTS, fc_envelope


def _experiment(setup) -> dict | None:
    if setup.scenario.validation is None:
        return None
    from corneasim.data import load_dataset

    data = load_dataset(setup.scenario.validation.dataset)
    return {key: (data.columns["time_s"], data.columns[column]) for key, column in EXPERIMENT_COLUMNS.items()}


def forces_figure(setup, history: dict, summary: dict, path: Path) -> None:
    """Three panels against time: rotation angle (rad), F_z (N), F_c (N), with the experiment."""
    from corneasim.analysis import gaussian_sum

    time = history["time_s"]
    experiment = _experiment(setup)
    figure = Figure(figsize=(6.4, 8.0))
    axes = figure.subplots(3, 1, sharex=True)
    axes[0].plot(time, history["angle_rad"], color="C2", lw=1.0)
    axes[0].set_ylabel("rotation, rad")
    axes[1].plot(time, history["fz_N"], color="0.55", lw=0.8, label="simulation (raw)")
    fit = summary.get("fit")
    if fit:
        a, b, c = (np.asarray(fit[key]) for key in "abc")
        axes[1].plot(time, gaussian_sum(time, a, b, c), color="C0", lw=2.0, label="simulation (eq. 14 fit)")
    for event in summary.get("punctures", []):
        axes[1].plot([event["time_s"]], [event["fz_N"]], "kv", ms=7)
        axes[1].annotate(event["event"], (event["time_s"], event["fz_N"]), textcoords="offset points",
                         xytext=(4, 6), fontsize=8)
    axes[1].set_ylabel("Fz, N")
    axes[2].plot(time, history["fc_N"], color="0.55", lw=0.6, label="simulation (raw)")
    axes[2].plot(time, fc_envelope(time, history["fc_N"], summary.get("rotation_period_s")), color="C0",
                 lw=1.6, label="simulation, max |Fc| over a rotation period")
    axes[2].set_ylabel("Fc = Mz / R, N")
    if experiment is not None:
        for axis, key in ((axes[1], "fz"), (axes[2], "fc")):
            axis.plot(*experiment[key], "o-", color="C3", ms=4, label="robot experiment (Table 2)")
    for axis in axes[1:]:
        axis.legend(fontsize=7, loc="upper left")
    for axis in axes:
        axis.grid(alpha=0.3)
    axes[2].set_xlim(0.0, max(float(time[-1]), 1e-9))
    axes[2].set_xlabel("time, s")
    axes[0].set_title("Trephination: rotation, linear (Fz) and rotary (Fc) cutting forces", fontsize=10)
    save(figure, path)


def symmetry_plane_faces(cells: np.ndarray, on_plane: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Element faces lying in the symmetry plane: the elements and their four face nodes in cyclic order.

    Parameters
    ----------
    cells : ndarray (n_elements, 8)
        Hexahedra (VTK/Abaqus node order: bottom face 0-3, top face 4-7).
    on_plane : ndarray of bool (n_nodes,)
        Nodes on the plane.
    """
    faces = np.array([[0, 1, 2, 3], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]])
    elements, quads = [], []
    for face in faces:
        nodes = cells[:, face]
        hit = np.flatnonzero(on_plane[nodes].all(axis=1))
        elements.append(hit)
        quads.append(nodes[hit])
    return np.concatenate(elements), np.concatenate(quads)


def stress_sections(setup, snapshots: dict, plots: Path) -> None:
    """``stress-<name>.png`` for each snapshot: von Mises on the deformed y = 0 plane around the cut (x = R)."""
    from corneasim.output import EVENTS, lowest_point, map_title, stress_map, tip_window

    mesh = setup.mesh
    on_plane = np.zeros(mesh.n_nodes, dtype=bool)
    on_plane[mesh.node_sets["symmetry_plane"]] = True
    elements, quads = symmetry_plane_faces(mesh.cells, on_plane)
    apex = float(mesh.points[:, 2].max())
    radius = setup.scenario.instrument.shape.cutting_radius
    for name, (time, fields) in snapshots.items():
        solver_time = setup.solver_time(time)
        current = mesh.points + fields["displacement"]
        keep = fields["alive"][elements] != 0
        tip = lowest_point(instrument_section(setup.instrument, solver_time, (radius - 1.0, radius + 1.0),
                                              (apex - 3.0, apex + 0.5)))
        x_limits, z_limits = tip_window(tip[1] if tip else apex, radius, half_width=0.9, below=0.9, above=0.35)
        displacement = setup.instrument.motion.insertion(solver_time)
        instant = " (Fig. 5)" if name in FIGURE_5_INSTANTS else ""
        stress_map(current[quads[keep]][:, :, [0, 2]], fields["von_mises"][elements[keep]],
                   path=plots / f"stress-{name}.png", x_limits=x_limits, z_limits=z_limits,
                   title=map_title("von Mises stress on the symmetry plane", name, time,
                                   f"displacement {displacement:.3f} mm{instant}",
                                   events={**EVENTS, "cornea": "cornea cut through"}),
                   instrument=instrument_section(setup.instrument, solver_time, x_limits, z_limits))
