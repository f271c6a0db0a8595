"""Fit a force surrogate to training cases: registration, principal components, Gaussian processes.

1. **Registration.** Each case's curve :math:`F_n(a)` is resampled on a uniform grid of the
   registered abscissa :math:`s \\in [0, a_{max}]`, the piecewise-linear map taking its own
   puncture abscissae :math:`\\lambda_{ne}` to their training mean :math:`\\bar\\lambda_e`
   (landmark registration, Ramsay & Silverman, *Functional Data Analysis*, 2005, ch. 7): the
   drops of every case line up, so a few components describe the curves.
2. **Principal components** of the registered curves (SVD of the centred matrix), as many as
   keep :data:`VARIANCE_KEPT` of the variance (at most :data:`MAX_COMPONENTS`).
3. **Gaussian processes**, one per output (each puncture abscissa, each component coefficient),
   with the kernel :math:`c\\,\\exp(-\\tfrac12 \\lVert (u - u')/\\ell \\rVert^2) + \\sigma_n^2\\delta`
   on the inputs scaled to [0, 1], hyperparameters by maximum marginal likelihood
   (scikit-learn; Rasmussen & Williams, *Gaussian Processes for Machine Learning*, 2006, eq. 2.30;
   the posterior, eq. 2.25-2.26).
   The posterior is stored as closed-form arrays (:mod:`corneasim.surrogate._evaluate`).
4. **Band calibration** (:func:`calibrate`): K-fold cross-validation gives the residual variance
   :math:`r(s)` the model does not explain (smoothed over :data:`SMOOTHING` grid points each side)
   and the factor :math:`q` that puts 95% of the left-out samples inside
   :math:`F \\pm q\\sqrt{\\sum_k \\phi_k^2 v_k + r}`.
"""

from __future__ import annotations

import warnings

import numpy as np

from corneasim.surrogate._evaluate import FORMAT, FORMAT_VERSION, Surrogate

GRID_POINTS = 256
VARIANCE_KEPT = 0.999
MAX_COMPONENTS = 10
SMOOTHING = 4
LEVEL = 0.95
NOMINAL_FACTOR = 1.959964
"""The normal distribution's two-sided 95% factor: the least an event band is widened to."""
FOLDS = 5
RESTARTS = 1
"""Extra random starts of the full fit's likelihood maximisation."""


def metadata(training, extra: dict | None = None) -> dict:
    """The self-description of a model of ``training`` (a :class:`~corneasim.surrogate._study.TrainingSet`)."""
    from corneasim import __version__

    return {"format": FORMAT, "format_version": FORMAT_VERSION, "kind": training.kind,
            "corneasim_version": __version__, "scenario": training.scenario,
            "inputs": training.inputs, "abscissa": training.abscissa, "channels": training.channels,
            "events": training.events, "band_level": LEVEL, **(extra or {})}


def registered_curve(case, events, reference, maximum, channel, grid) -> np.ndarray:
    """``case``'s curve of ``channel`` on the registered ``grid`` (its punctures moved to ``reference``)."""
    knots = np.concatenate(([0.0], [case.events[e] for e in events], [maximum]))
    anchors = np.concatenate(([0.0], reference, [maximum]))
    return np.interp(np.interp(grid, anchors, knots), case.abscissa, case.forces[channel])


def fit_gaussian_process(U: np.ndarray, y: np.ndarray, start=None) -> tuple:
    """Posterior arrays of a GP of ``y`` (N,) on the scaled inputs ``U`` (N, D).

    ``start``: a fitted kernel to start the likelihood's maximisation from (one start instead
    of :data:`RESTARTS` + 1 from the default; the cross-validation folds start from the full fit).

    Returns
    -------
    inverse_length_scales (D,), weights (N,), covariance_weights (N, N), prior_variance, mean, noise_variance
        With :math:`\\tilde k_n = \\exp(-\\tfrac12\\lVert (u - U_n)/\\ell\\rVert^2)`: mean
        :math:`\\bar y + \\sum_n w_n \\tilde k_n`, variance :math:`v^0 - \\tilde k^T C \\tilde k`,
        at least the noise variance :math:`\\sigma_n^2` (the variance of a new case's output).
    """
    from sklearn.exceptions import ConvergenceWarning
    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel

    mean = float(y.mean())
    scale = float(y.std()) or 1.0
    t = (y - mean) / scale
    kernel = start if start is not None else (
        ConstantKernel(1.0, (1e-2, 1e2)) * RBF(np.full(U.shape[1], 0.5), (0.05, 50.0))
        + WhiteKernel(1e-2, (1e-6, 1.0)))
    restarts = 0 if start is not None else RESTARTS
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        fitted = GaussianProcessRegressor(kernel, n_restarts_optimizer=restarts, random_state=0).fit(U, t).kernel_
    amplitude = fitted.k1.k1.constant_value
    inverse = 1.0 / np.broadcast_to(fitted.k1.k2.length_scale, (U.shape[1],))
    z = (U[:, None, :] - U[None, :, :]) * inverse                         # (N, N, D)
    K = amplitude * np.exp(-0.5 * np.einsum("npd,npd->np", z, z)) + fitted.k2.noise_level * np.eye(len(y))
    K_inverse = np.linalg.inv(K)
    noise = scale**2 * fitted.k2.noise_level
    return (inverse, scale * amplitude * (K_inverse @ t), scale**2 * amplitude**2 * K_inverse,
            scale**2 * amplitude + noise, mean, noise, fitted)


def fit_arrays(training, cases, low, high, components=None, starts=None) -> tuple[dict, list]:
    """The model arrays fitted to ``cases`` (bands not yet calibrated: r = 0, q = 1) and the kernels.

    ``components``: principal components kept per channel (default: by :data:`VARIANCE_KEPT`);
    ``starts``: kernels to start each output's fit from (:func:`fit_gaussian_process`).
    """
    events, maximum = training.events, training.abscissa["max"]
    U = (np.array([case.inputs for case in cases]) - low) / (high - low)           # (N, D)
    landmarks = np.array([[case.events[e] for e in events] for case in cases]).reshape(len(cases), -1)
    reference = landmarks.mean(axis=0)                                             # (L,)
    grid = np.linspace(0.0, maximum, GRID_POINTS)
    targets = [landmarks[:, e] for e in range(len(events))]
    arrays = {"inputs_low": low, "inputs_high": high, "train_inputs": U, "event_reference": reference,
              "event_band_factor": np.full(len(events), NOMINAL_FACTOR),
              "event_residual_variance": np.zeros(len(events))}
    for channel in training.channels:
        name = channel["name"]
        Y = np.array([registered_curve(c, events, reference, maximum, name, grid) for c in cases])  # (N, G)
        curve = Y.mean(axis=0)
        _, singular, rows = np.linalg.svd(Y - curve, full_matrices=False)
        kept = np.cumsum(singular**2) / max(np.sum(singular**2), 1e-300)
        count = int(min(np.searchsorted(kept, VARIANCE_KEPT) + 1, MAX_COMPONENTS, len(cases) - 1)
                    if components is None else components[name])
        basis = rows[:count]                                                       # (K, G)
        targets += list(((Y - curve) @ basis.T).T)
        arrays.update({f"mean_curve_{name}": curve, f"basis_{name}": basis,
                       f"residual_variance_{name}": np.zeros(GRID_POINTS), f"band_factor_{name}": np.array(1.0)})
    fits = [fit_gaussian_process(U, y, start) for y, start in zip(targets, starts or [None] * len(targets))]
    for key, part in zip(("inverse_length_scales", "weights", "covariance_weights", "prior_variance",
                          "output_mean", "noise_variance"), zip(*fits)):
        arrays[key] = np.array(part)
    return arrays, [fit[-1] for fit in fits]


def calibrate(training, cases, low, high, arrays: dict, kernels: list, folds: int = FOLDS, seed: int = 0) -> dict:
    """Residual variance r(s), force band factors q and event band factors, by K-fold cross-validation.

    Returns the cross-validation scores (:func:`corneasim.surrogate._scores.scores` of the
    left-out cases under the calibrated bands); ``arrays`` is updated in place.
    """
    from corneasim.surrogate._scores import scores

    meta = metadata(training)
    components = {c["name"]: len(arrays[f"basis_{c['name']}"]) for c in training.channels}
    folds = min(folds, len(cases))
    order = np.random.default_rng(seed).permutation(len(cases))
    models = []
    for fold in range(folds):
        left_out = [cases[k] for k in order[fold::folds]]
        kept = [cases[k] for k in np.sort(np.concatenate([order[f::folds] for f in range(folds) if f != fold]))]
        fold_arrays, _ = fit_arrays(training, kept, low, high, components, kernels)
        models.append((Surrogate(meta, fold_arrays), left_out))
    maximum = training.abscissa["max"]
    grid = np.linspace(0.0, maximum, GRID_POINTS)
    for channel in training.channels:
        name = channel["name"]
        excess = []
        for model, left_out in models:
            for case in left_out:
                inputs = dict(zip(model.inputs, case.inputs))
                events = np.array([model.punctures(extrapolate=True, **inputs)[e][0] for e in training.events])
                anchors = np.concatenate(([0.0], np.clip(np.maximum.accumulate(events), 0, maximum), [maximum]))
                a = np.interp(grid, np.concatenate(([0.0], model.arrays["event_reference"], [maximum])), anchors)
                mean, _, upper = model.predict(a, name, extrapolate=True, **inputs)
                truth = np.interp(a, case.abscissa, case.forces[name])
                excess.append((truth - mean) ** 2 - (upper - mean) ** 2)
        window = np.ones(2 * SMOOTHING + 1)
        raw = np.maximum(np.mean(excess, axis=0), 0.0)
        residual = np.convolve(raw, window, "same") / np.convolve(np.ones_like(raw), window, "same")
        models = [(_with(model, **{f"residual_variance_{name}": residual}), left_out) for model, left_out in models]
        ratios = []
        for model, left_out in models:
            for case in left_out:
                inside = case.abscissa <= maximum
                mean, _, upper = model.predict(case.abscissa[inside], name, extrapolate=True,
                                               **dict(zip(model.inputs, case.inputs)))
                ratios.append(np.abs(case.forces[name][inside] - mean) / np.maximum(upper - mean, 1e-12))
        factor = np.array(float(np.quantile(np.concatenate(ratios), LEVEL)))
        arrays.update({f"residual_variance_{name}": residual, f"band_factor_{name}": factor})
        models = [(_with(model, **{f"band_factor_{name}": factor}), left_out) for model, left_out in models]
    if training.events:
        errors, variances = [], []
        for model, left_out in models:
            for case in left_out:
                x = model.input_vector(dict(zip(model.inputs, case.inputs)), extrapolate=True)
                mean, variance = model.outputs(x)
                errors.append([case.events[e] - mean[k] for k, e in enumerate(training.events)])
                variances.append(variance[: len(training.events)])
        errors, variances = np.array(errors), np.array(variances)                 # (n, L)
        residual = np.maximum(np.mean(errors**2 - variances, axis=0), 0.0)
        ratios = np.abs(errors) / np.maximum(np.sqrt(variances + residual), 1e-300)
        factors = np.maximum(np.quantile(ratios, LEVEL, axis=0), NOMINAL_FACTOR)
        arrays.update(event_band_factor=factors, event_residual_variance=residual)
        models = [(_with(model, event_band_factor=factors, event_residual_variance=residual), left_out)
                  for model, left_out in models]
    return scores(models, training)


def _with(model: Surrogate, **arrays) -> Surrogate:
    """A copy of ``model`` with some arrays replaced."""
    return Surrogate(model.metadata, {**model.arrays, **arrays})
