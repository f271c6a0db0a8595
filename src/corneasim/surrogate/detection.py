"""Causal detection of the layers' punctures in a force signal streamed one sample at a time.

The rule (docs/surrogate.md, "Puncture detection"), for samples :math:`F_i` at a fixed rate:

* the signal is smoothed by a causal moving average of :math:`m` samples, :math:`\\bar F_i`;
  its noise is :math:`\\sigma(F) = \\sqrt{\\sigma_0^2 + (\\rho_0 F)^2}/\\sqrt m` (absolute
  :math:`\\sigma_0` in N and relative :math:`\\rho_0` noise of the sensor);
* a **drop** is reported when :math:`\\bar F` falls below its running maximum :math:`P` (since
  the last drop) by more than :math:`\\delta = \\max(k\\,\\sigma(P),\\ \\rho P)`, or a single
  sample :math:`F_i` by more than :math:`\\max(k\\sqrt m\\,\\sigma(P),\\ 2\\rho P)` (the same
  number of its own standard deviations: a tear that recovers within a sample or two is
  averaged away by the mean); the running maximum restarts :math:`r` samples after a drop
  (one drop is one report);
* the **whole cornea** is punctured when, after contact (:math:`\\max \\bar F` above
  :math:`\\max(F_c, 2 k \\sigma(0))`), :math:`\\bar F` stays below :math:`\\epsilon \\max \\bar F` for :math:`h`
  samples: the tip has left the cornea and only the shaft's friction remains; the rule is
  armed once the depth reaches the lower end of the prior's band of the whole cornea, or,
  without that prior, once the stroma's puncture is detected (after the epithelium's the
  force also falls to a fraction of its peak);
* **layers**: without a prior the first drop is the epithelium's and the second the stroma's;
  with a prior (the surrogate's puncture bands, ``Surrogate.punctures``) a drop is the
  puncture of the first undetected layer whose band holds its depth, the band widened by
  ``margin`` on both sides and by the depth of ``latency`` samples above (a drop is seen a few
  samples after the puncture),
  and drops outside every band (tearing within a layer, contact chatter) are kept in
  :attr:`PunctureDetector.drops` without raising a puncture.

Every decision uses only the samples received so far; the cost per sample is constant.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

LAYERS = ("epithelium", "stroma")
EXIT = "cornea"


@dataclass(frozen=True)
class Detection:
    """A detected puncture (or drop): event, sample index, depth (mm) and smoothed force (N)."""

    event: str
    sample: int
    depth_mm: float
    force_N: float


class PunctureDetector:
    """Streaming puncture detector (rule in the module docstring).

    Parameters
    ----------
    noise_N : float
        Absolute noise of the sensor, RMS, N (:math:`\\sigma_0`).
    relative_noise : float
        Noise proportional to the load, RMS fraction (:math:`\\rho_0`; 0.004 for +-0.4% of load).
    window : int
        Samples of the causal moving average (:math:`m`).
    sigmas : float
        Drop threshold in smoothed-noise standard deviations (:math:`k`).
    relative_drop : float
        Least drop as a fraction of the running maximum (:math:`\\rho`).
    refractory : int
        Samples after a drop before the running maximum restarts (:math:`r`).
    contact_N : float
        Least peak force before the exit rule is armed, N (:math:`F_c`; at least twice the
        drop threshold of the noise alone).
    exit_fraction : float
        Fraction of the peak force below which the tip has left the cornea (:math:`\\epsilon`).
    hold : int
        Consecutive samples below it (:math:`h`).
    prior : dict, optional
        ``{event: (mean, lower, upper)}`` puncture depths, mm (``Surrogate.punctures``).
    margin : float
        Widening of each prior band on both sides, mm.
    latency : int
        Samples by which a detection may follow its puncture: the prior bands' upper ends are
        moved on by the depth travelled in that many samples.
    """

    def __init__(self, noise_N: float = 0.005, relative_noise: float = 0.004, window: int = 4,
                 sigmas: float = 8.0, relative_drop: float = 0.05, refractory: int = 4,
                 contact_N: float = 0.02, exit_fraction: float = 0.25, hold: int = 2,
                 prior: dict | None = None, margin: float = 0.0, latency: int = 10):
        self.noise_N, self.relative_noise, self.sigmas = noise_N, relative_noise, sigmas
        self.relative_drop, self.refractory, self.contact_N = relative_drop, refractory, contact_N
        self.exit_fraction, self.hold, self.margin, self.latency = exit_fraction, hold, margin, latency
        self._depth, self._step = None, 0.0
        self.prior = dict(prior or {})
        self._window = deque(maxlen=window)
        self._sum, self._sample = 0.0, -1
        self._peak, self._maximum, self._since_drop, self._below = -np.inf, -np.inf, refractory, 0
        self.punctures: list[Detection] = []
        self.drops: list[Detection] = []

    @property
    def finished(self) -> bool:
        """True once the whole cornea is punctured."""
        return any(p.event == EXIT for p in self.punctures)

    def detected(self, event: str) -> Detection | None:
        """The detection of ``event``, or None."""
        return next((p for p in self.punctures if p.event == event), None)

    def update(self, force_N: float, depth_mm: float) -> list[Detection]:
        """Take the next sample; return the punctures it reveals (usually none)."""
        self._sample += 1
        if self._depth is not None:
            self._step = depth_mm - self._depth
        self._depth = depth_mm
        if len(self._window) == self._window.maxlen:
            self._sum -= self._window[0]
        self._window.append(force_N)
        self._sum += force_N
        if len(self._window) < self._window.maxlen or self.finished:
            return []  # no decision before the average has its m samples (its noise is the rule's)
        smooth = self._sum / len(self._window)
        self._maximum = max(self._maximum, smooth)
        new = []
        self._since_drop += 1
        if self._since_drop == self.refractory:
            self._peak = smooth
        if self._since_drop >= self.refractory:
            self._peak = max(self._peak, smooth)
            threshold = max(self.sigmas * self._sigma(self._peak), self.relative_drop * self._peak)
            sudden = max(self.sigmas * self._sigma(self._peak) * np.sqrt(self._window.maxlen),
                         2.0 * self.relative_drop * self._peak)
            if self._peak - smooth > threshold or self._peak - force_N > sudden:
                self._since_drop = 0
                drop = Detection("drop", self._sample, depth_mm, smooth)
                self.drops.append(drop)
                event = self._layer(depth_mm)
                if event is not None:
                    new.append(Detection(event, self._sample, depth_mm, smooth))
        armed = self._maximum > max(self.contact_N, 2.0 * self.sigmas * self._sigma(0.0)) \
            and self._exit_reached(depth_mm)
        self._below = self._below + 1 if armed and smooth < self.exit_fraction * self._maximum else 0
        if self._below >= self.hold:
            new.append(Detection(EXIT, self._sample, depth_mm, smooth))
        self.punctures.extend(new)
        return new

    def _sigma(self, force: float) -> float:
        return np.sqrt(self.noise_N**2 + (self.relative_noise * force) ** 2) / np.sqrt(self._window.maxlen)

    def _exit_reached(self, depth: float) -> bool:
        """Whether the exit rule may fire at ``depth``: inside or past the prior's band of the whole
        cornea (widened by ``margin``), or without that prior, once the stroma's puncture is detected
        (the force falls to a fraction of its peak after the epithelium's puncture too)."""
        if EXIT in self.prior:
            return depth >= self.prior[EXIT][1] - self.margin
        return self.detected(LAYERS[-1]) is not None

    def _layer(self, depth: float) -> str | None:
        """The layer a drop at ``depth`` punctures, or None (see the module docstring)."""
        pending = [e for e in LAYERS if self.detected(e) is None]
        if not self.prior:
            return pending[0] if pending else None
        for event in pending:
            if event in self.prior:
                _, lower, upper = self.prior[event]
                if lower - self.margin <= depth <= upper + self.margin + self.latency * abs(self._step):
                    return event
        return None
