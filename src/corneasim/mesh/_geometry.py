"""The parametric eye: a two-layer cornea on a scleral shell, in the (r, z) half-plane.

Coordinates (see :mod:`corneasim.mesh._mesh`): r >= 0 is the distance from the optical
axis, z the optical axis with the anterior corneal apex at the origin and the eye
below it (z <= 0). All lengths are in mm.

Shape (documented in ``docs/geometry.md``):

* **Anterior cornea**: sphere of radius ``anterior_radius`` centred at (0, -R_a).
* **Posterior cornea**: conic of revolution with apical radius ``posterior_radius``
  through (0, -``central_thickness``); its conic constant Q is solved so that the
  thickness at the limbus, measured along the anterior-surface normal (as pachymetry
  does), equals ``peripheral_thickness``. Two spheres with the paper's radii cannot give
  both 0.55 mm at the apex and 1.0 mm at an 11.1 mm limbus (they give 0.69 mm).
* **Epithelium**: layer of uniform thickness ``epithelium_thickness`` under the
  anterior surface (bounded by the concentric sphere R_a - t_e); the rest is stroma.
* **Limbus**: the cornea ends at the radius ``limbus_radius`` (the mean of the horizontal
  and vertical diameters, halved); the cornea-sclera junction is the anterior normal
  there, from the anterior limbus point A to the posterior limbus point P.
* **Sclera**: the outer surface is the sphere through A and the posterior pole at
  z = -``axial_length``; the inner surface is the sphere through P and the inner pole at
  z = -``axial_length`` + ``sclera_thickness``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pydantic

from corneasim.errors import InputError
from corneasim.schema import StrictModel


class EyeGeometry(StrictModel):
    """Dimensions of the eye (mm); defaults: porcine eye of the needle paper, Table 1.

    Attributes
    ----------
    anterior_radius : float
        Radius of curvature of the anterior corneal surface, mm (7.8).
    posterior_radius : float
        Apical radius of curvature of the posterior corneal surface, mm (6.8).
    central_thickness : float
        Corneal thickness on the optical axis, mm (0.55).
    peripheral_thickness : float
        Corneal thickness at the limbus along the anterior normal, mm (1.0).
    epithelium_thickness : float
        Epithelium thickness, mm (0.067); the stroma is the rest (0.483 mm at the apex).
    horizontal_diameter, vertical_diameter : float
        Corneal diameters, mm (11.2, 11.0); the axisymmetric eye uses their mean.
    axial_length : float
        Distance from the anterior apex to the outer posterior pole, mm (26.5).
    sclera_thickness : float
        Scleral thickness at the posterior pole, mm (1.0); at the limbus the sclera
        takes the peripheral corneal thickness.
    """

    anterior_radius: float = pydantic.Field(7.8, gt=0)
    posterior_radius: float = pydantic.Field(6.8, gt=0)
    central_thickness: float = pydantic.Field(0.55, gt=0)
    peripheral_thickness: float = pydantic.Field(1.0, gt=0)
    epithelium_thickness: float = pydantic.Field(0.067, gt=0)
    horizontal_diameter: float = pydantic.Field(11.2, gt=0)
    vertical_diameter: float = pydantic.Field(11.0, gt=0)
    axial_length: float = pydantic.Field(26.5, gt=0)
    sclera_thickness: float = pydantic.Field(1.0, gt=0)

    @property
    def limbus_radius(self) -> float:
        """Radius of the limbus (mm): half the mean corneal diameter."""
        return 0.25 * (self.horizontal_diameter + self.vertical_diameter)

    def shape(self) -> "EyeShape":
        """Derived surfaces and points; raises :class:`InputError` for impossible dimensions."""
        return EyeShape.from_geometry(self)


@dataclass(frozen=True)
class EyeShape:
    """Derived quantities of an :class:`EyeGeometry` (mm, rad).

    Attributes
    ----------
    geometry : EyeGeometry
    theta_limbus : float
        Polar angle of the anterior limbus point about the anterior centre (0, -R_a).
    conic_constant : float
        Q of the posterior surface r^2 = 2 R_p sigma - (1 + Q) sigma^2, sigma = -t_c - z.
    anterior_limbus, posterior_limbus : tuple of float
        (r, z) of A and P.
    globe_centre, globe_radius : float
        z of the centre and radius of the outer scleral sphere.
    inner_centre, inner_radius : float
        z of the centre and radius of the inner scleral sphere.
    phi_limbus, psi_limbus : float
        Polar angles of A about the globe centre and of P about the inner centre.
    """

    geometry: EyeGeometry
    theta_limbus: float
    conic_constant: float
    anterior_limbus: tuple[float, float]
    posterior_limbus: tuple[float, float]
    globe_centre: float
    globe_radius: float
    inner_centre: float
    inner_radius: float
    phi_limbus: float
    psi_limbus: float

    @classmethod
    def from_geometry(cls, g: EyeGeometry) -> "EyeShape":
        R_a, R_p, t_c, t_p, t_e = (
            g.anterior_radius, g.posterior_radius, g.central_thickness,
            g.peripheral_thickness, g.epithelium_thickness,
        )
        r_L = g.limbus_radius
        if t_e >= t_c:
            raise InputError(f"epithelium_thickness {t_e} mm must be smaller than central_thickness {t_c} mm")
        if r_L >= R_a:
            raise InputError(f"limbus radius {r_L} mm must be smaller than anterior_radius {R_a} mm")
        theta = math.asin(r_L / R_a)
        A = (r_L, -R_a + R_a * math.cos(theta))
        P = (A[0] - t_p * math.sin(theta), A[1] - t_p * math.cos(theta))
        sigma_P = -t_c - P[1]
        if P[0] <= 0 or sigma_P <= 0:
            raise InputError(
                f"peripheral_thickness {t_p} mm does not fit: the posterior limbus point falls "
                f"above the posterior apex or across the axis"
            )
        one_plus_Q = (2 * R_p * sigma_P - P[0] ** 2) / sigma_P**2
        if one_plus_Q <= 0 or R_p - one_plus_Q * sigma_P <= 0:
            raise InputError(
                f"posterior_radius {R_p} mm, central_thickness {t_c} mm and peripheral_thickness "
                f"{t_p} mm give no posterior surface that is a graph over r up to the limbus"
            )
        L = g.axial_length
        if L + A[1] <= r_L:
            raise InputError(f"axial_length {L} mm is too short for a globe behind a {2 * r_L} mm cornea")
        z_g = (A[0] ** 2 + A[1] ** 2 - L**2) / (2 * (A[1] + L))
        L_i = L - g.sclera_thickness
        if L_i + P[1] <= 0:
            raise InputError(f"sclera_thickness {g.sclera_thickness} mm is too large for the globe")
        z_i = (P[0] ** 2 + P[1] ** 2 - L_i**2) / (2 * (P[1] + L_i))
        return cls(
            geometry=g,
            theta_limbus=theta,
            conic_constant=one_plus_Q - 1.0,
            anterior_limbus=A,
            posterior_limbus=P,
            globe_centre=z_g,
            globe_radius=z_g + L,
            inner_centre=z_i,
            inner_radius=z_i + L_i,
            phi_limbus=math.atan2(A[0], A[1] - z_g),
            psi_limbus=math.atan2(P[0], P[1] - z_i),
        )

    @property
    def cornea_arc(self) -> float:
        """Arc length of the anterior surface from the apex to the limbus (mm)."""
        return self.geometry.anterior_radius * self.theta_limbus

    @property
    def sclera_arc(self) -> float:
        """Arc length of the outer scleral surface from the limbus to the posterior pole (mm)."""
        return self.globe_radius * (math.pi - self.phi_limbus)

    def posterior_z(self, r: np.ndarray) -> np.ndarray:
        """z of the posterior corneal surface at radius ``r`` (mm), for r <= r_P."""
        g = self.geometry
        k = 1.0 + self.conic_constant
        r = np.asarray(r, dtype=float)
        sigma = r**2 / (g.posterior_radius * (1.0 + np.sqrt(1.0 - k * r**2 / g.posterior_radius**2)))
        return -g.central_thickness - sigma

    def ray_to_posterior(self, start: np.ndarray, direction: np.ndarray) -> np.ndarray:
        """Distance along unit rays (from anterior points, pointing inward) to the posterior surface.

        Solves the quadratic of the conic r^2 - 2 R_p sigma + (1 + Q) sigma^2 = 0 along
        ``start + lambda * direction``; returns the smallest positive root, shape (n,).
        """
        g = self.geometry
        k = 1.0 + self.conic_constant
        r0, z0 = start[:, 0], start[:, 1]
        dr, dz = direction[:, 0], direction[:, 1]
        sigma0 = -g.central_thickness - z0
        a = dr**2 + k * dz**2
        b = 2 * r0 * dr + 2 * g.posterior_radius * dz - 2 * k * sigma0 * dz
        c = r0**2 - 2 * g.posterior_radius * sigma0 + k * sigma0**2
        root = np.sqrt(np.maximum(b**2 - 4 * a * c, 0.0))
        q = -0.5 * (b + np.copysign(root, b))
        roots = np.stack([q / a, np.divide(c, q, out=np.full_like(q, np.inf), where=q != 0)])
        roots[roots <= 0] = np.inf
        return roots.min(axis=0)

    def ray_to_epithelium(self, start: np.ndarray, direction: np.ndarray) -> np.ndarray:
        """Distance along inward unit rays from anterior points to the epithelium-stroma sphere."""
        g = self.geometry
        centre = np.array([0.0, -g.anterior_radius])
        p = np.einsum("ij,ij->i", start - centre, direction)
        k = g.anterior_radius**2 - (g.anterior_radius - g.epithelium_thickness) ** 2
        return -p - np.sqrt(p**2 - k)
