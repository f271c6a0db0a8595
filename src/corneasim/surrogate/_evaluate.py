"""Evaluate a saved force surrogate: numpy only, no finite-element code.

This module imports nothing from corneasim's solver, meshes or scenarios; it can be copied
next to a controller and used on its own (``load("model.npz").force(0.4, rate=5.0, ...)``).
A model file is a plain ``.npz`` of float arrays plus one JSON string ``metadata``
(docs/surrogate.md, "File format").

The model, for inputs :math:`x` scaled to :math:`u \\in [0, 1]^D` by the training ranges:

* every output :math:`j` (the puncture abscissae :math:`\\lambda_e`, then the principal-component
  coefficients :math:`c_k` of each channel's registered curve) is a Gaussian-process posterior
  with a squared-exponential kernel,

  .. math::

      k_{jn}(u) = \\exp\\Big(-\\tfrac12 \\sum_d \\big((u_d - U_{nd})\\,\\ell^{-1}_{jd}\\big)^2\\Big),
      \\quad m_j = \\bar y_j + \\sum_n w_{jn} k_{jn}, \\quad
      v_j = v^0_j - \\sum_{n,p} k_{jn} C_{jnp} k_{jp};

* the abscissa :math:`a` is registered, piecewise linearly, from the predicted puncture abscissae
  :math:`(0, \\lambda_1, \\dots, \\lambda_L, a_{max})` onto the training mean ones
  :math:`(0, \\bar\\lambda_1, \\dots, \\bar\\lambda_L, a_{max})`, giving :math:`s(a)`;
* the curve is :math:`F(a) = \\mu(s) + \\sum_k \\phi_k(s) m_k`, with variance
  :math:`\\sigma^2 = \\sum_k \\phi_k(s)^2 v_k + r(s)` (``r``: the cross-validated residual
  variance the components do not explain) and the band :math:`F \\pm q\\,\\sigma`, :math:`q`
  calibrated by cross-validation so that 95% of left-out samples fall inside.
"""

from __future__ import annotations

import json
import math

import numpy as np

try:
    from corneasim.errors import InputError
except ImportError:  # used on its own, without the corneasim package
    class InputError(ValueError):
        """Bad user input: the message is one line naming the culprit."""

FORMAT = "corneasim-surrogate"
FORMAT_VERSION = 1
ARRAYS = ("inputs_low", "inputs_high", "train_inputs", "inverse_length_scales", "weights",
          "covariance_weights", "prior_variance", "output_mean", "noise_variance", "event_reference",
          "event_band_factor", "event_residual_variance")
CHANNEL_ARRAYS = ("mean_curve", "basis", "residual_variance", "band_factor")
RANGE_SLACK = 1e-9
"""Relative tolerance on the training range (round-off of a value given at its bound)."""


class Surrogate:
    """A force surrogate: mean curves, calibrated bands and puncture abscissae of the inputs.

    Parameters
    ----------
    metadata : dict
        The self-description (inputs with units and ranges, abscissa, channels, events,
        scenario, corneasim version, training size, held-out scores).
    arrays : dict of ndarray
        The model's arrays (:data:`ARRAYS`, and :data:`CHANNEL_ARRAYS` suffixed ``_<channel>``).
    """

    def __init__(self, metadata: dict, arrays: dict):
        if metadata.get("format") != FORMAT:
            raise InputError(f"surrogate: expected format {FORMAT!r}, got {metadata.get('format')!r}")
        self.metadata = metadata
        self.arrays = {name: np.asarray(value, dtype=float) for name, value in arrays.items()}
        a = self.arrays
        self._low, self._high = a["inputs_low"], a["inputs_high"]
        self._span = self._high - self._low
        self._U, self._ils = a["train_inputs"], a["inverse_length_scales"]  # (N, D), (J, D)
        self._W, self._C = a["weights"], a["covariance_weights"]             # (J, N), (J, N, N)
        self._v0, self._ybar = a["prior_variance"], a["output_mean"]         # (J,), (J,)
        self._ref = a["event_reference"]                                     # (L,)
        self._max = float(metadata["abscissa"]["max"])
        self._exponent = -0.5 * self._ils**2                                 # (J, D): the kernel's exponent
        self._inverse_span = 1.0 / self._span
        self._offset_U = self._low * self._inverse_span + self._U            # u - U_n = x / span - this
        slack = RANGE_SLACK * np.maximum(np.abs(self._span), 1.0)
        self._lower, self._upper = (self._low - slack).tolist(), (self._high + slack).tolist()
        self._vmin = a["noise_variance"]                                     # (J,)
        self._anchors = np.concatenate(([0.0], self._ref, [self._max]))     # registered knots
        self._last = (None, None, None)  # the last input vector and its outputs (a controller repeats them)
        self._names = [item["name"] for item in metadata["inputs"]]
        self._aliases = {item["alias"]: k for k, item in enumerate(metadata["inputs"])}
        self._aliases.update({name: k for k, name in enumerate(self._names)})
        self._channels = {}
        self._first = metadata["channels"][0]["name"]
        start = len(self._ref)
        for channel in metadata["channels"]:
            name = channel["name"]
            basis = a[f"basis_{name}"]
            self._channels[name] = (a[f"mean_curve_{name}"], basis, a[f"residual_variance_{name}"],
                                    float(a[f"band_factor_{name}"]), slice(start, start + len(basis)))
            start += len(basis)

    @property
    def inputs(self) -> list[str]:
        """The input names (dotted scenario keys), in the model's order."""
        return list(self._names)

    @property
    def channels(self) -> list[str]:
        """The curve names (``force_N`` for the needle; ``fz_N``, ``fc_N`` for the trephine)."""
        return list(self._channels)

    @property
    def events(self) -> list[str]:
        """The puncture events the model predicts, in order."""
        return list(self.metadata["events"])

    def input_vector(self, inputs: dict, extrapolate: bool = False) -> np.ndarray:
        """The inputs as a vector in the model's order; refuses unknown, missing or out-of-range ones."""
        values = [math.nan] * len(self._names)
        for key, value in inputs.items():
            if key not in self._aliases:
                raise InputError(f"surrogate: unknown input {key!r}; expected {', '.join(self._names)}")
            values[self._aliases[key]] = float(value)
        for k, value in enumerate(values):
            if not self._lower[k] <= value <= self._upper[k] and not (extrapolate and math.isfinite(value)):
                item = self.metadata["inputs"][k]
                if not math.isfinite(value):
                    raise InputError(f"surrogate: input {item['name']} ({item['alias']}) missing or not a finite "
                                     f"number, {item['unit']}")
                raise InputError(f"surrogate: {item['name']} = {value:g} {item['unit']} is outside the training "
                                 f"range [{self._low[k]:g}, {self._high[k]:g}] (extrapolate=True to allow)")
        return np.array(values)

    def outputs(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Posterior mean and variance of every output at the input vector ``x`` (model units)."""
        key = x.tobytes()
        if key != self._last[0]:
            z = x * self._inverse_span - self._offset_U                        # (N, D)
            k = np.exp(self._exponent @ (z * z).T)                                  # (J, N)
            mean = self._ybar + np.einsum("jn,jn->j", k, self._W)
            variance = self._v0 - np.einsum("jn,jn->j", k, np.matmul(self._C, k[:, :, None])[:, :, 0])
            self._last = (key, mean, np.maximum(variance, self._vmin))
        return self._last[1], self._last[2]

    def _registered(self, abscissa, events):
        """The registered abscissa s(a) of the training mean punctures (piecewise linear)."""
        knots = self._anchors.copy()
        knots[1:-1] = np.clip(np.maximum.accumulate(events), 0.0, self._max)
        return np.interp(abscissa, knots, self._anchors)

    def predict(self, abscissa, channel: str | None = None, extrapolate: bool = False, **inputs):
        """Mean curve and band of one channel at ``abscissa`` (mm for the needle, s for the trephine).

        Returns
        -------
        mean, lower, upper : ndarray or float
            In the channel's unit (N); the band is the calibrated 95% band.
        """
        x = self.input_vector(inputs, extrapolate)
        a = np.asarray(abscissa, dtype=float)
        first, last = (float(a), float(a)) if a.ndim == 0 else (a.min(), a.max())
        if not extrapolate and not (first >= 0.0 and last <= self._max * (1 + RANGE_SLACK)):
            name = self.metadata["abscissa"]
            raise InputError(f"surrogate: {name['name']} outside the trained range [0, {self._max:g}] "
                             f"{name['unit']} (extrapolate=True to allow)")
        try:
            curve, basis, residual, factor, rows = self._channels[channel or self._first]
        except KeyError:
            raise InputError(f"surrogate: unknown channel {channel!r}; expected {', '.join(self._channels)}") from None
        mean, variance = self.outputs(x)
        if a.ndim == 0:
            return self._at(float(a), mean, variance, curve, basis, residual, factor, rows)
        s = self._registered(a, mean[: len(self._ref)])
        g = np.clip(s, 0.0, self._max) * ((curve.size - 1) / self._max)
        i = np.minimum(g.astype(int), curve.size - 2)
        w = g - i
        phi = basis[:, i] * (1.0 - w) + basis[:, i + 1] * w                    # (K, n)
        f = curve[i] * (1.0 - w) + curve[i + 1] * w + mean[rows] @ phi
        var = variance[rows] @ (phi * phi) + residual[i] * (1.0 - w) + residual[i + 1] * w
        half = factor * np.sqrt(var)
        return f, f - half, f + half

    def _at(self, a, mean, variance, curve, basis, residual, factor, rows):
        """:meth:`predict` at one abscissa, in floats: the same arithmetic with fewer array calls."""
        low = anchor = s = 0.0
        for e in range(len(self._ref) + 1):  # registration, as in the C evaluator
            high = min(max(float(mean[e]), low), self._max) if e < len(self._ref) else self._max
            target = float(self._ref[e]) if e < len(self._ref) else self._max
            if a <= high or e == len(self._ref):
                s = anchor + (a - low) * (target - anchor) / (high - low) if high > low else anchor
                break
            low, anchor = high, target
        g = min(max(s, 0.0), self._max) * ((curve.size - 1) / self._max)
        i = min(int(g), curve.size - 2)
        w = g - i
        phi = basis[:, i] * (1.0 - w) + basis[:, i + 1] * w                    # (K,)
        f = float(curve[i] * (1.0 - w) + curve[i + 1] * w + mean[rows] @ phi)
        half = factor * math.sqrt(float(variance[rows] @ (phi * phi) + residual[i] * (1.0 - w) + residual[i + 1] * w))
        return f, f - half, f + half

    def force(self, depth, extrapolate: bool = False, **inputs):
        """Needle force (N) at ``depth`` (mm): ``(mean, lower, upper)`` of the 95% band."""
        return self.predict(depth, None, extrapolate, **inputs)

    def punctures(self, extrapolate: bool = False, **inputs) -> dict:
        """Expected puncture abscissa of each event: ``{event: (mean, lower, upper)}`` (mm or s)."""
        mean, variance = self.outputs(self.input_vector(inputs, extrapolate))
        L = len(self._ref)
        half = self.arrays["event_band_factor"] * np.sqrt(variance[:L] + self.arrays["event_residual_variance"])
        return {event: (float(mean[e]), float(mean[e] - half[e]), float(mean[e] + half[e]))
                for e, event in enumerate(self.events)}

    def save(self, path) -> None:
        """Write the model as ``.npz`` (arrays and the JSON metadata)."""
        with open(path, "wb") as handle:
            np.savez(handle, metadata=np.array(json.dumps(self.metadata)), **self.arrays)


def load(path) -> Surrogate:
    """Read a model written by :meth:`Surrogate.save`; a missing or foreign file is an InputError."""
    try:
        with np.load(path, allow_pickle=False) as data:
            metadata = json.loads(str(data["metadata"]))
            arrays = {name: data[name] for name in data.files if name != "metadata"}
    except (OSError, KeyError, ValueError) as error:
        raise InputError(f"{path}: not a readable surrogate model ({error})") from None
    if metadata.get("format_version") != FORMAT_VERSION:
        raise InputError(f"{path}: surrogate format version {metadata.get('format_version')}, "
                         f"this evaluator reads {FORMAT_VERSION}")
    return Surrogate(metadata, arrays)
