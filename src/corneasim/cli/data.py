"""``corneasim data``: the papers' datasets and the curve tools.

Sub-commands: ``list``, ``show NAME|FILE [--csv]``, ``fit NAME|FILE --x COL --y COL
--terms N``, ``compare SIM --x COL --y COL --against NAME|FILE --exp-x COL --exp-y COL``
and ``drops NAME|FILE --x COL --force COL``. ``NAME`` is a shipped dataset
(``corneasim data list``); an argument ending in ``.csv`` or containing a path
separator is read as a CSV file of the same format.
"""

from __future__ import annotations

import argparse
import os

from corneasim.analysis import (
    DEFAULT_MIN_DROP,
    DEFAULT_NOISE_FACTOR,
    compare_to_experiment,
    detect_force_drops,
    fit_gaussian_sum,
)
from corneasim.data import Dataset, column_unit, list_datasets, load_dataset, load_dataset_file

HELP = "Experimental datasets from the papers, and curve tools."


def register(commands: argparse._SubParsersAction) -> None:
    """Add the ``data`` command group and its sub-commands."""
    group = commands.add_parser("data", help=HELP, description=HELP)
    sub = group.add_subparsers(dest="data_command", metavar="COMMAND", required=True)

    listing = sub.add_parser("list", help="List the shipped datasets.", description="List the shipped datasets.",
                             epilog="example: corneasim data list")
    listing.set_defaults(handler=run_list)

    show = sub.add_parser("show", help="Print a dataset with units and source.",
                          description="Print a dataset (or a CSV file) with its units, source and notes.",
                          epilog="example: corneasim data show needle-insertion-force")
    show.add_argument("source", metavar="NAME|FILE", help="dataset name or CSV file")
    show.add_argument("--csv", action="store_true", help="print the raw CSV text (comments included)")
    show.set_defaults(handler=run_show)

    fit = sub.add_parser("fit", help="Fit an N-term Gaussian sum to two columns.",
                         description="Least-squares fit of f(x) = sum a_i exp(-((x-b_i)/c_i)^2) to two columns.",
                         epilog="example: corneasim data fit needle-insertion-force --x depth_mm "
                                "--y experiment_1mm_s_N --terms 3",
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    fit.add_argument("source", metavar="NAME|FILE")
    fit.add_argument("--x", required=True, metavar="COL", help="abscissa column")
    fit.add_argument("--y", required=True, metavar="COL", help="ordinate column")
    fit.add_argument("--terms", type=int, default=3, metavar="N", help="number of Gaussian terms (default 3)")
    fit.add_argument("--nonnegative", action="store_true", help="constrain the amplitudes a_i >= 0")
    fit.set_defaults(handler=run_fit)

    compare = sub.add_parser("compare", help="RMSE and max error of a simulated curve against a table.",
                             description="RMSE and max error of a simulated curve against an experimental table.\n\n"
                             "The curve is interpolated at the table's abscissae; table points outside "
                             "the simulated range are excluded and counted.",
                             epilog="example: corneasim data compare results/needle-1/history.csv --x depth_mm "
                                    "--y force_N --against needle-insertion-force --exp-x depth_mm "
                                    "--exp-y experiment_1mm_s_N",
                             formatter_class=argparse.RawDescriptionHelpFormatter)
    compare.add_argument("simulation", metavar="SIM", help="dataset name or CSV file of the simulated curve")
    compare.add_argument("--x", required=True, metavar="COL", help="abscissa column of SIM")
    compare.add_argument("--y", required=True, metavar="COL", help="value column of SIM")
    compare.add_argument("--against", required=True, metavar="NAME|FILE", help="experimental table")
    compare.add_argument("--exp-x", required=True, metavar="COL", help="abscissa column of the table")
    compare.add_argument("--exp-y", required=True, metavar="COL", help="value column of the table")
    compare.set_defaults(handler=run_compare)

    drops = sub.add_parser("drops", help="Detect force drops (punctures) in a force signal.",
                           description="Sudden drops larger than max(K x robust noise of the first "
                           "differences, MIN_DROP N).",
                           epilog="example: corneasim data drops results/needle-1/history.csv --x depth_mm "
                                  "--force force_N",
                           formatter_class=argparse.RawDescriptionHelpFormatter)
    drops.add_argument("source", metavar="NAME|FILE")
    drops.add_argument("--x", required=True, metavar="COL", help="abscissa column (depth in mm or time in s)")
    drops.add_argument("--force", required=True, metavar="COL", help="force column, N")
    drops.add_argument("--noise-factor", type=float, default=DEFAULT_NOISE_FACTOR, metavar="K",
                       help=f"multiple of the noise level a drop must exceed (default {DEFAULT_NOISE_FACTOR:g})")
    drops.add_argument("--min-drop", type=float, default=DEFAULT_MIN_DROP, metavar="N",
                       help=f"smallest drop that counts, N (default {DEFAULT_MIN_DROP:g})")
    drops.set_defaults(handler=run_drops)


def open_dataset(source: str) -> Dataset:
    """A shipped dataset by name, or a CSV file if ``source`` looks like a path."""
    if source.endswith(".csv") or os.sep in source or "/" in source:
        return load_dataset_file(source)
    return load_dataset(source)


def run_list(arguments: argparse.Namespace) -> int:
    """Print one line per shipped dataset: name, rows x columns, title."""
    datasets = [load_dataset(name) for name in list_datasets()]
    width = max(len(dataset.name) for dataset in datasets)
    for dataset in datasets:
        shape = f"{dataset.n_rows}x{len(dataset.columns)}"
        print(f"{dataset.name:<{width}}  {shape:>5}  {dataset.title}")
    return 0


def run_show(arguments: argparse.Namespace) -> int:
    """Print a dataset: title, source, notes, then the table with units in the header."""
    dataset = open_dataset(arguments.source)
    if arguments.csv:
        print(dataset.text, end="" if dataset.text.endswith("\n") else "\n")
        return 0
    print(f"{dataset.name}: {dataset.title}" if dataset.title else dataset.name)
    if dataset.source:
        print(f"source: {dataset.source}")
    for note in dataset.notes:
        print(f"note: {note}")
    print()
    headers = [f"{name} [{unit}]" if unit else name for name, unit in dataset.units.items()]
    cells = [[f"{value:.6g}" for value in column] for column in dataset.columns.values()]
    widths = [max(len(header), *(len(cell) for cell in column)) for header, column in zip(headers, cells)]
    print("  ".join(header.rjust(width) for header, width in zip(headers, widths)))
    for row in zip(*cells):
        print("  ".join(cell.rjust(width) for cell, width in zip(row, widths)))
    return 0


def run_fit(arguments: argparse.Namespace) -> int:
    """Fit a Gaussian sum and print its coefficients with units and the RMSE."""
    dataset = open_dataset(arguments.source)
    fit = fit_gaussian_sum(
        dataset[arguments.x], dataset[arguments.y], arguments.terms, nonnegative=arguments.nonnegative
    )
    x_unit, y_unit = column_unit(arguments.x), column_unit(arguments.y)
    print(f"f({arguments.x}) = sum_i a_i exp(-(({arguments.x} - b_i)/c_i)^2), {fit.n_terms} terms, "
          f"RMSE {fit.rmse:.4g} {y_unit}".rstrip())
    print(f"term  a [{y_unit or '-'}]  b [{x_unit or '-'}]  c [{x_unit or '-'}]")
    for term, (a, b, c) in enumerate(zip(fit.a, fit.b, fit.c), start=1):
        print(f"{term:>4}  {a:.6g}  {b:.6g}  {c:.6g}")
    return 0


def run_compare(arguments: argparse.Namespace) -> int:
    """Print RMSE, max error and point counts of a simulated curve against a table."""
    simulation = open_dataset(arguments.simulation)
    table = open_dataset(arguments.against)
    result = compare_to_experiment(
        simulation[arguments.x], simulation[arguments.y], table[arguments.exp_x], table[arguments.exp_y]
    )
    unit = column_unit(arguments.exp_y)
    print(f"rmse: {result['rmse']:.6g} {unit}".rstrip())
    print(f"max_abs_error: {result['max_abs_error']:.6g} {unit} at {arguments.exp_x} = {result['x_max_error']:g}")
    print(f"n_points: {result['n_points']} (outside the simulated range, not compared: {result['n_outside']})")
    return 0


def run_drops(arguments: argparse.Namespace) -> int:
    """Print the detected force drops, one per line."""
    dataset = open_dataset(arguments.source)
    events = detect_force_drops(
        dataset[arguments.force], dataset[arguments.x],
        noise_factor=arguments.noise_factor, min_drop=arguments.min_drop,
    )
    x_unit = column_unit(arguments.x)
    print(f"{len(events)} drop(s)")
    for event in events:
        print(f"at {arguments.x} = {event.x:.6g} {x_unit}: force {event.force:.6g} N falls by "
              f"{event.drop:.6g} N to {arguments.x} = {event.end_x:.6g} {x_unit}")
    return 0
