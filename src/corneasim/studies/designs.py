"""The cases of a study: parameter values from its design.

* ``grid``: every combination of the parameters' values (a list as given, a range as
  ``steps`` evenly spaced values), the last parameter varying fastest.
* ``latin-hypercube``: ``samples`` points, one in each of ``samples`` equal-probability strata
  of every parameter (McKay, Beckman & Conover 1979, doi:10.1080/00401706.1979.10489755).
* ``sobol``: Saltelli's extension of a Sobol' sequence, ``N (D + 2)`` points (``N (2 D + 2)``
  with second order) for the estimators of Saltelli et al. 2010
  (doi:10.1016/j.cpc.2009.09.018), SALib's ``sample.sobol``.
* ``morris``: ``r`` one-at-a-time trajectories of ``D + 1`` points on a ``p``-level grid
  (Morris 1991, doi:10.1080/00401706.1991.10484804), SALib's ``sample.morris``.
* ``realizations``: every grid point run as given and with the round-off perturbations that
  reveal a chaotic response (:data:`REALIZATIONS`).
* ``list``: the cases written out in the study (``design.cases``), for one-factor-at-a-time
  studies and for factors that set several keys together.

The sampled designs draw points ``u`` in the unit cube and map each coordinate through the
inverse distribution function of its parameter, ``x = F^-1(u)``. Unbounded distributions
(``normal``) are mapped from ``u`` clipped to [:data:`TAIL`, 1 - :data:`TAIL`], since a Morris grid
has levels at exactly 0 and 1.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from scipy import stats

from corneasim.studies.spec import LogUniform, Normal, Study, TruncatedNormal, Uniform, ValueRange

TAIL = 1e-3
"""Probability cut from each tail of an unbounded distribution in the sampled designs."""

REALIZATIONS = (
    ("as-given", {}, False),
    ("start-gap+1e-7", {"instrument.start_gap": 1e-7}, False),
    ("start-gap-1e-7", {"instrument.start_gap": -1e-7}, False),
    ("start-gap+5e-8", {"instrument.start_gap": 5e-8}, False),
    ("fresh-kernels", {}, True),
    ("one-thread", {"solver.threads": 1}, False),
)
"""(name, {key: change}, fresh Numba cache) of each realization: ``instrument.start_gap`` moved
by 1e-7, -1e-7 and 5e-8 mm (added to the case's value); a run whose kernels are compiled into
an empty ``NUMBA_CACHE_DIR`` in a process of its own (their last digits differ from the cached
ones'); a run on one thread (``solver.threads`` = 1, set, not added)."""


@dataclass
class Case:
    """One case of a study.

    Attributes
    ----------
    index : int
        Position in the design (the case folder is ``c`` + the index, zero-padded).
    values : dict
        Dotted scenario key -> value (unit of the key), the table's parameter columns.
    fresh_kernels : bool
        Run in a process of its own with an empty Numba cache.
    realization : str or None
        Name of the realization (``realizations`` designs only).
    """

    index: int
    values: dict
    fresh_kernels: bool = False
    realization: str | None = None

    @property
    def name(self) -> str:
        return case_name(self.index)


def case_name(index: int) -> str:
    """``c0000``, ``c0001``, ...; more digits past 9999."""
    return f"c{index:04d}"


def grid_values(parameter) -> list:
    """The values a grid takes for one parameter (list as given, range evenly spaced)."""
    if isinstance(parameter, ValueRange):
        if parameter.scale == "log":
            return [float(v) for v in np.geomspace(parameter.low, parameter.high, parameter.steps)]
        return [float(v) for v in np.linspace(parameter.low, parameter.high, parameter.steps)]
    return list(parameter)


def inverse_cdf(parameter, u: np.ndarray) -> np.ndarray:
    """x = F^-1(u) of a range (uniform, or log-uniform for a log range) or a distribution."""
    u = np.asarray(u, dtype=float)
    if isinstance(parameter, ValueRange):
        if parameter.scale == "log":
            return np.exp(np.log(parameter.low) + u * np.log(parameter.high / parameter.low))
        return parameter.low + u * (parameter.high - parameter.low)
    if isinstance(parameter, Uniform):
        return parameter.low + u * (parameter.high - parameter.low)
    if isinstance(parameter, LogUniform):
        return np.exp(np.log(parameter.low) + u * np.log(parameter.high / parameter.low))
    if isinstance(parameter, Normal):
        return stats.norm.ppf(np.clip(u, TAIL, 1 - TAIL), loc=parameter.mean, scale=parameter.std)
    if isinstance(parameter, TruncatedNormal):
        a, b = (parameter.low - parameter.mean) / parameter.std, (parameter.high - parameter.mean) / parameter.std
        return stats.truncnorm.ppf(u, a, b, loc=parameter.mean, scale=parameter.std)
    raise TypeError(f"not a sampled parameter: {parameter!r}")


def salib_problem(study: Study) -> dict:
    """The SALib problem on the unit cube (the designs map it through :func:`inverse_cdf`)."""
    names = list(study.parameters)
    return {"num_vars": len(names), "names": names, "bounds": [[0.0, 1.0]] * len(names)}


def unit_sample(study: Study) -> np.ndarray:
    """Points of a sampled design in the unit cube, shape (cases, parameters)."""
    design = study.design
    problem = salib_problem(study)
    if design.kind == "latin-hypercube":
        from scipy.stats import qmc

        return qmc.LatinHypercube(d=problem["num_vars"], seed=design.seed).random(design.samples)
    if design.kind == "sobol":
        from SALib.sample import sobol

        return sobol.sample(problem, design.samples, calc_second_order=design.second_order, seed=design.seed)
    if design.kind == "morris":
        from SALib.sample import morris

        return morris.sample(problem, design.samples, num_levels=design.levels, seed=design.seed)
    raise ValueError(f"{design.kind} is not a sampled design")


def cases(study: Study, scenario: str) -> list[Case]:
    """Every case of the study, in design order (``scenario``: the base scenario, as
    :func:`~corneasim.studies.spec.scenario_reference` gives it)."""
    names = list(study.parameters)
    kind = study.design.kind
    if kind == "list":
        return [Case(index, dict(values)) for index, values in enumerate(study.design.cases)]
    if kind in ("grid", "realizations"):
        points = [dict(zip(names, combination))
                  for combination in itertools.product(*(grid_values(study.parameters[n]) for n in names))]
        if kind == "grid":
            return [Case(index, point) for index, point in enumerate(points)]
        return _realizations(study, scenario, points)
    unit = unit_sample(study)
    columns = {name: inverse_cdf(study.parameters[name], unit[:, j]) for j, name in enumerate(names)}
    return [Case(i, {name: float(columns[name][i]) for name in names}) for i in range(unit.shape[0])]


def list_keys(study: Study) -> list[str]:
    """The keys the cases of a list design set, in the order they first appear (the table's columns)."""
    return list(dict.fromkeys(key for values in study.design.cases or [] for key in values))


def _realizations(study: Study, scenario: str, points: list[dict]) -> list[Case]:
    """Each grid point with every realization; the start gap is in every case's values (the
    perturbed ones add to the point's own)."""
    result = []
    for point in points:
        gap = base_value(study, scenario, point, "instrument.start_gap")
        for name, changes, fresh in REALIZATIONS:
            values = {**point, "instrument.start_gap": gap}
            for key, change in changes.items():
                values[key] = gap + change if key == "instrument.start_gap" else change
            result.append(Case(len(result), values, fresh_kernels=fresh, realization=name))
    return result


def base_value(study: Study, scenario: str, point: dict, key: str) -> float:
    """The value of ``key`` (its unit) in the scenario of a grid point, before a realization's change."""
    from corneasim.studies.case import case_overrides
    from corneasim.scenarios import load_scenario

    if key in point:
        return float(point[key])
    if key in study.overrides:
        return float(study.overrides[key])
    from corneasim.scenarios._overrides import parse_key

    _, resolved, _ = load_scenario(scenario, case_overrides(study.overrides, point), study.unset)
    table = resolved
    for part in parse_key(key):
        table = table[part]
    return float(table)
