"""``corneasim run`` and ``corneasim show``: run a scenario, print a scenario for editing."""

from __future__ import annotations

import argparse
import math
import re
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path

from corneasim.errors import InputError

RESULTS_ROOT = Path("results")
"""Where the default results folders go (relative to the working folder)."""


def register(commands: argparse._SubParsersAction) -> None:
    """Add the ``run`` and ``show`` commands."""
    run = commands.add_parser(
        "run", help="Run a scenario (built-in name or TOML file) and write its results folder.",
        description="Run a scenario and write scenario.toml, history.csv, summary.json, fields/, plots/ and "
        "report.html.",
        epilog="example: corneasim run needle --preset coarse --out results/needle-coarse\n\n"
               "exit codes: 0 ok, 1 failed simulation (reason in summary.json), 2 bad input, 130 interrupted",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    run.add_argument("scenario", nargs="?", help="Built-in name (needle, trephine) or a scenario .toml file.")
    run.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                     help="Override a key, e.g. --set mesh.preset=coarse (repeatable).")
    run.add_argument("--unset", action="append", default=[], metavar="KEY",
                     help="Remove a key, so that it takes its default (an optional key: off), e.g. --unset "
                          "instrument.contact.cutting_toughness (repeatable; after --set and the presets).")
    run.add_argument("--speed", type=float, metavar="MM_PER_S",
                     help="Needle: insertion speed, mm/s (1 or 5 for the paper's experiments).")
    run.add_argument("--depth", type=float, metavar="MM",
                     help="Needle: insertion depth, mm (default 0.7, the paper's; deeper runs show the whole "
                          "cornea punctured and are still scored on Table 2's 0-0.7 mm).")
    run.add_argument("--mesh", dest="mesh_strategy", choices=["umbrella", "vertical", "horizontal"],
                     help="Trephine: 3D meshing strategy.")
    run.add_argument("--preset", action="append", metavar="NAME",
                     help="Mesh density preset (coarse, default, fine; needle-path[-2x|-4x]: the needle only) with the "
                          "settings the scenario's [presets.NAME] table gives it, or a model variant of the "
                          "scenario (paper: the paper's own model); repeatable: --preset paper --preset coarse.")
    run.add_argument("--out", type=Path, help="Results folder (default results/<name>[-<speed>]); a folder "
                     "holding an earlier run's results is refused unless --overwrite is given.")
    run.add_argument("--overwrite", action="store_true",
                     help="Delete the files an earlier run wrote in the results folder before running "
                          "(other files are left alone).")
    run.add_argument("--resume", type=Path, metavar="DIR", help="Continue the interrupted run in DIR.")
    run.add_argument("--preload-from", type=Path, metavar="DIR",
                     help="Start from the settled preload of an earlier run of the same eye (its results folder "
                          "DIR, which holds preload.npz): same results, without settling again.")
    run.add_argument("--no-progress", action="store_true", help="No progress bar.")
    run.add_argument("--no-plots", action="store_true",
                     help="Write the data files only: no plots/ and no report.html (1-2 s less per run).")
    run.set_defaults(handler=run_command)

    show = commands.add_parser("show", help="Print a scenario's TOML (to copy and edit).",
                           description="Print a scenario's TOML, commented, to copy and edit.",
                           epilog="example: corneasim show needle > my-needle.toml")
    show.add_argument("scenario", help="Built-in name or a .toml file.")
    show.add_argument("--resolved", action="store_true", help="Print with every default filled in.")
    show.set_defaults(handler=show_command)


def shortcut_overrides(arguments, kind: str) -> list[str]:
    """Turn --speed/--mesh/--preset into ``--set`` overrides for the scenario's kind."""
    if arguments.speed is not None and not math.isfinite(arguments.speed):
        raise InputError(f"--speed: expected a finite speed > 0 mm/s, got {arguments.speed}")
    from corneasim.scenarios import scenario_kind

    return scenario_kind(kind).shortcut_overrides(arguments)


def depth_override(arguments, kind: str, overrides: list[str]) -> list[str]:
    """``solver.end_time`` for the needle's ``--depth`` (mm) at the insertion rate the scenario
    has with ``overrides`` (mm/s); none without ``--depth``."""
    if arguments.depth is None:
        return []
    if not math.isfinite(arguments.depth):
        raise InputError(f"--depth: expected a finite depth > 0 mm, got {arguments.depth}")
    from corneasim.scenarios import load_scenario, scenario_kind

    return scenario_kind(kind).depth_overrides(arguments.depth,
                                               lambda: load_scenario(arguments.scenario, overrides)[0])


def folder_name(text: str) -> str:
    """``text`` as one safe folder name: runs of characters other than letters, digits and ``._+-``
    become ``-``, leading and trailing dots and dashes go (no ``..``, no hidden folder), at most
    100 characters; ``run`` when nothing is left.

    >>> folder_name("../../../elsewhere/x/ESCAPED")
    'elsewhere-x-ESCAPED'
    """
    cleaned = re.sub(r"[^\w.+-]+", "-", text)[:100].strip(".-")
    return cleaned or "run"


def default_out_dir(scenario) -> Path:
    """The kind's folder (``results/<name>``, the needle's ``results/needle-1``) with its name made
    safe (:func:`folder_name`): a scenario's name never places its results outside ``results/``."""
    from corneasim.scenarios import scenario_kind

    folder = scenario_kind(scenario.kind).default_out_dir(scenario)
    name = str(folder.relative_to(RESULTS_ROOT)) if folder.parts[:1] == RESULTS_ROOT.parts else str(folder)
    return RESULTS_ROOT / folder_name(name)


@dataclass
class RunPlan:
    """A run checked and ready to start (:func:`prepare_run`): nothing has been written yet.

    Attributes
    ----------
    scenario : Scenario
    base_dir : Path
        Folder the scenario's relative paths refer to.
    out_dir : Path
        The results folder.
    resume : bool
    record : str or None
        The text of ``scenario.toml`` for a new run (None when resuming).
    """

    scenario: object
    base_dir: Path
    out_dir: Path
    resume: bool
    record: str | None


def prepare_run(arguments) -> RunPlan:
    """Read, override and validate the scenario and the options of ``run``, touching no file.

    Raises
    ------
    InputError
        The first problem, as one line (the results folder is not created).
    """
    from corneasim.scenarios import load_scenario, read_tables, to_toml
    from corneasim.scenarios._meaning import check_scenario

    if arguments.resume is not None:
        if arguments.scenario or arguments.overrides or arguments.unset or arguments.speed or arguments.preset or arguments.depth \
                or arguments.overwrite or arguments.out:
            raise InputError("--resume DIR takes no scenario, overrides, --out or --overwrite: it continues "
                             "DIR/scenario.toml in DIR")
        out_dir = arguments.resume
        if not (out_dir / "scenario.toml").is_file():
            raise InputError(f"--resume {out_dir}: no scenario.toml there (not the results folder of a run)")
        if _finished(out_dir):
            raise InputError(f"--resume {out_dir}: that run completed; nothing to resume (run again with "
                             "--out and --overwrite to redo it)")
        scenario, _, base_dir = load_scenario(str(out_dir / "scenario.toml"), resolved=True)
        check_scenario(scenario)
        return RunPlan(scenario, base_dir, out_dir, True, None)
    if not arguments.scenario:
        raise InputError("run: name a scenario (needle, trephine or a .toml file), or give --resume DIR")
    tables, _, source = read_tables(arguments.scenario)
    kind = tables.get("kind", "general")
    if not isinstance(kind, str):
        raise InputError(f"{source}: kind: expected a string (the scenario kind), got {kind!r}")
    overrides = shortcut_overrides(arguments, kind)
    overrides += depth_override(arguments, kind, overrides)
    scenario, resolved, base_dir = load_scenario(arguments.scenario, overrides, arguments.unset)
    check_scenario(scenario)
    out_dir = arguments.out or default_out_dir(scenario)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError(f"--out {out_dir}: is a file, not a results folder")
    if scenario.mesh.file is not None and not Path(scenario.mesh.file).is_absolute():
        resolved["mesh"]["file"] = str((base_dir / scenario.mesh.file).resolve())
    from corneasim.scenarios import material_source

    for block, assignment in scenario.materials.items():
        resolved["materials"][block]["material"] = material_source(assignment.material, base_dir.resolve())
    return RunPlan(scenario, base_dir, out_dir, False, to_toml(resolved))


def _finished(folder: Path) -> bool:
    """Whether the run in ``folder`` says it completed (``summary.json``)."""
    import json

    try:
        return json.loads((folder / "summary.json").read_text()).get("status") == "completed"
    except (OSError, ValueError, AttributeError):
        return False


def run_command(arguments) -> int:
    """Run a scenario, or resume one; print where the results are and the key figures.

    Exit codes (docs/results-format.md): 0 completed, 1 the simulation failed (its reason in
    summary.json and on stderr), 2 bad input (nothing run), 130 interrupted (resumable)."""
    from corneasim.scenarios import simulate
    from corneasim.scenarios._run_record import failure_reason
    from corneasim.solver import SimulationError

    plan = prepare_run(arguments)
    out_dir = plan.out_dir
    try:
        with warnings.catch_warnings():  # NumPy's floating-point warnings of a run blowing up: its failure says it
            warnings.simplefilter("ignore", RuntimeWarning)
            result = simulate(plan.scenario, out_dir=out_dir, base_dir=plan.base_dir, resume=plan.resume,
                              progress=not arguments.no_progress, preload_from=arguments.preload_from,
                              overwrite=arguments.overwrite, record=plan.record, plots=not arguments.no_plots)
    except InputError:
        raise
    except SimulationError as failure:
        print(f"corneasim: run failed: {failure} (history and last checkpoint kept in {out_dir})", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"corneasim: interrupted; results so far and a checkpoint are in {out_dir}; "
              f"continue with: corneasim run --resume {out_dir}", file=sys.stderr)
        return 130
    except Exception as failure:  # a crash of the simulation: one line, the summary says failed
        print(f"corneasim: run failed: {failure_reason(failure)} (history and summary.json in {out_dir})",
              file=sys.stderr)
        return 1
    print_summary(result.summary, out_dir)
    return 0


def print_summary(summary: dict, out_dir: Path) -> None:
    """A few lines: where the results are and the figures a user looks at first."""
    run = summary.get("run", {})
    print(f"results: {out_dir}")
    for key in ("peak_force_N", "peak_fz_N", "peak_fc_N"):
        if key in summary:
            print(f"  {key}: {summary[key]:.4g}")
    for event in summary.get("punctures", []):
        where = f"depth {event['depth_mm']:.3f} mm" if "depth_mm" in event else f"displacement {event['displacement_mm']:.3f} mm"
        print(f"  puncture {event['event']}: t = {event['time_s']:.3f} s, {where}")
    validation = summary.get("validation") or {}
    # The needle validates one column; the trephine Fz and Fc (entries "fz", "fc").
    for entry in [validation] if "column" in validation else [validation[k] for k in ("fz", "fc") if k in validation]:
        print(f"  validation vs {entry['column']}: RMSE {entry['rmse_N']:.4f} N, "
              f"max error {entry['max_abs_error_N']:.4f} N")
    if run:
        print(f"  {run.get('elements')} elements, {run.get('steps')} steps, {run.get('wall_s', 0):.1f} s wall, "
              f"{(run.get('element_steps_per_s') or 0):.3g} element-steps/s")
    for warning in run.get("warnings", []):
        print(f"  warning: {warning}")


def show_command(arguments) -> int:
    """Print the scenario's TOML text (or the resolved tables)."""
    from corneasim.scenarios import load_scenario, scenario_text, to_toml

    if arguments.resolved:
        _, resolved, _ = load_scenario(arguments.scenario)
        print(to_toml(resolved), end="")
    else:
        print(scenario_text(arguments.scenario), end="")
    return 0
