"""Sensitivity indices of a study's scalar outputs: Morris screening and Sobol' variance shares.

* Morris (SALib ``analyze.morris``): per parameter the mean of the absolute elementary effects
  mu* and their standard deviation sigma (Morris 1991; Campolongo, Cariboni & Saltelli 2007,
  doi:10.1016/j.envsoft.2006.10.004), in output units per unit of the normalised input (the
  input's quantile, 0..1). The confidence interval of mu* is SALib's bootstrap; that of sigma
  a bootstrap over the trajectories (percentiles of sigma recomputed on trajectories drawn
  with replacement). A trajectory with a failed case is left out.
* Sobol' (SALib ``analyze.sobol``): first-order S1 and total ST indices with their bootstrap
  confidence intervals (Saltelli et al. 2010, doi:10.1016/j.cpc.2009.09.018); they need every
  case, so one failed case leaves them uncomputed.

Confidence intervals are half-widths at ``confidence`` (default 95%).
"""

from __future__ import annotations

import numpy as np

from corneasim.studies.designs import salib_problem, unit_sample
from corneasim.studies.spec import Study

CONFIDENCE = 0.95
RESAMPLES = 200


def morris_indices(study: Study, y: np.ndarray, seed: int = 0) -> dict | None:
    """mu*, sigma and their confidence half-widths per parameter; None if no trajectory is complete.

    ``y``: the output of every case in design order (NaN for failed cases).
    """
    from SALib.analyze import morris

    problem = salib_problem(study)
    x = unit_sample(study)
    size = problem["num_vars"] + 1
    complete = [t for t in range(len(y) // size) if np.all(np.isfinite(y[t * size:(t + 1) * size]))]
    if len(complete) < 2:
        return None

    def analyse(trajectories, resamples=RESAMPLES):
        rows = np.concatenate([np.arange(t * size, (t + 1) * size) for t in trajectories])
        return morris.analyze(problem, x[rows], y[rows], num_resamples=resamples, conf_level=CONFIDENCE,
                              num_levels=study.design.levels, seed=seed)

    result = analyse(complete)
    generator = np.random.default_rng(seed)
    sigmas = np.array([analyse(generator.choice(complete, len(complete)), resamples=2)["sigma"]
                       for _ in range(RESAMPLES)])
    low, high = np.percentile(sigmas, [50 * (1 - CONFIDENCE), 50 * (1 + CONFIDENCE)], axis=0)
    return {"names": problem["names"], "mu_star": np.asarray(result["mu_star"]),
            "mu_star_conf": np.asarray(result["mu_star_conf"]), "sigma": np.asarray(result["sigma"]),
            "sigma_conf": (high - low) / 2, "trajectories": len(complete)}


def sobol_indices(study: Study, y: np.ndarray, seed: int = 0) -> dict | None:
    """S1, ST and their confidence half-widths per parameter; None unless every case has a value."""
    from SALib.analyze import sobol

    if not np.all(np.isfinite(y)):
        return None
    problem = salib_problem(study)
    result = sobol.analyze(problem, y, calc_second_order=study.design.second_order, num_resamples=RESAMPLES,
                           conf_level=CONFIDENCE, seed=seed)
    return {"names": problem["names"], "S1": np.asarray(result["S1"]), "S1_conf": np.asarray(result["S1_conf"]),
            "ST": np.asarray(result["ST"]), "ST_conf": np.asarray(result["ST_conf"])}
