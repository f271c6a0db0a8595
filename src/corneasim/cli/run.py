"""``corneasim run`` and ``corneasim show``: run a scenario, print a scenario for editing."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from corneasim.errors import InputError
from corneasim.output import atomic_write_text


def register(commands: argparse._SubParsersAction) -> None:
    """Add the ``run`` and ``show`` commands."""
    run = commands.add_parser(
        "run", help="Run a scenario (built-in name or TOML file) and write its results folder.",
        description="Run a scenario and write scenario.toml, history.csv, summary.json, fields/ and plots/.",
        epilog="example: corneasim run needle --preset coarse --out results/needle-coarse\n\n"
               "exit codes: 0 ok, 1 failed simulation (reason in summary.json), 2 bad input, 130 interrupted",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    run.add_argument("scenario", nargs="?", help="Built-in name (needle, trephine) or a scenario .toml file.")
    run.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                     help="Override a key, e.g. --set mesh.preset=coarse (repeatable).")
    run.add_argument("--speed", type=float, metavar="MM_PER_S",
                     help="Needle: insertion speed, mm/s (1 or 5 for the paper's experiments).")
    run.add_argument("--depth", type=float, metavar="MM",
                     help="Needle: insertion depth, mm (default 0.7, the paper's; deeper runs show the whole "
                          "cornea punctured and are still scored on Table 2's 0-0.7 mm).")
    run.add_argument("--mesh", dest="mesh_strategy", choices=["umbrella", "vertical", "horizontal"],
                     help="Trephine: 3D meshing strategy.")
    run.add_argument("--preset", choices=["coarse", "default", "fine", "needle-path"],
                     help="Mesh density preset (needle-path: the needle only), with the settings the scenario's "
                          "[presets.NAME] table gives it.")
    run.add_argument("--out", type=Path, help="Results folder (default results/<name>[-<speed>]).")
    run.add_argument("--resume", type=Path, metavar="DIR", help="Continue the interrupted run in DIR.")
    run.add_argument("--preload-from", type=Path, metavar="DIR",
                     help="Start from the settled preload of an earlier run of the same eye (its results folder "
                          "DIR, which holds preload.npz): same results, without settling again.")
    run.add_argument("--no-progress", action="store_true", help="No progress bar.")
    run.set_defaults(handler=run_command)

    show = commands.add_parser("show", help="Print a scenario's TOML (to copy and edit).",
                           description="Print a scenario's TOML, commented, to copy and edit.",
                           epilog="example: corneasim show needle > my-needle.toml")
    show.add_argument("scenario", help="Built-in name or a .toml file.")
    show.add_argument("--resolved", action="store_true", help="Print with every default filled in.")
    show.set_defaults(handler=show_command)


def shortcut_overrides(arguments, kind: str) -> list[str]:
    """Turn --speed/--mesh/--preset into ``--set`` overrides for the scenario's kind."""
    from corneasim.scenarios import scenario_kind

    return scenario_kind(kind).shortcut_overrides(arguments)


def depth_override(arguments, kind: str, overrides: list[str]) -> list[str]:
    """``solver.end_time`` for the needle's ``--depth`` (mm) at the insertion rate the scenario
    has with ``overrides`` (mm/s); none without ``--depth``."""
    if arguments.depth is None:
        return []
    from corneasim.scenarios import load_scenario, scenario_kind

    return scenario_kind(kind).depth_overrides(arguments.depth,
                                               lambda: load_scenario(arguments.scenario, overrides)[0])


def default_out_dir(scenario) -> Path:
    """``results/<name>``, with the needle's speed appended (``results/needle-1``)."""
    from corneasim.scenarios import scenario_kind

    return scenario_kind(scenario.kind).default_out_dir(scenario)


def run_command(arguments) -> int:
    """Run a scenario, or resume one; print where the results are and the key figures."""
    from corneasim.scenarios import load_scenario, to_toml
    from corneasim.scenarios import simulate
    from corneasim.solver import SimulationError

    if arguments.resume is not None:
        if arguments.scenario or arguments.overrides or arguments.speed or arguments.preset or arguments.depth:
            raise InputError("--resume DIR takes no scenario or overrides: it continues DIR/scenario.toml")
        out_dir = arguments.resume
        scenario, resolved, base_dir = load_scenario(str(out_dir / "scenario.toml"))
        resume = True
    else:
        if not arguments.scenario:
            raise InputError("run: name a scenario (needle, trephine or a .toml file), or give --resume DIR")
        from corneasim.scenarios import read_tables

        kind = read_tables(arguments.scenario)[0].get("kind", "general")
        overrides = shortcut_overrides(arguments, kind)
        overrides += depth_override(arguments, kind, overrides)
        scenario, resolved, base_dir = load_scenario(arguments.scenario, overrides)
        out_dir = arguments.out or default_out_dir(scenario)
        resume = False
        out_dir.mkdir(parents=True, exist_ok=True)
        if scenario.mesh.file is not None and not Path(scenario.mesh.file).is_absolute():
            resolved["mesh"]["file"] = str((base_dir / scenario.mesh.file).resolve())
        from corneasim.scenarios import material_source

        for block, assignment in scenario.materials.items():
            resolved["materials"][block]["material"] = material_source(assignment.material, base_dir.resolve())
        atomic_write_text(out_dir / "scenario.toml", to_toml(resolved))
    try:
        result = simulate(scenario, out_dir=out_dir, base_dir=base_dir, resume=resume,
                          progress=not arguments.no_progress, preload_from=arguments.preload_from)
    except SimulationError as failure:
        print(f"corneasim: run failed: {failure} (history and last checkpoint kept in {out_dir})", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"corneasim: interrupted; results so far and a checkpoint are in {out_dir}; "
              f"continue with: corneasim run --resume {out_dir}", file=sys.stderr)
        return 130
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
        where = f"depth {event['depth_mm']:.3f} mm" if "depth_mm" in event else f"{event['displacement_um']:.0f} um"
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
