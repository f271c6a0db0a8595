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

The ``cornea-in-vivo`` preset (:func:`calibrate_cornea_in_vivo`) refits the same
curve re-referenced at the physiological prestretch of the cornea in the eye, because
the models' stress-free reference is the eye as measured in vivo.

See docs/materials.md for the numbers.
"""

from __future__ import annotations

import numpy as np

from corneasim.materials._fitting import FitResult, fit_hyperelastic
from corneasim.materials._homogeneous import nominal_stress

PUBLISHED_MOONEY_RIVLIN = (10.59, -11.20)
"""(C10, C01) of the needle paper, eq. 1, MPa."""

PHYSIOLOGICAL_STRAIN = 0.17
"""Mean corneal strain in the normal physiological state (needle paper, sec. 2.3)."""

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


def in_vivo_uniaxial_curve(stretch=CALIBRATION_STRETCHES,
                           physiological_strain: float = PHYSIOLOGICAL_STRAIN) -> np.ndarray:
    """The published uniaxial curve seen from the prestretched in-vivo state, MPa.

    A strip at the in-vivo stretch lambda_0 = 1 + physiological_strain (relative to the
    excised, stress-free tissue of the tensile tests) stretched further by lambda reaches
    lambda_0 lambda; its force per in-vivo area (A_0 / lambda_0, incompressible) minus the
    prestress, which the models carry in their stress-free in-vivo reference, is

    .. math::

        P_{vivo}(\\lambda) = \\lambda_0 \\, [P(\\lambda_0 \\lambda) - P(\\lambda_0)],

    with P the published Mooney-Rivlin nominal stress (needle paper, eq. 1). Its slope at
    lambda = 1 is lambda_0^2 P'(lambda_0), the tangent modulus of the tissue in the eye.

    Parameters
    ----------
    stretch : array_like
        Stretch from the in-vivo state (dimensionless).
    physiological_strain : float
        lambda_0 - 1 (dimensionless); 0 gives the published curve itself.
    """
    stretch0 = 1.0 + physiological_strain
    total = stretch0 * np.asarray(stretch, dtype=float)
    return stretch0 * (published_uniaxial_curve(total) - published_uniaxial_curve(np.array([stretch0]))[0])


def calibrate_cornea_in_vivo(physiological_strain: float = PHYSIOLOGICAL_STRAIN) -> FitResult:
    """Fit the stable Yeoh law of the ``cornea-in-vivo`` preset (constants in MPa).

    The least-squares Yeoh fit of :func:`in_vivo_uniaxial_curve` at the 41 stretches
    1.0-1.2 from the in-vivo state (no clipping is needed: the curve is positive there
    for a physiological strain above 0.058).

    Parameters
    ----------
    physiological_strain : float
        lambda_0 - 1 (dimensionless), default the needle paper's 0.17.
    """
    target = in_vivo_uniaxial_curve(CALIBRATION_STRETCHES, physiological_strain)
    return fit_hyperelastic("yeoh", (CALIBRATION_STRETCHES, target))
