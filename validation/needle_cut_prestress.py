"""The cut needle insertion with and without the prestressed reference (``preload.stress_free_reference``).

Runs ``validation/needle_cut.toml`` (the radial-crack cut, HGO stroma, docs/cutting.md) twice on
one mesh: with the mesh taken as stress-free (the scenario as it is) and built on the
stress-free reference whose preload gives the mesh back (docs/solver.md, "Prestressed
reference"). For each it prints the apex's rise under the IOP at the end of the preload (the
preloaded apex above the mesh's, mm), the RMSE against the 1 mm/s experiment, the peak force,
the force at 0.35 and 0.7 mm, the puncture depths, the largest kinetic / internal energy and
the wall time; with the reference also its iterations and their nodal errors. Writes
``prestress.json``.

Usage::

    python validation/needle_cut_prestress.py [--out results/needle-cut-prestress]
        [--preset needle-path-4x] [--set KEY=VALUE ...]
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from corneasim.mesh import mesh_axisymmetric
from corneasim.output import write_json
from corneasim.scenarios._registry import load_scenario

from needle_cut_calibration import SCENARIO, run_point

CASES = {"stress-free mesh": [], "prestressed reference": ["preload.stress_free_reference=true"]}


def apex_rise(folder: Path, measured: np.ndarray) -> float:
    """Height (mm) of the preloaded apex above the mesh's (the highest node on the axis)."""
    reference = measured
    if (folder / "reference.npz").is_file():
        with np.load(folder / "reference.npz") as saved:
            reference = saved["points"]
    with np.load(folder / "preload.npz") as settled:
        displacement = settled["u"]
    on_axis = np.flatnonzero(measured[:, 0] <= 1e-9)
    top = on_axis[np.argmax(measured[on_axis, 1])]
    return float(reference[top, 1] + displacement[top, 1] - measured[top, 1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/needle-cut-prestress"))
    parser.add_argument("--preset", default="needle-path-4x", help="mesh preset of needle_cut.toml")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                        help="more overrides for both runs")
    arguments = parser.parse_args()
    common = [f"mesh.preset={arguments.preset}", *arguments.overrides]
    scenario, _, _ = load_scenario(str(SCENARIO), common)
    measured = mesh_axisymmetric(scenario.mesh.geometry, arguments.preset).points
    rows = {}
    for name, extra in CASES.items():
        folder = arguments.out / name.replace(" ", "-")
        row = run_point(folder, [*common, *extra])
        row["apex_rise_mm"] = apex_rise(folder, measured) if (folder / "preload.npz").is_file() else math.nan
        summary = json.loads((folder / "summary.json").read_text())
        row["out_of_balance"] = summary["run"]["preload"]["out_of_balance"]
        if "stress_free_reference" in summary:
            row["reference"] = summary["stress_free_reference"]
        rows[name] = row
        print(f"{name}: " + ", ".join(f"{key} {value:.4g}" if isinstance(value, float) else f"{key} {value}"
                                      for key, value in row.items() if key != "reference"))
        if "reference" in row:
            print(f"  reference: {row['reference']['iterations']} solves, nodal errors (mm) "
                  + " ".join(f"{error:.2g}" for error in row["reference"]["errors_mm"]))
    write_json(arguments.out / "prestress.json", {"preset": arguments.preset, "overrides": common, "runs": rows})


if __name__ == "__main__":
    main()
