"""Plots of a finished run (``plots/`` in the results folder): the scenario kind's and the stress maps.

Matplotlib is imported only when plots are written (a run without a results folder, e.g.
``run_scenario`` from Python, never loads it: 0.6 s of start-up).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


def experiment_curve(setup, scale_x: float = 1.0):
    """The validation dataset's (x, y, label) for a plot (None without validation)."""
    spec = setup.scenario.validation
    if spec is None:
        return None
    from corneasim.data import load_dataset
    from corneasim.output import experiment_label

    data = load_dataset(spec.dataset)
    return data.columns[spec.x_column] * scale_x, data.columns[spec.y_column], experiment_label(spec.y_column)


def gaussian_fit(summary):
    """The Gaussian sum of ``summary["fit"]`` as a callable (None without one); also takes a
    validation block, whose ``fit`` is the fit over the experiment's range."""
    fit = summary.get("fit")
    if not fit:
        return None
    from corneasim.analysis import gaussian_sum

    a, b, c = (np.asarray(fit[key]) for key in "abc")
    return lambda x: gaussian_sum(x, a, b, c)


def write_plots(setup, history: dict, summary: dict, snapshots: dict, out_dir: Path) -> None:
    """The scenario kind's figures (force curves, sections) and, axisymmetric, stress maps at the
    puncture events and the end of the run."""
    plots = out_dir / "plots"
    if history:
        setup.kind.plots(setup, history, summary, snapshots, plots)
    if setup.mesh.axisymmetric and snapshots:
        _stress_maps(setup, snapshots, plots)


def _stress_maps(setup, snapshots: dict, plots: Path) -> None:
    """``stress-<name>.png``: von Mises stress on the deformed section around the instrument's tip."""
    from corneasim.instruments import instrument_section
    from corneasim.output import axisymmetric_section, lowest_point, map_title, stress_map, tip_window

    mesh = setup.mesh
    apex = float(mesh.points[:, 1].max())
    instrument = setup.scenario.instrument
    size = max(0.75, 2.0 * instrument.shape.diameter) if instrument is not None else 0.75  # window, mm
    for name, (time, fields) in snapshots.items():
        solver_time = setup.solver_time(time)
        tip = lowest_point(instrument_section(setup.instrument, solver_time, (-size, size), (apex - 2.0, apex + 0.5)))
        x_limits, z_limits = tip_window(tip[1] if tip else apex, 0.0, half_width=size, below=0.8 * size,
                                        above=0.4 * size)
        depth = setup.instrument.motion.insertion(solver_time) if setup.instrument is not None else None
        polygons, values = axisymmetric_section(mesh.points, mesh.cells, fields["displacement"],
                                                fields["von_mises"], fields["alive"])
        stress_map(polygons, values, path=plots / f"stress-{name}.png", x_limits=x_limits, z_limits=z_limits,
                   title=map_title("von Mises stress", name, time,
                                   None if depth is None else f"depth {depth:.3f} mm"),
                   instrument=instrument_section(setup.instrument, solver_time, x_limits, z_limits),
                   x_label="r, mm (mirrored about the axis)")
