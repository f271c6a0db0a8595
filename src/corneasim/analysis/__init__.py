"""Curve tools: Gaussian-sum fits, error against experiments, puncture detection.

* :func:`gaussian_sum`, :func:`fit_gaussian_sum` -> :class:`GaussianFit`: the
  N-term Gaussian model the papers use to summarise force curves (needle paper
  eq. 16, trephination paper eq. 14);
* :func:`compare_to_experiment`: RMSE and maximum error of a simulated curve at
  an experimental table's abscissae;
* :func:`detect_force_drops` -> list of :class:`ForceDrop`: sudden force drops
  (punctures) above a robust noise threshold (:func:`noise_level`).

See ``docs/data.md``.
"""

from corneasim.analysis._compare import compare_to_experiment
from corneasim.analysis._drops import (
    DEFAULT_MIN_DROP,
    DEFAULT_NOISE_FACTOR,
    ForceDrop,
    detect_force_drops,
    noise_level,
)
from corneasim.analysis._gaussian import GaussianFit, fit_gaussian_sum, gaussian_sum

__all__ = [
    "DEFAULT_MIN_DROP",
    "DEFAULT_NOISE_FACTOR",
    "ForceDrop",
    "GaussianFit",
    "compare_to_experiment",
    "detect_force_drops",
    "fit_gaussian_sum",
    "gaussian_sum",
    "noise_level",
]
