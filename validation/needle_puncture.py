"""Cut depth and corneal deflection on the axis of needle runs, frame by frame.

For each results folder of ``corneasim run needle`` this reads the field frames
(``fields/fields.pvd`` and its ``.vtu`` files: reference points, ``displacement``, cell
``alive``) and ``history.csv``, and prints per frame:

* needle travel (mm) and force (N, history averaged over +-0.01 mm of travel);
* the cut on the axis column (the cornea elements with a corner on r = 0, anterior first):
  contiguous deleted elements from the anterior surface ("cut top") and from the
  posterior surface ("cut bottom"), as counts and reference thickness (mm), and the
  intact share of the column's thickness (0.55 mm);
* "core cut": the deleted share of the cornea's volume within the needle radius;
* "front": depth of the highest live axis node below the apex's position at the first
  frame (deformed, mm; the needle tip while they touch);
* "post.": inward axial displacement of the lowest live axis node (the posterior surface)
  since the first frame, mm, and the secant stiffness force / that deflection, N/mm.

The first frame is the start of the insertion when the run wrote one at travel 0 (else
the table says from which travel the displacements count). While the cut front sits on
the tip, puncture needs travel = thickness + posterior deflection (docs/calibration.md,
"The whole cornea").

Usage::

    python validation/needle_puncture.py RESULTS_DIR [RESULTS_DIR ...] [--runs-csv CSV]

``--runs-csv`` appends one row per folder (parameters read from its ``scenario.toml``,
punctures, RMSE, force, cut and deflection at 0.6 and 0.7 mm, max KE/IE, deletions).
"""

from __future__ import annotations

import argparse
import csv
import json
import tomllib
from pathlib import Path
from xml.etree import ElementTree

import meshio
import numpy as np

CORNEA_BOTTOM_MM = -2.0
"""Axis elements with their centre above this height (mm) belong to the cornea; the
sclera reaches the axis only at the posterior pole, about 26 mm below the apex."""
FORCE_WINDOW_MM = 0.01
"""Half width of the travel window the force is averaged over, mm (as in the calibration)."""


def axis_column(points_mm: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cornea elements with a corner on the axis, anterior first, and their axis nodes.

    Parameters
    ----------
    points_mm : ndarray, shape (n_nodes, 2 or 3)
        Reference coordinates (r, z), mm.
    cells : ndarray, shape (n_elements, 4)
        Quadrilateral connectivity.

    Returns
    -------
    elements : ndarray of int
        Column elements ordered from the anterior surface down.
    edges : ndarray of int, shape (n_column + 1,)
        Axis nodes between them: ``edges[i]`` is the top of ``elements[i]`` on the axis,
        ``edges[-1]`` the posterior surface.
    """
    r_mm, z_mm = points_mm[:, 0], points_mm[:, 1]
    centre_z_mm = z_mm[cells].mean(axis=1)
    on_axis = (np.abs(r_mm[cells]).min(axis=1) <= 1e-9) & (centre_z_mm > CORNEA_BOTTOM_MM)
    elements = np.flatnonzero(on_axis)
    elements = elements[np.argsort(-centre_z_mm[elements])]
    column_nodes = np.unique(cells[elements])
    edges = column_nodes[np.abs(r_mm[column_nodes]) <= 1e-9]
    return elements, edges[np.argsort(-z_mm[edges])]


def core_volumes(points_mm: np.ndarray, cells: np.ndarray, radius_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """Cornea elements whose centre lies within ``radius_mm`` of the axis, and their ring volumes.

    The volume of an axisymmetric element is 2 pi r_c A (r_c its centre radius, A its
    reference area in (r, z) by the shoelace formula), mm^3.
    """
    corners = points_mm[cells][:, :, :2]
    centre = corners.mean(axis=1)
    selected = np.flatnonzero((centre[:, 0] < radius_mm) & (centre[:, 1] > CORNEA_BOTTOM_MM))
    r, z = corners[selected, :, 0], corners[selected, :, 1]
    area_mm2 = 0.5 * np.abs((r * np.roll(z, -1, axis=1) - np.roll(r, -1, axis=1) * z).sum(axis=1))
    return selected, 2.0 * np.pi * centre[selected, 0] * area_mm2


def frames(folder: Path) -> list[tuple[float, Path]]:
    """(procedure time s, file) of every field frame listed in ``fields/fields.pvd``."""
    root = ElementTree.parse(folder / "fields" / "fields.pvd").getroot()
    return [(float(entry.get("timestep")), folder / "fields" / entry.get("file"))
            for entry in root.findall("./Collection/DataSet")]


def frame_table(folder: Path) -> list[dict]:
    """One row per field frame of a needle results folder.

    ``cut_top`` / ``cut_bottom``: contiguous deleted column elements from the anterior /
    posterior surface (count and reference thickness, mm); ``intact_fraction``: share of
    the column's reference thickness still alive; ``front_mm``: depth of the highest live
    axis node below the apex's position at the first frame (deformed; the apex itself
    until it is deleted, so the needle tip while they touch); ``posterior_deflection_mm``:
    inward displacement, since the first frame, of the lowest live axis node.
    """
    history = np.genfromtxt(folder / "history.csv", delimiter=",", names=True)
    needle_radius_mm = 0.5 * tomllib.loads((folder / "scenario.toml").read_text())["instrument"]["shape"]["diameter"]
    rows = []
    start_uz_mm = None
    for time_s, path in frames(folder):
        mesh = meshio.read(path)
        z_mm = mesh.points[:, 1]
        elements, edges = axis_column(mesh.points, mesh.cells_dict["quad"])
        uz_mm = mesh.point_data["displacement"][:, 1]
        if start_uz_mm is None:
            start_uz_mm = uz_mm.copy()
        apex_start_mm = z_mm[edges[0]] + start_uz_mm[edges[0]]
        alive_all = np.asarray(mesh.cell_data_dict["alive"]["quad"]) > 0
        core, core_volume_mm3 = core_volumes(mesh.points, mesh.cells_dict["quad"], needle_radius_mm)
        alive = alive_all[elements]
        thickness_mm = z_mm[edges[0]] - z_mm[edges[-1]]
        live = np.flatnonzero(alive)
        top = int(live[0]) if live.size else len(elements)
        bottom = int(len(elements) - 1 - live[-1]) if live.size else 0
        cut_top_mm = z_mm[edges[0]] - z_mm[edges[top]]
        cut_bottom_mm = z_mm[edges[len(elements) - bottom]] - z_mm[edges[-1]]
        thicknesses_mm = z_mm[edges[:-1]] - z_mm[edges[1:]]
        front, back = edges[top], edges[len(elements) - bottom]
        travel_mm = float(np.interp(time_s, history["time_s"], history["depth_mm"]))
        near = np.abs(history["depth_mm"] - travel_mm) <= FORCE_WINDOW_MM
        force_N = float(history["force_N"][near].mean()) if near.any() else float("nan")
        posterior_mm = float(start_uz_mm[back] - uz_mm[back]) if live.size else float("nan")
        front_mm = float(apex_start_mm - (z_mm[front] + uz_mm[front])) if live.size else float("nan")
        rows.append({
            "travel_mm": travel_mm, "force_N": force_N,
            "cut_top_elements": top, "cut_top_mm": float(cut_top_mm),
            "cut_bottom_elements": bottom, "cut_bottom_mm": float(cut_bottom_mm),
            "intact_fraction": float(thicknesses_mm[alive].sum() / thickness_mm),
            "core_cut_fraction": float(core_volume_mm3[~alive_all[core]].sum() / core_volume_mm3.sum()),
            "front_mm": front_mm,
            "posterior_deflection_mm": posterior_mm,
            "secant_N_per_mm": force_N / posterior_mm if posterior_mm > 1e-3 else float("nan"),
        })
    return rows


def print_table(folder: Path, rows: list[dict]) -> None:
    """Print the frame table of one folder."""
    print(f"\n{folder}")
    if rows[0]["travel_mm"] > 1e-3:
        print(f"(no frame at the start: front and deflections are relative to travel {rows[0]['travel_mm']:.3f} mm)")
    print(f"{'travel mm':>9} {'force N':>8} {'cut top':>12} {'cut bottom':>12} {'intact':>6} {'core cut':>8} "
          f"{'front mm':>8} {'post. mm':>8} {'F/post N/mm':>11}")
    for row in rows:
        print(f"{row['travel_mm']:9.3f} {row['force_N']:8.3f} "
              f"{row['cut_top_elements']:3d} {row['cut_top_mm']:8.3f} "
              f"{row['cut_bottom_elements']:3d} {row['cut_bottom_mm']:8.3f} {row['intact_fraction']:6.2f} "
              f"{row['core_cut_fraction']:8.2f} {row['front_mm']:8.3f} {row['posterior_deflection_mm']:8.3f} {row['secant_N_per_mm']:11.3f}")


def _at_travel(rows: list[dict], key: str, travel_mm: float) -> float:
    """Value of ``key`` in the frame nearest to ``travel_mm`` (within 0.02 mm), else NaN."""
    nearest = min(rows, key=lambda row: abs(row["travel_mm"] - travel_mm))
    return nearest[key] if abs(nearest["travel_mm"] - travel_mm) <= 0.02 else float("nan")


def run_row(folder: Path, rows: list[dict]) -> dict:
    """Parameters, punctures and scores of one run, for the runs CSV."""
    scenario = tomllib.loads((folder / "scenario.toml").read_text())
    summary = json.loads((folder / "summary.json").read_text())
    history = np.genfromtxt(folder / "history.csv", delimiter=",", names=True)
    materials, shape = scenario["materials"], scenario["instrument"]["shape"]
    friction = scenario["instrument"]["contact"]["friction"]
    punctures = {event["event"]: event["depth_mm"] for event in summary["punctures"]}
    return {
        "run": folder.name, "status": summary["status"], "mesh": scenario["mesh"].get("preset", "file"),
        "rate_mm_per_s": scenario["instrument"]["motion"]["insertion"].get("rate"),
        "target_time_step_s": scenario["solver"].get("target_time_step"),
        "epithelium_failure_MPa": materials["epithelium"].get("failure_limit", "preset"),
        "stroma_material": Path(materials["stroma"]["material"]).stem,
        "stroma_failure_MPa": materials["stroma"].get("failure_limit", "preset"),
        "stroma_fracture_energy_N_per_mm": materials["stroma"].get("fracture_energy"),
        "tip": shape["tip"] + (f" {shape['tip_angle']:g}" if shape["tip"] == "conical" else ""),
        "friction": f"{friction['law']} mu_limit {friction.get('coefficient_limit')}"
                    if friction["law"] == "karnopp" else f"{friction['law']} {friction.get('coefficient', '')}",
        "epithelium_mm": punctures.get("epithelium", ""), "stroma_mm": punctures.get("stroma", ""),
        "cornea_mm": punctures.get("cornea", ""),
        "rmse_N": summary.get("validation", {}).get("rmse_N"),
        "rmse_raw_N": summary.get("validation", {}).get("rmse_raw_N"),
        "force_0.6_N": _at_travel(rows, "force_N", 0.6), "force_0.7_N": _at_travel(rows, "force_N", 0.7),
        "peak_N": summary.get("peak_force_N"),
        "cut_top_0.6_mm": _at_travel(rows, "cut_top_mm", 0.6),
        "cut_top_0.7_mm": _at_travel(rows, "cut_top_mm", 0.7),
        "cut_bottom_0.7_mm": _at_travel(rows, "cut_bottom_mm", 0.7),
        "intact_0.7": _at_travel(rows, "intact_fraction", 0.7),
        "core_cut_0.7": _at_travel(rows, "core_cut_fraction", 0.7),
        "posterior_0.6_mm": _at_travel(rows, "posterior_deflection_mm", 0.6),
        "posterior_0.7_mm": _at_travel(rows, "posterior_deflection_mm", 0.7),
        "deflection_reference_travel_mm": rows[0]["travel_mm"],
        "max_ke_ie": summary["run"].get("max_kinetic_to_internal"),
        "deleted": int(history["deleted_elements"][-1]), "wall_s": summary["run"].get("wall_s"),
    }


def main(argv: list[str] | None = None) -> int:
    """Command line: print the frame tables, optionally append the runs CSV."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folders", nargs="+", type=Path, help="results folders of needle runs")
    parser.add_argument("--runs-csv", type=Path, help="append one row per folder to this CSV")
    args = parser.parse_args(argv)
    records = []
    for folder in args.folders:
        rows = frame_table(folder)
        print_table(folder, rows)
        if args.runs_csv:
            records.append(run_row(folder, rows))
    if records:
        new = not args.runs_csv.exists()
        args.runs_csv.parent.mkdir(parents=True, exist_ok=True)
        with args.runs_csv.open("a", newline="") as stream:
            writer = csv.DictWriter(stream, fieldnames=list(records[0]))
            if new:
                writer.writeheader()
            writer.writerows(records)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
