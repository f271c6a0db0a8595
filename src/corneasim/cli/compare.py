"""``corneasim compare-meshes``: the trephination paper's Table 1, one run per meshing strategy."""

from __future__ import annotations

import argparse
from pathlib import Path

HELP = "Run the trephine with each meshing strategy and tabulate them (trephination paper Table 1)."

DESCRIPTION = """Run a trephine scenario with the umbrella, vertical and horizontal meshes (same
overrides for all) and write DIR/<strategy>/ results folders, DIR/table1.csv and DIR/table1.md:
elements in total and in the trephine area, wall time, Fz RMSE and maximum error against the
robot experiment up to 65 s, trend (Pearson r) and magnitude (simulated/experimental ratio).
With --realizations every strategy also runs in each round-off realization (start gap moved by
+1e-7, -1e-7, +5e-8 mm, kernels compiled anew, one thread) as one study on a local Dask cluster
(DIR/realizations/), and the table gives each figure's median and range. Units: N, s."""


def register(commands: argparse._SubParsersAction) -> None:
    """Add the ``compare-meshes`` command."""
    parser = commands.add_parser("compare-meshes", help=HELP, description=HELP + "\n\n" + DESCRIPTION,
                                 epilog="example: corneasim compare-meshes trephine --preset coarse",
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scenario", help="trephine, or a trephine scenario .toml file")
    parser.add_argument("--preset", choices=("coarse", "default", "fine"), help="mesh density preset")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                        help="override a key in every run, e.g. --set solver.end_time=10 (repeatable)")
    parser.add_argument("--strategies", default="umbrella,vertical,horizontal", metavar="LIST",
                        help="comma-separated subset of umbrella,vertical,horizontal")
    parser.add_argument("--out", type=Path, default=Path("results/compare-meshes"), help="output folder")
    parser.add_argument("--realizations", action="store_true",
                        help="run each strategy in every realization and give each figure's spread")
    parser.add_argument("--workers", type=int, metavar="N",
                        help="with --realizations: runs at a time (default: one per core)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bars")
    parser.set_defaults(handler=run)


def run(arguments) -> int:
    """Run the comparison and print the Markdown table."""
    from corneasim.scenarios import compare_meshes, spread_markdown, table_markdown

    overrides = ([f"mesh.preset={arguments.preset}"] if arguments.preset else []) + list(arguments.overrides)
    strategies = [s.strip() for s in arguments.strategies.split(",") if s.strip()]
    rows = compare_meshes(arguments.scenario, overrides, arguments.out, strategies,
                          progress=not arguments.no_progress, realizations=arguments.realizations,
                          workers=arguments.workers)
    print(spread_markdown(rows) if arguments.realizations else table_markdown(rows), end="")
    print(f"written: {arguments.out / 'table1.csv'}, {arguments.out / 'table1.md'}")
    return 0
