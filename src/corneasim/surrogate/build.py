"""Build a surrogate from a study folder: split off held-out cases, fit, calibrate, score.

The saved model is the one fitted to the training cases; its metadata carries the
cross-validation scores of the calibration and the scores on the held-out cases, which the
fit never saw (:mod:`corneasim.surrogate._scores`).
"""

from __future__ import annotations

import numpy as np

from corneasim.errors import InputError
from corneasim.surrogate._evaluate import Surrogate
from corneasim.surrogate._fit import calibrate, fit_arrays, metadata
from corneasim.surrogate._scores import scores
from corneasim.surrogate._study import read_study, study_folders

DEFAULT_HOLD_OUT = 0.2
"""Fraction of the completed cases kept out of training to score the model."""


def split(count: int, hold_out: float, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Indices of the training and held-out cases: a seeded random ``hold_out`` fraction held out.

    >>> train, held = split(10, 0.2)
    >>> len(train), len(held), sorted(set(train) | set(held)) == list(range(10))
    (8, 2, True)
    """
    if not 0.0 <= hold_out < 1.0:
        raise InputError(f"hold_out: expected a fraction in [0, 1), got {hold_out}")
    order = np.random.default_rng(seed).permutation(count)
    held = int(round(hold_out * count))
    return np.sort(order[held:]), np.sort(order[:held])


def build_surrogate(study_dir, hold_out: float = DEFAULT_HOLD_OUT, seed: int = 0, events=None,
                    held_out_cases=None) -> Surrogate:
    """Fit a surrogate to the completed cases of the study in ``study_dir``.

    Parameters
    ----------
    study_dir : path or list of paths
        A study folder (``study.toml``, ``results.parquet`` or ``results.csv``, ``cases/``), or
        several of the same scenario, overrides and parameters, whose cases are pooled and
        named ``<folder>/<case>``.
    hold_out : float
        Fraction of the completed cases kept for the held-out scores (0: train on all).
    seed : int
        Seed of the held-out split and of the cross-validation folds.
    events : list of str, optional
        Puncture events to model (``epithelium``, ``stroma``, ``cornea``); the cases without one
        of them are left out of the fit (``metadata["left_out_cases"]``, with the reason).
        Default: the events of every completed case.
    held_out_cases : list of str, optional
        Names of the cases to hold out instead of a random ``hold_out`` fraction (those of an
        earlier model's ``metadata["held_out_cases"]``, to score a model of more cases on the
        same ones).

    Returns
    -------
    Surrogate
        Self-describing (``metadata``: inputs, ranges, units, scenario, version, training
        size, cross-validation and held-out scores, the cases left out and the events some
        cases lack, ``partial_events``).
    """
    folders = study_folders(study_dir)
    where = ", ".join(map(str, folders))
    training = read_study(folders, events)
    if held_out_cases is None:
        train, held = split(len(training.cases), hold_out, seed)
    else:
        names = [case.name for case in training.cases]
        unknown = [name for name in held_out_cases if name not in names]
        if unknown:
            raise InputError(f"held_out_cases: no completed case {unknown[0]!r} in {where}")
        held = np.array([k for k, name in enumerate(names) if name in held_out_cases], dtype=int)
        train = np.array([k for k, name in enumerate(names) if name not in held_out_cases], dtype=int)
    if len(train) < 3:
        raise InputError(f"{where}: {len(train)} training case(s) after the hold-out; need at least 3")
    cases = [training.cases[k] for k in train]
    low = np.array([item["low"] for item in training.inputs])
    high = np.array([item["high"] for item in training.inputs])
    arrays, kernels = fit_arrays(training, cases, low, high)
    cross_validation = calibrate(training, cases, low, high, arrays, kernels, seed=seed)
    model = Surrogate(metadata(training), arrays)
    held_out = scores([(model, [training.cases[k] for k in held])], training)
    model.metadata.update({
        "study": ", ".join(folder.name for folder in folders),
        "training_cases": [case.name for case in cases],
        "held_out_cases": [training.cases[k].name for k in held],
        "left_out_cases": training.left_out, "partial_events": training.partial_events,
        "cross_validation": _brief(cross_validation), "held_out": _brief(held_out),
    })
    return model


def _brief(result: dict) -> dict:
    """Scores without the per-case rows, except each case's relative RMSE and puncture errors."""
    brief = {key: value for key, value in result.items() if key != "per_case"}
    if result:
        brief["per_case"] = [{"case": c["case"],
                              "relative_rmse": {n: v["relative_rmse"] for n, v in c["channels"].items()},
                              "puncture_error": c["puncture_error"]} for c in result["per_case"]]
    return brief
