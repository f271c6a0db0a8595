"""``report.html`` of a results folder: what a run was, how it compares and what it computed.

The page is built from the folder alone (``scenario.toml``, ``summary.json``,
``history.csv``, ``plots/``), so it can be made again for any finished, failed or
interrupted run (``corneasim report DIR``); ``corneasim run`` writes it at the end of every
run. Its sections: the scenario's key inputs and materials; the force plots with the
experiment; the validation table (the summary's scores against the targets of
:mod:`corneasim.output._targets`); the punctures; the energies over time (kinetic and
internal, hourglass, energy balance; drawn here from the history into
``plots/energies.png``); the stress maps (``plots/stress-*.png``, in time order); the run's
platform, size and wall time. The page is an :mod:`corneasim.output._html_report` page.
"""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path

from corneasim.errors import InputError
from corneasim.output._html_report import Image, Mark, Paragraph, Section, Table, write_page
from corneasim.output._targets import score

REPORT = "report.html"

KEY_INPUTS = (
    ("mesh generator", "mesh.generator", ""),
    ("mesh file", "mesh.file", ""),
    ("meshing strategy", "mesh.strategy", ""),
    ("mesh preset", "mesh.preset", ""),
    ("instrument", "instrument.shape.kind", ""),
    ("instrument diameter", "instrument.shape.diameter", "mm"),
    ("insertion rate", "instrument.motion.insertion.rate", "mm/s"),
    ("rotation", "instrument.motion.rotation.type", ""),
    ("rotation amplitude", "instrument.motion.rotation.sine", "rad"),
    ("rotation circular frequency", "instrument.motion.rotation.circular_frequency", "rad/s"),
    ("start gap", "instrument.start_gap", "mm"),
    ("friction", "instrument.contact.friction.law", ""),
    ("friction coefficient", "instrument.contact.friction.coefficient", ""),
    ("intraocular pressure", "pressures.0.pressure", "MPa"),
    ("preload duration", "preload.duration", "s"),
    ("preload damping", "preload.damping", "1/s"),
    ("procedure end time", "solver.end_time", "s"),
    ("mass-scaling target time step", "solver.target_time_step", "s"),
    ("mass scaling", "solver.mass_scaling", ""),
    ("time scaling", "solver.time_scaling", ""),
    ("procedure damping", "solver.damping", "1/s"),
    ("validation dataset", "validation.dataset", ""),
    ("validation column", "validation.y_column", ""),
)
"""(label, dotted key of ``scenario.toml``, unit) of the inputs the page lists when present."""

FORCE_PLOTS = ("force.png", "forces.png")

RATIO_FLOOR = 1e-5
"""Lowest energy ratio the energies figure shows, dimensionless."""

MAP_WIDTH = 520
"""Width of a stress map on the page, CSS pixels (two in a row)."""


def _lookup(tables: dict, key: str):
    value = tables
    for part in key.split("."):
        if isinstance(value, list) and part.isdigit() and int(part) < len(value):
            value = value[int(part)]
        elif isinstance(value, dict) and part in value:
            value = value[part]
        else:
            return None
    return value


def _text(value, unit: str = "") -> str:
    if isinstance(value, list):
        value = ", ".join(f"{v:g}" if isinstance(v, float) else str(v) for v in value)
    elif isinstance(value, float):
        value = f"{value:g}"
    return f"{value} {unit}".strip()


def read_results(results_dir: str | Path) -> tuple[dict, dict, dict]:
    """The scenario tables, summary and history columns of a results folder.

    Raises
    ------
    InputError
        When ``results_dir`` is not a folder holding ``summary.json``. The scenario tables are
        empty without ``scenario.toml`` (a run from Python's ``simulate`` writes none).
    """
    folder = Path(results_dir)
    if not folder.is_dir():
        raise InputError(f"{folder}: no such results folder")
    if not (folder / "summary.json").is_file():
        raise InputError(f"{folder}: not a results folder (no summary.json; run `corneasim run` first)")
    try:
        summary = json.loads((folder / "summary.json").read_text())
        toml = folder / "scenario.toml"
        scenario = tomllib.loads(toml.read_text()) if toml.is_file() else {}
    except (ValueError, tomllib.TOMLDecodeError) as error:
        raise InputError(f"{folder}: unreadable summary.json or scenario.toml ({error})") from None
    history = {}
    if (folder / "history.csv").is_file():
        from corneasim.data import read_table

        history = read_table(folder / "history.csv")
    return scenario, summary, history


def energies_figure(history: dict, path: Path) -> bool:
    """``plots/energies.png``: energies (mJ), their ratios and the balance error against time.

    Returns False (and writes nothing) when the history has no time and energy columns.
    """
    if not {"time_s", "kinetic_energy_mJ", "internal_energy_mJ"} <= set(history):
        return False
    from matplotlib.figure import Figure

    from corneasim.output._plots import save

    time = history["time_s"]
    kinetic, internal = history["kinetic_energy_mJ"], history["internal_energy_mJ"]
    hourglass = history.get("hourglass_energy_mJ")
    figure = Figure(figsize=(6.4, 7.2))
    axes = figure.subplots(3, 1, sharex=True)
    axes[0].plot(time, internal, color="C0", label="internal")
    axes[0].plot(time, kinetic, color="C3", label="kinetic")
    if hourglass is not None:
        axes[0].plot(time, hourglass, color="C2", label="hourglass")
    if "external_work_mJ" in history:
        axes[0].plot(time, history["external_work_mJ"], color="0.4", ls="--", label="external work")
    axes[0].set_ylabel("energy, mJ")
    axes[0].legend(fontsize=7, loc="upper left")
    positive = internal > 0
    ratio_time = time[positive]
    axes[1].plot(ratio_time, kinetic[positive] / internal[positive], color="C3", label="kinetic / internal")
    if hourglass is not None:
        axes[1].plot(ratio_time, hourglass[positive] / internal[positive], color="C2", label="hourglass / internal")
    axes[1].axhline(0.05, color="k", lw=0.8, ls=":", label="5% (quasi-static limit)")
    axes[1].set_yscale("log")
    axes[1].set_ylim(bottom=RATIO_FLOOR)  # before contact the ratios sit at round-off
    axes[1].set_ylabel("ratio to internal energy")
    axes[1].legend(fontsize=7, loc="upper left")
    if "energy_balance_error" in history:
        axes[2].plot(time, history["energy_balance_error"], color="C4")
    axes[2].set_ylabel("energy balance error\n(relative)")
    axes[2].set_xlabel("procedure time, s")
    for axis in axes:
        axis.grid(alpha=0.3)
    axes[0].set_title("Energies over the procedure", fontsize=10)
    save(figure, path)
    return True


def _snapshot_time(name: str, summary: dict) -> float:
    """Sort key of a stress map: its instant ("3.5s"), its puncture's time, or last ("end")."""
    instant = re.fullmatch(r"(\d+(?:\.\d+)?)s", name)
    if instant:
        return float(instant.group(1))
    for event in summary.get("punctures") or []:
        if event.get("event") == name:
            return float(event.get("time_s", 0.0))
    return float("inf")


def _map_caption(name: str) -> str:
    """``plots/stress-<name>.png``'s caption: the event, or the instant."""
    from corneasim.output._stress_maps import EVENTS

    if name in EVENTS:
        return EVENTS[name]
    instant = re.fullmatch(r"(\d+(?:\.\d+)?)s", name)
    return f"t = {instant.group(1)} s" if instant else name


def _inputs_section(scenario: dict, summary: dict) -> Section:
    rows = [("scenario", scenario.get("name", summary.get("scenario"))), ("kind", summary.get("kind"))]
    rows += [(label, _text(value, unit)) for label, key, unit in KEY_INPUTS
             if (value := _lookup(scenario, key)) is not None and value != ""]
    run = summary.get("run") or {}
    if "elements" in run:
        rows.append(("elements / nodes", f"{run['elements']} / {run.get('nodes')}"))
    half = (len(rows) + 1) // 2  # two tables side by side
    blocks = [Paragraph(scenario["description"])] if scenario.get("description") else []
    blocks += [Table(["input", "value"], rows[:half]), Table(["input", "value"], rows[half:])]
    if not scenario:
        blocks.append(Paragraph("The folder holds no scenario.toml: the inputs are not known."))
    materials = scenario.get("materials") or {}
    if materials:
        blocks.append(Table(
            ["block", "material", "failure limit, MPa", "fracture energy, N/mm"],
            [(block, _text(table.get("material")), table.get("failure_limit"), table.get("fracture_energy"))
             for block, table in materials.items()],
            caption="Materials by block (a failure limit of the material itself when not given here)."))
    return Section("Scenario", blocks)


def _validation_section(scenario: dict, summary: dict) -> Section:
    rows = score(summary, _lookup(scenario, "instrument.motion.insertion.rate"))
    if not rows:
        return Section("Validation", [Paragraph("No validation scores in summary.json.")])
    table = [(quantity, value, target or "–",
              None if met is None else Mark("met" if met else "not met", met))
             for quantity, value, target, met in rows]
    return Section("Validation", [Table(["quantity", "value", "target", "result"], table)])


def _punctures_section(summary: dict) -> Section:
    events = summary.get("punctures") or []
    if not events:
        return Section("Punctures", [Paragraph("No layer was punctured in this run.")])
    columns = [c for c in ("time_s", "depth_mm", "displacement_mm", "force_N", "fz_N") if c in events[0]]
    header = ["event"] + [{"time_s": "time, s", "depth_mm": "depth, mm", "displacement_mm": "displacement, mm",
                           "force_N": "force, N", "fz_N": "F_z, N"}[c] for c in columns]
    return Section("Punctures", [Table(header, [[e["event"]] + [e.get(c) for c in columns] for e in events],
                                       caption="When the cut front first crossed each layer.")])


def _run_section(summary: dict) -> Section:
    run = summary.get("run") or {}
    platform = run.get("platform") or {}
    rows = [("status", summary.get("status"))]
    if summary.get("error"):
        rows.append(("error", summary["error"]))
    for label, key, unit in (("wall time", "wall_s", "s"), ("steps", "steps", ""),
                             ("element-steps per second", "element_steps_per_s", "1/s"),
                             ("stable time step", "stable_time_step_s", "s"),
                             ("added mass fraction", "added_mass_fraction", "")):
        if run.get(key) is not None:
            rows.append((label, _text(float(run[key]) if key != "steps" else run[key], unit)))
    for label, key in (("processor", "processor"), ("compiled for", "compiled_for"),
                       ("logical CPUs", "logical_cpus"), ("Numba threads", "numba_threads"),
                       ("threading layer", "threading_layer"), ("Python", "python"), ("NumPy", "numpy"),
                       ("Numba", "numba"), ("corneasim", "corneasim")):
        if platform.get(key) is not None:
            rows.append((label, str(platform[key])))
    blocks = [Table(["run", "value"], rows)]
    blocks += [Paragraph(f"Warning: {warning}") for warning in run.get("warnings") or []]
    return Section("Run", blocks)


def run_sections(results_dir: str | Path) -> tuple[str, str, list[Section]]:
    """The title, subtitle and sections of a results folder's report (writes ``plots/energies.png``)."""
    folder = Path(results_dir)
    scenario, summary, history = read_results(folder)
    plots = folder / "plots"
    sections = [_inputs_section(scenario, summary)]
    forces = [Image.from_file(plots / name, "Simulated force (raw and Gaussian fit) with the experiment; "
                                            "triangles: punctures.")
              for name in FORCE_PLOTS if (plots / name).is_file()]
    sections.append(Section("Forces", forces or [Paragraph("No force plot in plots/.")]))
    sections.append(_validation_section(scenario, summary))
    sections.append(_punctures_section(summary))
    energies = plots / "energies.png"
    if energies_figure(history, energies):
        sections.append(Section("Energies", [Image.from_file(
            energies, "Kinetic, internal and hourglass energy of the model, their ratios to the internal "
                      "energy, and the relative energy balance error, over the procedure.")]))
    maps = sorted(plots.glob("stress-*.png"), key=lambda p: _snapshot_time(p.stem[len("stress-"):], summary))
    sections.append(Section("Stress maps", [Image.from_file(p, _map_caption(p.stem[len("stress-"):]), MAP_WIDTH)
                                            for p in maps] or [Paragraph("No stress maps in plots/.")]))
    sections.append(_run_section(summary))
    title = f"corneasim report: {summary.get('scenario', folder.name)}"
    subtitle = f"{summary.get('kind', 'general')} scenario, run {summary.get('status', 'of unknown status')}"
    return title, subtitle, sections


def write_run_report(results_dir: str | Path) -> Path:
    """Write ``report.html`` into the results folder; returns its path.

    Raises
    ------
    InputError
        When ``results_dir`` is not a results folder (:func:`read_results`).
    """
    title, subtitle, sections = run_sections(results_dir)
    return write_page(Path(results_dir) / REPORT, title, sections, subtitle)
