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
        U, ils = a["train_inputs"], a["inverse_length_scales"]               # (N, D), (J, D)
        self._exponent = -0.5 * ils**2                                       # (J, D): the kernel's exponent
        self._inverse_span = 1.0 / self._span
        self._offset_U = self._low * self._inverse_span + U                  # u - U_n = x / span - this
        self._stacked = np.concatenate((a["weights"][:, None, :], a["covariance_weights"]), axis=1)  # (J, 1+N, N)
        self._v0, self._ybar, self._vmin = a["prior_variance"], a["output_mean"], a["noise_variance"]  # (J,)
        self._events = len(a["event_reference"])                             # L
        self._max = float(metadata["abscissa"]["max"])
        slack = RANGE_SLACK * np.maximum(np.abs(self._span), 1.0)
        self._lower, self._upper = (self._low - slack).tolist(), (self._high + slack).tolist()
        self._anchors = np.concatenate(([0.0], a["event_reference"], [self._max]))  # registered knots
        self._anchor_list = self._anchors.tolist()
        self._key = self._state = None  # the last input vector and its state (a controller repeats them)
        self._names = [item["name"] for item in metadata["inputs"]]
        self._aliases = {item["alias"]: k for k, item in enumerate(metadata["inputs"])}
        self._aliases.update({name: k for k, name in enumerate(self._names)})
        self._channels = {}
        self._first = metadata["channels"][0]["name"]
        start = self._events
        for channel in metadata["channels"]:
            name = channel["name"]
            phi = a[f"basis_{name}"]                                          # (K, G)
            zero = np.zeros_like(phi[:, 1:])
            rows = np.stack([np.concatenate(pair) for pair in (
                (phi[:, :-1], zero), (phi[:, 1:], zero), (zero, phi[:, :-1] ** 2), (zero, phi[:, 1:] ** 2),
                (zero, phi[:, :-1] * phi[:, 1:]))]).transpose(2, 0, 1)        # (G-1, 5, 2K)
            curve, residual = a[f"mean_curve_{name}"], a[f"residual_variance_{name}"]
            self._channels[name] = (rows, curve, residual, curve.tolist(), residual.tolist(),
                                    float(a[f"band_factor_{name}"]), slice(start, start + len(phi)))
            start += len(phi)

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
        return np.array(self._values(inputs, extrapolate))

    def _values(self, inputs: dict, extrapolate: bool) -> tuple:
        """:meth:`input_vector` as a tuple of floats (the key of the cached state)."""
        values = [math.nan] * len(self._names)
        aliases = self._aliases
        for key, value in inputs.items():
            k = aliases.get(key)
            if k is None:
                raise InputError(f"surrogate: unknown input {key!r}; expected {', '.join(self._names)}")
            values[k] = float(value)
        lower, upper = self._lower, self._upper
        for k, value in enumerate(values):
            if not lower[k] <= value <= upper[k] and not (extrapolate and math.isfinite(value)):
                item = self.metadata["inputs"][k]
                if not math.isfinite(value):
                    raise InputError(f"surrogate: input {item['name']} ({item['alias']}) missing or not a finite "
                                     f"number, {item['unit']}")
                raise InputError(f"surrogate: {item['name']} = {value:g} {item['unit']} is outside the training "
                                 f"range [{self._low[k]:g}, {self._high[k]:g}] (extrapolate=True to allow)")
        return tuple(values)

    def outputs(self, x) -> tuple[np.ndarray, np.ndarray]:
        """Posterior mean and variance of every output at the input vector ``x`` (model units)."""
        state = self._posterior(tuple(float(v) for v in x))
        return state["mean"], state["variance"]

    def _posterior(self, key: tuple) -> dict:
        """What does not depend on the abscissa, at the input vector ``key``, computed once per vector.

        ``mean``, ``variance``: every output's posterior (one batched product gives
        :math:`\\sum_n w_n k_n` and :math:`C k`); ``knots``: the predicted punctures made
        non-decreasing and clipped to :math:`[0, a_{max}]`, the registration's knots; per
        channel, its coefficients' means followed by their variances.
        """
        if key != self._key:
            z = np.array(key) * self._inverse_span - self._offset_U                # (N, D)
            k = np.exp(self._exponent @ (z * z).T)                                  # (J, N)
            y = np.matmul(self._stacked, k[:, :, None])[:, :, 0]                     # (J, 1+N)
            mean = self._ybar + y[:, 0]
            variance = np.maximum(self._v0 - np.einsum("jn,jn->j", k, y[:, 1:]), self._vmin)
            knots, low = [0.0], 0.0
            for event in mean[: self._events].tolist():
                low = min(max(event, low), self._max)
                knots.append(low)
            knots.append(self._max)
            self._state = {"mean": mean, "variance": variance, "knots": knots,
                           **{name: np.concatenate((mean[rows], variance[rows]))
                              for name, (*_, rows) in self._channels.items()}}
            self._key = key
        return self._state

    def predict(self, abscissa, channel: str | None = None, extrapolate: bool = False, **inputs):
        """Mean curve and band of one channel at ``abscissa`` (mm for the needle, s for the trephine).

        Between grid points :math:`i, i+1` of the registered abscissa, :math:`s = s_i + w\\,\\Delta s`,
        the mean is :math:`(1-w) F_i + w F_{i+1}`, :math:`F_i = \\mu_i + \\sum_k m_k \\phi_{ki}`,
        and the variance :math:`\\sum_k v_k \\phi_k(s)^2 = (1-w)^2 A_i + 2w(1-w) B_i + w^2 A_{i+1}`
        with :math:`A_i = \\sum_k v_k \\phi_{ki}^2`, :math:`B_i = \\sum_k v_k \\phi_{ki}\\phi_{k,i+1}`:
        one product of a stored (5, 2K) matrix of the interval with the coefficients' means and
        variances gives all five.

        Returns
        -------
        mean, lower, upper : ndarray or float
            In the channel's unit (N); the band is the calibrated 95% band.
        """
        state = self._posterior(self._values(inputs, extrapolate))
        try:
            rows, curve, residual, curve_list, residual_list, factor, _ = self._channels[channel or self._first]
        except KeyError:
            raise InputError(f"surrogate: unknown channel {channel!r}; expected {', '.join(self._channels)}") from None
        coefficients = state[channel or self._first]
        if isinstance(abscissa, (float, int)) or np.ndim(abscissa) == 0:
            a = float(abscissa)
            if not extrapolate and not 0.0 <= a <= self._max * (1 + RANGE_SLACK):
                self._refuse()
            i, w = self._grid(self._registered(a, state["knots"]), len(curve_list))
            f0, f1, A0, A1, B = (rows[i] @ coefficients).tolist()
            mean = curve_list[i] * (1.0 - w) + curve_list[i + 1] * w + f0 * (1.0 - w) + f1 * w
            var = ((1.0 - w) ** 2 * A0 + 2.0 * w * (1.0 - w) * B + w * w * A1
                   + residual_list[i] * (1.0 - w) + residual_list[i + 1] * w)
            half = factor * math.sqrt(max(var, 0.0))
            return mean, mean - half, mean + half
        a = np.asarray(abscissa, dtype=float)
        if not extrapolate and a.size and not (a.min() >= 0.0 and a.max() <= self._max * (1 + RANGE_SLACK)):
            self._refuse()
        i, w = self._grid(np.interp(a, state["knots"], self._anchors), curve.size)
        f0, f1, A0, A1, B = np.moveaxis(rows[i] @ coefficients, -1, 0)
        mean = curve[i] * (1.0 - w) + curve[i + 1] * w + f0 * (1.0 - w) + f1 * w
        var = ((1.0 - w) ** 2 * A0 + 2.0 * w * (1.0 - w) * B + w * w * A1
               + residual[i] * (1.0 - w) + residual[i + 1] * w)
        half = factor * np.sqrt(np.maximum(var, 0.0))
        return mean, mean - half, mean + half

    def _registered(self, a: float, knots: list) -> float:
        """The registered abscissa s(a): piecewise linear from ``knots`` onto the training mean punctures."""
        anchors = self._anchor_list
        for e in range(1, len(knots)):  # as in the C evaluator
            if a <= knots[e] or e == len(knots) - 1:
                low, high = knots[e - 1], knots[e]
                return anchors[e - 1] + (a - low) * (anchors[e] - anchors[e - 1]) / (high - low) if high > low \
                    else anchors[e - 1]
        return a

    def _grid(self, s, size: int):
        """Grid interval ``i`` and weight ``w`` of the registered abscissa ``s`` (float or array)."""
        if isinstance(s, float):
            g = min(max(s, 0.0), self._max) * ((size - 1) / self._max)
            i = min(int(g), size - 2)
        else:
            g = np.clip(s, 0.0, self._max) * ((size - 1) / self._max)
            i = np.minimum(g.astype(int), size - 2)
        return i, g - i

    def _refuse(self):
        name = self.metadata["abscissa"]
        raise InputError(f"surrogate: {name['name']} outside the trained range [0, {self._max:g}] "
                         f"{name['unit']} (extrapolate=True to allow)")

    def force(self, depth, extrapolate: bool = False, **inputs):
        """Needle force (N) at ``depth`` (mm): ``(mean, lower, upper)`` of the 95% band."""
        return self.predict(depth, None, extrapolate, **inputs)

    def punctures(self, extrapolate: bool = False, **inputs) -> dict:
        """Expected puncture abscissa of each event: ``{event: (mean, lower, upper)}`` (mm or s)."""
        state = self._posterior(self._values(inputs, extrapolate))
        mean, variance = state["mean"], state["variance"]
        L = self._events
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
