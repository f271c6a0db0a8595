"""The study file: a base scenario, the parameters varied, the design and the outputs collected.

A study file is TOML validated like a scenario (every model a
:class:`~corneasim.schema.StrictModel`, so an unknown key is one line naming it). Parameters
are dotted scenario keys, as ``corneasim run --set``; each is a list of values, a range
(``{ low, high, steps }``) or a distribution (``{ distribution = "uniform", low, high }``,
``log-uniform``, ``normal`` with ``mean`` and ``std``, ``truncated-normal`` with all four).
Outputs are dotted paths into ``summary.json`` or curves of the history resampled on a
given abscissa. Every key and its unit: ``docs/studies.md``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Literal, Union

import pydantic
from pydantic import Field

from corneasim.errors import InputError
from corneasim.schema import StrictModel, load_toml

ScalarValue = Union[bool, int, float, str]
Value = Union[ScalarValue, list, dict]


class ValueRange(StrictModel):
    """Evenly spaced values ``low .. high`` (both included); sampled designs draw uniformly
    (``scale = "log"``: log-uniformly) between the bounds. Unit: the key's."""

    low: float = Field(description="Lower bound, unit of the key.")
    high: float = Field(description="Upper bound, unit of the key.")
    steps: pydantic.PositiveInt = Field(2, description="Number of values of a grid design (>= 2 unless low == high).")
    scale: Literal["linear", "log"] = Field("linear", description="Spacing of the values: linear or logarithmic.")

    @pydantic.model_validator(mode="after")
    def _bounds(self):
        if not self.low < self.high:
            raise ValueError(f"range needs low < high, got low = {self.low}, high = {self.high}")
        if self.scale == "log" and not self.low > 0:
            raise ValueError(f"a log range needs low > 0, got {self.low}")
        return self


class Uniform(StrictModel):
    """Uniform on [low, high], unit of the key."""

    distribution: Literal["uniform"]
    low: float = Field(description="Lower bound, unit of the key.")
    high: float = Field(description="Upper bound, unit of the key.")

    @pydantic.model_validator(mode="after")
    def _bounds(self):
        if not self.low < self.high:
            raise ValueError(f"uniform distribution needs low < high, got low = {self.low}, high = {self.high}")
        return self


class LogUniform(StrictModel):
    """log(value) uniform on [log low, log high]; 0 < low < high, unit of the key."""

    distribution: Literal["log-uniform"]
    low: float = Field(description="Lower bound (> 0), unit of the key.")
    high: float = Field(description="Upper bound, unit of the key.")

    @pydantic.model_validator(mode="after")
    def _bounds(self):
        if not 0 < self.low < self.high:
            raise ValueError(f"log-uniform distribution needs 0 < low < high, got low = {self.low}, "
                             f"high = {self.high}")
        return self


class Normal(StrictModel):
    """Normal with mean and standard deviation, unit of the key."""

    distribution: Literal["normal"]
    mean: float = Field(description="Mean, unit of the key.")
    std: float = Field(description="Standard deviation (> 0), unit of the key.")

    @pydantic.model_validator(mode="after")
    def _bounds(self):
        if not (self.std > 0 and math.isfinite(self.std)):
            raise ValueError(f"normal distribution needs std > 0, got {self.std}")
        return self


class TruncatedNormal(StrictModel):
    """Normal(mean, std) restricted to [low, high], unit of the key."""

    distribution: Literal["truncated-normal"]
    mean: float = Field(description="Mean of the untruncated normal, unit of the key.")
    std: float = Field(description="Standard deviation of the untruncated normal (> 0), unit of the key.")
    low: float = Field(description="Lower bound, unit of the key.")
    high: float = Field(description="Upper bound, unit of the key.")

    @pydantic.model_validator(mode="after")
    def _bounds(self):
        if not (self.std > 0 and math.isfinite(self.std)):
            raise ValueError(f"truncated-normal distribution needs std > 0, got {self.std}")
        if not self.low < self.high:
            raise ValueError(f"truncated-normal distribution needs low < high, got low = {self.low}, "
                             f"high = {self.high}")
        return self




class Design(StrictModel):
    """How the cases are chosen from the parameters."""

    kind: Literal["grid", "latin-hypercube", "sobol", "morris", "realizations", "list"] = Field(
        "grid", description="grid: every combination; latin-hypercube: `samples` cases; sobol: Saltelli's "
        "samples * (2 D + 2) cases (samples * (D + 2) without second order); morris: `samples` trajectories "
        "of D + 1 cases; realizations: every grid point run with round-off perturbations; list: the cases of "
        "`cases`, as given.")
    samples: pydantic.PositiveInt | None = Field(
        None, description="latin-hypercube: number of cases; sobol: base sample N (a power of 2); "
        "morris: number of trajectories r.")
    levels: pydantic.PositiveInt = Field(4, description="morris: grid levels p of each parameter (even).")
    second_order: bool = Field(False, description="sobol: also the second-order indices S2 (2 D + 2 cases per "
                               "base sample instead of D + 2).")
    seed: int = Field(0, description="Seed of the random designs (latin-hypercube, sobol, morris).")
    cases: list[dict[str, Value]] | None = Field(
        None, description="list: one table per case, dotted scenario key -> value (unit of the key); keys that "
        "change together (a speed and the end time of the same depth) go in one case.")

    @pydantic.model_validator(mode="after")
    def _samples(self):
        if (self.kind == "list") != (self.cases is not None):
            raise ValueError("cases: a list design needs its cases, and only a list design takes them")
        if self.kind == "list" and not self.cases:
            raise ValueError("cases: a list design needs at least one case")
        if self.kind in ("latin-hypercube", "sobol", "morris") and self.samples is None:
            raise ValueError(f"samples: a {self.kind} design needs a number of samples")
        if self.kind in ("grid", "realizations", "list") and self.samples is not None:
            raise ValueError(f"samples: a {self.kind} design takes no samples")
        if self.kind == "morris" and (self.levels < 2 or self.levels % 2):
            raise ValueError(f"levels: morris needs an even number of levels >= 2, got {self.levels}")
        if self.kind == "sobol" and self.samples & (self.samples - 1):
            raise ValueError(f"samples: sobol needs a power of 2, got {self.samples}")
        return self


class Abscissa(StrictModel):
    """Evenly spaced abscissa values ``low .. high`` (both included), unit of the x column."""

    low: float = Field(description="First value, unit of the x column.")
    high: float = Field(description="Last value, unit of the x column.")
    steps: Annotated[int, Field(ge=2)] = Field(description="Number of values (>= 2).")

    @pydantic.model_validator(mode="after")
    def _bounds(self):
        if not self.low < self.high:
            raise ValueError(f"abscissa needs low < high, got low = {self.low}, high = {self.high}")
        return self


class CurveOutput(StrictModel):
    """A history column resampled (linear interpolation) on a given abscissa; NaN outside the run."""

    curve: str = Field(description="History column of the ordinate, e.g. force_N (unit in its name).")
    x: str = Field(description="History column of the abscissa, e.g. depth_mm or time_s.")
    at: Union[list[float], Abscissa] = Field(description="Abscissa values, unit of the x column: a list or "
                                             "{ low, high, steps }.")

    @pydantic.field_validator("at")
    @classmethod
    def _increasing(cls, value):
        if isinstance(value, list) and (len(value) < 2 or any(b <= a for a, b in zip(value, value[1:]))):
            raise ValueError("at: expected at least two increasing values")
        return value


class Calibration(StrictModel):
    """Fit the study's parameters to a measured curve: minimise the RMSE of one curve output."""

    curve: str = Field(description="Name of a curve output of [outputs].")
    dataset: str = Field(description="Built-in dataset name (corneasim data list) or a CSV file (units in the "
                         "header, relative to the study file).")
    x_column: str = Field(description="Abscissa column of the dataset, same unit as the curve's x.")
    y_column: str = Field(description="Ordinate column of the dataset, same unit as the curve.")
    evaluations: pydantic.PositiveInt = Field(24, description="Number of cases run.")
    batch: pydantic.PositiveInt | None = Field(None, description="Cases run at once (default: the workers).")
    seed: int = Field(0, description="Seed of the optimiser (optuna TPE).")


class Study(StrictModel):
    """A study file (module notes; ``docs/studies.md``). ``parameters`` and ``outputs`` hold their
    validated models (:func:`read_study` parses them one key at a time, for one-line errors)."""

    scenario: str = Field(description="Built-in scenario name or a scenario file, relative to the study file.")
    description: str = Field("", description="What the study asks.")
    overrides: dict[str, Value] = Field({}, description="Fixed overrides of every case: dotted key -> value.")
    unset: list[str] = Field([], description="Dotted keys removed from every case, so that each takes its "
                             "default (as `corneasim run --unset`).")
    design: Design = Field(default_factory=Design, description="How cases are chosen.")
    parameters: dict[str, object] = Field({}, description="Dotted scenario key -> list, range or distribution.")
    outputs: dict[str, object] = Field(description="Output name -> dotted path into summary.json, or a curve table.")
    calibration: Calibration | None = Field(None, description="What `corneasim calibrate` fits.")
    case_plots: bool = Field(False, description="Write each case's plots/ and report.html (false: the data "
                             "files only, 1-2 s less per case).")


def _one_line(error: pydantic.ValidationError, where: str) -> str:
    first = error.errors()[0]
    loc = ".".join(str(part) for part in first.get("loc", ()) if not str(part).startswith("function-"))
    message = "unknown key" if first.get("type") == "extra_forbidden" else first.get("msg", "invalid value")
    message = message.removeprefix("Value error, ")
    return f"{where}.{loc}: {message}" if loc else f"{where}: {message}"


def _part(model, data, where: str):
    try:
        return pydantic.TypeAdapter(model).validate_python(data)
    except pydantic.ValidationError as error:
        raise InputError(_one_line(error, where)) from None


def parse_parameter(value, where: str):
    """A list of values, a :class:`ValueRange` or a distribution, from a TOML value."""
    if isinstance(value, list):
        if not value:
            raise InputError(f"{where}: expected at least one value")
        return value
    if not isinstance(value, dict):
        raise InputError(f"{where}: expected a list of values, a range {{ low, high, steps }} or a distribution "
                         "{ distribution = ..., ... }")
    if "distribution" in value:
        kinds = {"uniform": Uniform, "log-uniform": LogUniform, "normal": Normal, "truncated-normal": TruncatedNormal}
        if value["distribution"] not in kinds:
            raise InputError(f"{where}.distribution: expected one of {', '.join(kinds)}, got {value['distribution']!r}")
        return _part(kinds[value["distribution"]], value, where)
    return _part(ValueRange, value, where)


def parse_output(value, where: str):
    """A dotted summary path (str) or a :class:`CurveOutput`."""
    if isinstance(value, str):
        if not value or not all(value.split(".")):
            raise InputError(f"{where}: expected a dotted path into summary.json, e.g. validation.rmse_N")
        return value
    if not isinstance(value, dict):
        raise InputError(f"{where}: expected a dotted summary path or a curve {{ curve, x, at }}")
    return _part(CurveOutput, value, where)


def _check(study: Study, source: str) -> None:
    kind = study.design.kind
    sampled = kind in ("latin-hypercube", "sobol", "morris")
    for key, parameter in study.parameters.items():
        where = f"{source}: parameters.{key}"
        if sampled and isinstance(parameter, list):
            raise InputError(f"{where}: a {kind} design samples ranges or distributions, not a list of values")
        if not sampled and not isinstance(parameter, (list, ValueRange)):
            raise InputError(f"{where}: a {kind} design needs a list or a range, not a distribution")
        if key in study.overrides:
            raise InputError(f"{where}: also a fixed override")
        if key in study.unset:
            raise InputError(f"{where}: also in unset (a removed key takes its default)")
    if kind == "list" and study.parameters:
        raise InputError(f"{source}: parameters: a list design takes its values from design.cases, not parameters")
    for index, case in enumerate(study.design.cases or []):
        for key in case:
            if key in study.overrides:
                raise InputError(f"{source}: design.cases[{index}].{key}: also a fixed override")
    if sampled and not study.parameters:
        raise InputError(f"{source}: parameters: a {kind} design needs at least one parameter")
    if kind == "morris" and len(study.parameters) < 2:
        raise InputError(f"{source}: parameters: a morris design needs at least two parameters")
    if not study.outputs:
        raise InputError(f"{source}: outputs: expected at least one output")
    calibration = study.calibration
    if calibration is not None:
        if not isinstance(study.outputs.get(calibration.curve), CurveOutput):
            raise InputError(f"{source}: calibration.curve: {calibration.curve!r} is not a curve output of [outputs]")
        if not study.parameters:
            raise InputError(f"{source}: parameters: calibration needs at least one parameter to fit")
        for key, parameter in study.parameters.items():
            if isinstance(parameter, list):
                raise InputError(f"{source}: parameters.{key}: calibration needs bounds (a range or a distribution)")


def read_study(spec: str | Path | dict) -> tuple[Study, Path, dict]:
    """Validate a study file or table.

    Parameters
    ----------
    spec : path-like or dict
        Study TOML file, or its tables as a dict.

    Returns
    -------
    study : Study
        With ``parameters`` and ``outputs`` parsed into their models.
    base_dir : Path
        Folder that relative paths of the study refer to (the file's; the current one for a dict).
    tables : dict
        The raw tables (for the copy in the results folder).
    """
    if isinstance(spec, dict):
        tables, base_dir, source = spec, Path.cwd(), "study"
    else:
        path = Path(spec)
        tables, base_dir, source = load_toml(path), path.resolve().parent, str(path)
    try:
        raw = Study.model_validate(tables)
    except pydantic.ValidationError as error:
        raise InputError(_one_line(error, source).replace(f"{source}.", f"{source}: ", 1)) from None
    parameters = {key: parse_parameter(value, f"{source}: parameters.{key}") for key, value in raw.parameters.items()}
    outputs = {name: parse_output(value, f"{source}: outputs.{name}") for name, value in raw.outputs.items()}
    study = raw.model_copy(update={"parameters": parameters, "outputs": outputs})
    _check(study, source)
    return study, base_dir, tables


def scenario_reference(study: Study, base_dir: Path) -> str:
    """The base scenario as ``load_scenario`` takes it: a built-in name or an absolute file path."""
    from corneasim.scenarios import list_scenarios

    if study.scenario in list_scenarios():
        return study.scenario
    return str((base_dir / study.scenario).resolve())
