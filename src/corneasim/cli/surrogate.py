"""``corneasim surrogate``: build, check, evaluate and export force surrogates of a study."""

from __future__ import annotations

import argparse
from pathlib import Path

from corneasim.errors import InputError

HELP = "Fast force surrogates of a study's cases: build, check, predict, export to C."

BUILD = """Fit a force surrogate with a calibrated 95% band to a study's completed cases.

Learns force against depth (needle) or F_z, F_c against time (trephine), and the puncture
depths, as functions of the study's varied parameters; the band is calibrated by
cross-validation; the scores on held-out cases go into the model file. Units: mm, s, N."""
CHECK = """Print a surrogate's inputs, training ranges, training size and held-out scores.

Also its scenario, corneasim version, curves, events and cross-validation scores."""
PREDICT = """Print a surrogate's puncture depths and force band at given inputs.

Inputs are KEY=VALUE (dotted study keys or their short names), in the model's units; inputs
outside the training range are refused (exit 2) unless --extrapolate. Force in N."""
EXPORT = """Write a C header of a surrogate's arrays and a reference evaluator in plain C.

surrogate_eval.h holds the evaluator, surrogate_model.h the arrays of one channel with the
inputs' order, units and ranges in its comment, for a C or C++ controller."""
EXAMPLES = {"build": "corneasim surrogate build results/speed --out speed.npz",
            "check": "corneasim surrogate check speed.npz",
            "predict": "corneasim surrogate predict speed.npz rate=5 diameter=0.2 --at 0.2,0.4",
            "export-c": "corneasim surrogate export-c speed.npz --out controller"}


def register(commands: argparse._SubParsersAction) -> None:
    """Add ``surrogate build | check | predict | export-c``."""
    group = commands.add_parser("surrogate", help=HELP, description=HELP)
    sub = group.add_subparsers(dest="surrogate_command", metavar="COMMAND", required=True,
                               parser_class=type(group))
    formatter = argparse.RawDescriptionHelpFormatter
    build = sub.add_parser("build", help="Fit a surrogate to a study's completed cases.", description=BUILD,
                           formatter_class=formatter, epilog=f"example: {EXAMPLES['build']}")
    build.add_argument("study", type=Path, nargs="+",
                       help="study results folder (corneasim study run --out); several of the same scenario "
                            "and parameters are pooled")
    build.add_argument("--out", type=Path, required=True, help="model file to write (.npz)")
    build.add_argument("--hold-out", type=float, default=0.2, metavar="FRACTION",
                       help="fraction of the cases kept out of the fit to score it (default 0.2)")
    build.add_argument("--seed", type=int, default=0, help="seed of the hold-out split and the folds")
    build.add_argument("--events", metavar="LIST",
                       help="comma-separated puncture events to model (epithelium, stroma, cornea); cases "
                            "without one of them are left out (default: the events of every case)")
    build.set_defaults(handler=run_build)
    check = sub.add_parser("check", help="Describe a model: inputs, ranges, training size, scores.",
                           description=CHECK, formatter_class=formatter, epilog=f"example: {EXAMPLES['check']}")
    check.add_argument("model", type=Path, help="model file (.npz)")
    check.set_defaults(handler=run_check)
    predict = sub.add_parser("predict", help="Evaluate a model at given inputs.", description=PREDICT,
                             formatter_class=formatter, epilog=f"example: {EXAMPLES['predict']}")
    predict.add_argument("model", type=Path, help="model file (.npz)")
    predict.add_argument("inputs", nargs="*", metavar="KEY=VALUE", help="input values, the model's units")
    predict.add_argument("--at", default="", metavar="LIST", help="comma-separated depths (mm) or times (s)")
    predict.add_argument("--channel", help="curve to evaluate (default: the first)")
    predict.add_argument("--extrapolate", action="store_true", help="allow inputs outside the training range")
    predict.set_defaults(handler=run_predict)
    export = sub.add_parser("export-c", help="Write a C header and reference evaluator.", description=EXPORT,
                            formatter_class=formatter, epilog=f"example: {EXAMPLES['export-c']}")
    export.add_argument("model", type=Path, help="model file (.npz)")
    export.add_argument("--out", type=Path, required=True, help="folder for the two headers")
    export.add_argument("--channel", help="curve to export (default: the first)")
    export.set_defaults(handler=run_export)


def run_build(arguments) -> int:
    """Build, save and describe a model."""
    from corneasim.surrogate import build_surrogate

    events = None if arguments.events is None else [e.strip() for e in arguments.events.split(",") if e.strip()]
    model = build_surrogate(arguments.study, hold_out=arguments.hold_out, seed=arguments.seed, events=events)
    model.save(arguments.out)
    print(describe(model.metadata))
    print(f"written: {arguments.out}")
    return 0


def run_check(arguments) -> int:
    """Describe a saved model."""
    from corneasim.surrogate import load

    print(describe(load(arguments.model).metadata))
    return 0


def run_predict(arguments) -> int:
    """Punctures and force at the given inputs."""
    from corneasim.surrogate import load

    model = load(arguments.model)
    inputs = {}
    for item in arguments.inputs:
        key, _, value = item.partition("=")
        try:
            inputs[key.strip()] = float(value)
        except ValueError:
            raise InputError(f"{item!r}: expected KEY=NUMBER") from None
    at = [_number(text) for text in arguments.at.split(",") if text.strip()]
    unit = model.metadata["abscissa"]["unit"]
    for event, (mean, lower, upper) in model.punctures(arguments.extrapolate, **inputs).items():
        print(f"puncture {event}: {mean:.4f} {unit} (95% band {lower:.4f} - {upper:.4f})")
    if at:
        mean, lower, upper = model.predict(at, arguments.channel, arguments.extrapolate, **inputs)
        for a, m, lo, hi in zip(at, mean, lower, upper):
            print(f"{model.metadata['abscissa']['name']} {a:g}: {m:.4f} N (95% band {lo:.4f} - {hi:.4f})")
    return 0


def run_export(arguments) -> int:
    """Write the C headers."""
    from corneasim.surrogate import load, write_c_export

    for path in write_c_export(load(arguments.model), arguments.out, arguments.channel):
        print(f"written: {path}")
    return 0


def describe(meta: dict) -> str:
    """The model's description: what ``corneasim surrogate check`` prints."""
    lines = [f"surrogate of {meta['kind']} scenario {meta['scenario'].get('scenario')!r} "
             f"(overrides {meta['scenario'].get('overrides')}), corneasim {meta['corneasim_version']}, "
             f"format {meta['format']} {meta['format_version']}",
             f"trained on {len(meta.get('training_cases', []))} cases of study {meta.get('study', '?')!r}, "
             f"{len(meta.get('held_out_cases', []))} held out",
             f"curves: {', '.join(c['name'] for c in meta['channels'])} against {meta['abscissa']['name']} "
             f"0 - {meta['abscissa']['max']:.4g} {meta['abscissa']['unit']}; "
             f"punctures: {', '.join(meta['events']) or 'none'}", "inputs:"]
    lines += [f"  {item['name']} ({item['alias']}): {item['low']:.6g} - {item['high']:.6g} {item['unit']}"
              for item in meta["inputs"]]
    lines += [f"left out: {item['case']} ({item['reason']})" for item in meta.get("left_out_cases", [])]
    modelled = list(meta["events"])
    lines += [f"not modelled: {event}, missing from {len(names)} case(s) ({', '.join(names[:3])}"
              f"{', ...' if len(names) > 3 else ''}); --events {','.join(modelled + [event])} models it without them"
              for event, names in meta.get("partial_events", {}).items() if event not in modelled]
    for label in ("cross_validation", "held_out"):
        scores = meta.get(label) or {}
        if not scores:
            lines.append(f"{label.replace('_', '-')}: none")
            continue
        parts = [f"{name} RMSE/peak max {100 * s['relative_rmse_max']:.1f}% mean {100 * s['relative_rmse_mean']:.1f}%, "
                 f"inside 95% band {100 * s['coverage']:.1f}%" for name, s in scores["channels"].items()]
        parts += [f"{event} error max {error:.4g} {meta['abscissa']['unit']}"
                  for event, error in scores["puncture_error_max"].items()]
        lines.append(f"{label.replace('_', '-')} ({scores['cases']} cases): " + "; ".join(parts))
    return "\n".join(lines)


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise InputError(f"--at: {text.strip()!r} is not a number") from None
