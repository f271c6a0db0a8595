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

    data = load_dataset(spec.dataset)
    return data.columns[spec.x_column] * scale_x, data.columns[spec.y_column], f"experiment ({spec.y_column})"


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
    from corneasim.output import section_map
    from corneasim.instruments import instrument_section

    mesh = setup.mesh
    apex = mesh.points[:, 1].max()
    window = (1.2, apex - 1.6, apex + 0.3)
    vmax = max(float(np.max(fields["von_mises"] * (fields["alive"] != 0))) for _, fields in snapshots.values())
    for name, (time, fields) in snapshots.items():
        section_map(mesh.points, mesh.cells, fields["displacement"], fields["von_mises"], fields["alive"],
                    title=f"von Mises stress, {name} (t = {time:.3f} s)", path=plots / f"stress-{name}.png",
                    window=window, vmax=vmax,
                    instrument=instrument_section(setup.instrument, setup.solver_time(time),
                                                  (-window[0], window[0]), window[1:]))
