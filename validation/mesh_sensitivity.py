"""Mesh sensitivity of the needle scenario: coarse, default and fine presets.

Element deletion makes the force curve depend on the element size at the needle path (a
failed element removes a whole element of tissue, and the stress at the tip of a
needle is higher on a finer mesh). This script runs the built-in ``needle`` scenario with
the same parameters on each preset and reports, per mesh: the element count and the element
size at the apex, the peak force, the RMSE against the 1 mm/s experiment (Gaussian fit and
raw curve), the puncture events (depth and force), the deleted elements, the largest
kinetic/internal energy ratio and the wall time. It draws the three force-depth curves over
the experiment (``force_depth.png``).

Resumable: a preset whose results folder already holds a ``summary.json`` is not run again
(delete the folder to rerun it). A run that stops with a solver error is reported as failed.

Usage::

    NUMBA_NUM_THREADS=1 python validation/mesh_sensitivity.py [--out results/mesh-sensitivity]
        [--presets coarse default fine] [--set KEY=VALUE ...]

Writes ``<out>/<preset>/`` (results folders), ``<out>/mesh_sensitivity.json`` and
``<out>/mesh_sensitivity.md`` (the table) and prints the table.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

import corneasim
from corneasim.data import load_dataset, read_table
from corneasim.mesh import mesh_axisymmetric
from corneasim.mesh import EyeGeometry
from corneasim.output import atomic_write_text, write_json
from corneasim.solver import SimulationError

PRESETS = ("coarse", "default", "fine")


def apex_element_size(preset: str) -> tuple[int, float, float]:
    """Element count and the radial and axial size (mm) of the apex element of a preset's eye mesh."""
    mesh = mesh_axisymmetric(EyeGeometry(), preset)
    apex = int(np.argmax(mesh.points[:, 1] - 10.0 * mesh.points[:, 0]))
    element = int(np.flatnonzero((mesh.cells == apex).any(axis=1))[0])
    corners = mesh.points[mesh.cells[element]]
    return mesh.n_elements, float(np.ptp(corners[:, 0])), float(np.ptp(corners[:, 1]))


def run_preset(preset: str, out: Path, overrides: list[str]) -> dict:
    """Run (or read back) one preset; return its row of the table."""
    folder = out / preset
    if not (folder / "summary.json").exists():
        try:
            corneasim.run_scenario("needle", [f"mesh.preset={preset}", *overrides], out_dir=folder,
                                   progress=True)
        except SimulationError:
            pass  # the runner wrote summary.json with status "failed" and the history so far
    summary = json.loads((folder / "summary.json").read_text())
    elements, size_r, size_z = apex_element_size(preset)
    validation = summary.get("validation") or {}
    history = read_table(folder / "history.csv") if (folder / "history.csv").exists() else {}
    punctures = [{key: event[key] for key in ("event", "depth_mm", "force_N")}
                 for event in summary.get("punctures", [])]
    return {
        "preset": preset,
        "status": summary["status"],
        "elements": elements,
        "apex_element_mm": [size_r, size_z],
        "peak_force_N": summary.get("peak_force_N"),
        "rmse_N": validation.get("rmse_N"),
        "rmse_raw_N": validation.get("rmse_raw_N"),
        "punctures": punctures,
        "deleted_elements": int(history["deleted_elements"][-1]) if "deleted_elements" in history else 0,
        "max_kinetic_to_internal": summary["run"].get("max_kinetic_to_internal"),
        "wall_s": summary["run"]["wall_s"],
        "error": summary.get("error"),
    }


def _number(value, digits=3) -> str:
    return "-" if value is None else f"{value:.{digits}f}"


def table(rows: list[dict]) -> str:
    """The sensitivity table as Markdown."""
    lines = ["| mesh | elements | apex element (r x z, um) | status | peak force N | RMSE fit N | RMSE raw N "
             "| punctures (depth mm @ force N) | deleted | max KE/IE | wall s |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        punctures = ", ".join(f"{p['event']} {p['depth_mm']:.3f} @ {_number(p['force_N'])}"
                              for p in row["punctures"]) or "none"
        size = " x ".join(f"{1000 * s:.1f}" for s in row["apex_element_mm"])
        lines.append(f"| {row['preset']} | {row['elements']} | {size} | {row['status']} "
                     f"| {_number(row['peak_force_N'])} | {_number(row['rmse_N'], 4)} "
                     f"| {_number(row['rmse_raw_N'], 4)} | {punctures} | {row['deleted_elements']} "
                     f"| {_number(row['max_kinetic_to_internal'])} | {row['wall_s']:.0f} |")
    return "\n".join(lines)


def plot(rows: list[dict], out: Path) -> Path:
    """Force-depth curves of every preset over the 1 mm/s experiment."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    experiment = load_dataset("needle-insertion-force")
    figure, axes = plt.subplots(figsize=(6.5, 4.2))
    for row in rows:
        history = read_table(out / row["preset"] / "history.csv")
        axes.plot(history["depth_mm"], history["force_N"], lw=0.8,
                  label=f"{row['preset']} ({row['elements']} elements)")
    axes.plot(experiment["depth_mm"], experiment["experiment_1mm_s_N"], "ko", ms=4, label="experiment 1 mm/s")
    axes.set_xlabel("needle depth (mm)")
    axes.set_ylabel("force on the needle (N)")
    axes.legend(frameon=False)
    figure.tight_layout()
    path = out / "force_depth.png"
    figure.savefig(path, dpi=130)
    plt.close(figure)
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/mesh-sensitivity"))
    parser.add_argument("--presets", nargs="+", default=list(PRESETS), choices=PRESETS)
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    arguments = parser.parse_args()
    arguments.out.mkdir(parents=True, exist_ok=True)
    rows = [run_preset(preset, arguments.out, arguments.overrides) for preset in arguments.presets]
    write_json(arguments.out / "mesh_sensitivity.json", {"overrides": arguments.overrides, "rows": rows})
    text = table(rows)
    atomic_write_text(arguments.out / "mesh_sensitivity.md", text + "\n")
    plot(rows, arguments.out)
    print(text)


if __name__ == "__main__":
    main()
