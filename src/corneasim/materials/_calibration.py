"""Reproducible derivation of the default ``cornea`` preset from the published law.

The needle paper's Mooney-Rivlin constants (C10 = 10.59 MPa, C01 = -11.20 MPa,
eq. 1) were fitted by its authors to uniaxial tests; their incompressible
uniaxial nominal stress P = 2 (lambda - lambda^-2)(C10 + C01 / lambda) is the
best available description of those data, but it is negative for stretch 1 to
-C01 / C10 = 1.058 (Drucker-unstable). The default preset refits a Yeoh law,
stable by construction, to that curve:

* samples: 41 stretches evenly spaced over 1.0-1.2 (strain 0-20 %, which covers
  the mean physiological strain of about 0.17 quoted in the needle paper, sec. 2.3);
* negative published stresses (stretch < 1.058) are replaced by 0, the nearest
  stress a stable material can have;
* constants are instantaneous (the Prony series of eq. 2 relaxes them), as in
  ABAQUS/Explicit, which the papers used.

See docs/materials.md for the numbers.
"""

from __future__ import annotations

import numpy as np

from corneasim.materials._fitting import FitResult, fit_hyperelastic
from corneasim.materials._homogeneous import nominal_stress

PUBLISHED_MOONEY_RIVLIN = (10.59, -11.20)
"""(C10, C01) of the needle paper, eq. 1, MPa."""

CALIBRATION_STRETCHES = np.linspace(1.0, 1.2, 41)
"""Stretches at which the published uniaxial curve is sampled (dimensionless)."""


def published_uniaxial_curve(stretch=CALIBRATION_STRETCHES) -> np.ndarray:
    """Incompressible uniaxial nominal stress (MPa) of the published Mooney-Rivlin law."""
    return nominal_stress("mooney-rivlin", [*PUBLISHED_MOONEY_RIVLIN, 1.0], "uniaxial", stretch)


def calibrate_cornea() -> FitResult:
    """Fit the stable Yeoh law of the ``cornea`` preset (constants in MPa).

    Returns
    -------
    FitResult
        Parameters [C10, C20, C30] in MPa, residuals against the published curve.
    """
    target = np.maximum(published_uniaxial_curve(CALIBRATION_STRETCHES), 0.0)
    return fit_hyperelastic("yeoh", (CALIBRATION_STRETCHES, target))
