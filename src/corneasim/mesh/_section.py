"""The meridian section of the eye as a strip: (s, f) parameters to (r, z) points.

``s`` runs along the outer surface from the apex (s = 0): first the anterior cornea
(arc length on the anterior sphere, up to the limbus at s_L), then the outer sclera
(arc length on the globe, up to the posterior pole at s_P). ``f`` in [0, 1] is the
depth fraction along the through-thickness line at s: 0 on the outer surface, 1 on
the inner surface (posterior cornea, inner sclera).

Through-thickness lines in the cornea follow the anterior-surface normal (``normal``,
the umbrella strategy and the axisymmetric mesh) or the optical axis (``vertical``,
blended back to the normal near the limbus so every strategy meshes the same solid). A
``vertical`` section with ``normal_within`` follows the normal near the apex and turns to
the axis on the way out: the umbrella mesh split on the trephine's cylinder, whose lines
must be vertical where the cut runs (``mesh_3d(cut_radius=...)``).
In the sclera they join the outer and inner spheres at matching fractions of their
polar-angle spans from the limbus to the pole.
"""

from __future__ import annotations

import math

import numpy as np

from corneasim.errors import InputError
from corneasim.mesh._geometry import EyeShape


def _smoothstep(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


class Section:
    """Map strip parameters (s, f) to (r, z) points of the eye section.

    Parameters
    ----------
    shape : EyeShape
        Derived eye geometry.
    direction : {"normal", "vertical"}
        Through-thickness lines in the cornea.
    vertical_radius : float
        For ``vertical``: lines are parallel to the axis up to this anterior radius (mm),
        then turn smoothly to the normal, which they reach at the limbus; the turn starts
        earlier (at 2 r_P - r_L, r_P the posterior limbus radius) when the limbus is close.
    sclera_blend : float
        Arc length (mm) over which the sclera's layers go from the corneal layering
        (thin epithelium layers) to uniform thickness fractions.
    normal_within : (float, float), optional
        For ``vertical``: anterior radii (mm) r_0 < r_1; the lines follow the normal up to r_0
        and turn smoothly to the axis, which they follow from r_1 (r_1 <= the turn's start).
        Turning towards the axis on the way out spreads the lines' posterior ends apart, so
        they cannot cross.
    """

    def __init__(self, shape: EyeShape, direction: str = "normal", vertical_radius: float = 4.2,
                 sclera_blend: float = 3.0, normal_within: tuple[float, float] | None = None):
        self.shape = shape
        self.direction = direction
        self.vertical_radius = vertical_radius
        self.sclera_blend = sclera_blend
        g = shape.geometry
        self.s_limbus = shape.cornea_arc
        self.s_pole = shape.cornea_arc + shape.sclera_arc
        # the turn must leave the posterior ends of the lines at least half the anterior spacing
        turn_start = min(vertical_radius, 2.0 * shape.posterior_limbus[0] - g.limbus_radius)
        self.s_vertical = g.anterior_radius * math.asin(max(turn_start, 0.0) / g.anterior_radius)
        self.s_normal = None
        if normal_within is not None:
            self.s_normal = (self.s_of_radius(normal_within[0]), self.s_of_radius(normal_within[1]))
            if not 0.0 <= self.s_normal[0] < self.s_normal[1] <= self.s_vertical:
                raise InputError(f"mesh: the lines' turn to the axis ({normal_within[0]:g} to "
                                 f"{normal_within[1]:g} mm) must end before their turn back at "
                                 f"r = {turn_start:.3g} mm")

    def s_of_radius(self, radius: float) -> float:
        """Parameter s of the anterior-surface point at plan radius ``radius`` (mm)."""
        R_a = self.shape.geometry.anterior_radius
        return R_a * math.asin(radius / R_a)

    def cornea_frames(self, s: np.ndarray):
        """Anterior points, inward unit directions, depth of the epithelium and of the posterior."""
        g = self.shape.geometry
        theta = np.asarray(s, dtype=float) / g.anterior_radius
        normal = np.stack([np.sin(theta), np.cos(theta)], axis=-1)  # (n, 2) outward
        anterior = np.array([0.0, -g.anterior_radius]) + g.anterior_radius * normal  # (n, 2)
        inward = -normal
        if self.direction == "vertical":
            span = max(self.s_limbus - self.s_vertical, 1e-12)
            weight = _smoothstep((s - self.s_vertical) / span)
            if self.s_normal is not None:
                s_0, s_1 = self.s_normal
                weight = np.maximum(weight, 1.0 - _smoothstep((s - s_0) / (s_1 - s_0)))
            weight = weight[:, None]
            inward = (1.0 - weight) * np.array([0.0, -1.0]) + weight * inward
            inward /= np.linalg.norm(inward, axis=1, keepdims=True)
        depth_epithelium = self.shape.ray_to_epithelium(anterior, inward)
        depth_posterior = self.shape.ray_to_posterior(anterior, inward)
        return anterior, inward, depth_epithelium, depth_posterior

    def sclera_frames(self, s: np.ndarray):
        """Outer and inner scleral points at parameter s (beyond the limbus)."""
        sh = self.shape
        u = np.clip((np.asarray(s, dtype=float) - self.s_limbus) / sh.sclera_arc, 0.0, 1.0)
        phi = sh.phi_limbus + u * (math.pi - sh.phi_limbus)
        psi = sh.psi_limbus + u * (math.pi - sh.psi_limbus)
        outer = np.stack([sh.globe_radius * np.sin(phi), sh.globe_centre + sh.globe_radius * np.cos(phi)], -1)
        inner = np.stack([sh.inner_radius * np.sin(psi), sh.inner_centre + sh.inner_radius * np.cos(psi)], -1)
        outer[u >= 1.0, 0] = 0.0
        inner[u >= 1.0, 0] = 0.0
        return outer, inner

    def epithelium_fraction(self, s: float, epithelium_weights, stroma_weights) -> float:
        """Depth fraction of the epithelium-stroma interface (its mesh continuation in the sclera)."""
        g = self.shape.geometry
        if s <= self.s_limbus:
            _, _, d_e, d_p = self.cornea_frames(np.array([s]))
            return float(d_e[0] / d_p[0])
        at_limbus = g.epithelium_thickness / g.peripheral_thickness
        uniform = sum(epithelium_weights) / (sum(epithelium_weights) + sum(stroma_weights))
        w = float(_smoothstep(np.array((s - self.s_limbus) / self.sclera_blend)))
        return (1.0 - w) * at_limbus + w * uniform

    def station_fractions(self, s: float, epithelium_weights, stroma_weights) -> np.ndarray:
        """Depth fractions of the layer nodes at station s, shape (n_layers + 1,).

        Each part (epithelium, stroma) is divided in proportion to its layers' weights;
        beyond the limbus the interface moves to the weight fraction over ``sclera_blend``.
        """
        f_e = self.epithelium_fraction(s, epithelium_weights, stroma_weights)
        cumulative_e = np.cumsum((0,) + tuple(epithelium_weights)) / sum(epithelium_weights)
        cumulative_s = np.cumsum((0,) + tuple(stroma_weights)) / sum(stroma_weights)
        return np.concatenate([f_e * cumulative_e[:-1], f_e + (1.0 - f_e) * cumulative_s])

    def points(self, s: np.ndarray, f: np.ndarray) -> np.ndarray:
        """(r, z) of strip parameters (s, f), same shape as s, result shape (n, 2)."""
        s = np.asarray(s, dtype=float).ravel()
        f = np.asarray(f, dtype=float).ravel()
        out = np.empty((s.size, 2))
        cornea = s <= self.s_limbus
        if cornea.any():
            anterior, inward, _, d_p = self.cornea_frames(s[cornea])
            out[cornea] = anterior + (f[cornea] * d_p)[:, None] * inward
        sclera = ~cornea
        if sclera.any():
            outer, inner = self.sclera_frames(s[sclera])
            out[sclera] = outer + f[sclera][:, None] * (inner - outer)
        out[s == 0.0, 0] = 0.0
        return out
