"""Lamellar frames of the parametric cornea: the planes the stroma's collagen fibres lie in.

The stromal lamellae run parallel to the corneal surface (Meek & Knupp 2015,
doi:10.1016/j.preteyeres.2015.07.001). The frame of an element is taken from the cornea's
*mid-surface*, the locus of the midpoints between the anterior surface (sphere of radius
R_a centred at (0, -R_a), ``_geometry``) and the posterior conic, measured along the
anterior normal. Every anterior normal passes through the anterior centre, so a point
(r, z) of the cornea lies on the normal of polar angle theta = atan2(r, z + R_a), and its
lamella is the mid-surface's at that theta:

.. math::

    M(\\theta) = A(\\theta) - \\tfrac12 t(\\theta)\\, \\nu(\\theta), \\qquad
    m = \\frac{dM/d\\theta}{|dM/d\\theta|},

A(theta) the anterior point, nu its outward unit normal and t(theta) the thickness along
it. The frame is two orthogonal unit vectors of the lamellar plane: the meridional
tangent m (in the r-z section, pointing away from the axis) and the circumferential
(hoop) direction n. The two fibre families of a fibre material lie at +-angle from m
(``materials._fibre_law``), balanced, so an axisymmetric cornea does not twist.

In 3D (x, y, z with z the optical axis) m = m_r e_r + m_z e_z and n = e_phi at the
azimuth phi = atan2(y, x) (phi = 0 on the axis). The real central cornea's preferred
directions (nasal-temporal and superior-inferior, Aghamohammadzadeh et al. 2004,
doi:10.1016/j.str.2004.01.007) are not axisymmetric; this frame is the axisymmetric idealisation
both scenarios share.
"""

from __future__ import annotations

import numpy as np

from corneasim.mesh._geometry import EyeGeometry, EyeShape
from corneasim.mesh._mesh import Mesh

_STEP = 1e-6
"""Polar-angle step of the central difference dM/dtheta, rad."""


def _mid_surface(shape: EyeShape, theta: np.ndarray) -> np.ndarray:
    """Mid-surface points M(theta), (n, 2) mm in (r, z)."""
    R_a = shape.geometry.anterior_radius
    normal = np.stack([np.sin(theta), np.cos(theta)], axis=1)
    anterior = np.stack([R_a * normal[:, 0], -R_a + R_a * normal[:, 1]], axis=1)
    thickness = shape.ray_to_posterior(anterior, -normal)
    return anterior - 0.5 * thickness[:, None] * normal


def meridional_tangents(geometry: EyeGeometry, r, z) -> np.ndarray:
    """Unit meridional tangents (m_r, m_z) of the lamellae through the points (r, z) mm, (n, 2).

    Points beyond the limbus take the tangent at the limbus.
    """
    shape = EyeShape.from_geometry(geometry)
    R_a = geometry.anterior_radius
    theta = np.arctan2(np.asarray(r, dtype=float), np.asarray(z, dtype=float) + R_a)
    theta = np.clip(theta, _STEP, shape.theta_limbus - _STEP)
    tangent = (_mid_surface(shape, theta + _STEP) - _mid_surface(shape, theta - _STEP)) / (2 * _STEP)
    return tangent / np.linalg.norm(tangent, axis=1)[:, None]


def lamellar_frames(mesh: Mesh, geometry: EyeGeometry, elements=None) -> np.ndarray:
    """Fibre frame (m, n) of the elements of ``mesh``, (n_elements, 6), from the eye's shape.

    Parameters
    ----------
    mesh : Mesh
        Axisymmetric (r, z) quads or 3D hexahedra of the parametric eye (z the optical axis,
        the anterior apex at the origin).
    geometry : EyeGeometry
        The eye the mesh is of (mm).
    elements : ndarray (n_elements,) bool, optional
        The elements to give a frame (default all); the others get zero rows.

    Returns
    -------
    ndarray (n_elements, 6)
        (m_1, m_2, m_3, n_1, n_2, n_3) per element at its centre: for quads
        m = (m_r, m_z, 0), n = (0, 0, 1); in 3D the meridional and circumferential unit
        tangents (module doc).
    """
    frame = np.zeros((mesh.n_elements, 6))
    chosen = np.arange(mesh.n_elements) if elements is None else np.flatnonzero(elements)
    if chosen.size == 0:
        return frame
    centres = mesh.points[mesh.cells[chosen]].mean(axis=1)
    if mesh.axisymmetric:
        tangent = meridional_tangents(geometry, centres[:, 0], centres[:, 1])
        frame[chosen, 0], frame[chosen, 1] = tangent[:, 0], tangent[:, 1]
        frame[chosen, 5] = 1.0
        return frame
    r = np.hypot(centres[:, 0], centres[:, 1])
    phi = np.arctan2(centres[:, 1], centres[:, 0])
    tangent = meridional_tangents(geometry, r, centres[:, 2])
    c, s = np.cos(phi), np.sin(phi)
    frame[chosen, 0], frame[chosen, 1], frame[chosen, 2] = tangent[:, 0] * c, tangent[:, 0] * s, tangent[:, 1]
    frame[chosen, 3], frame[chosen, 4] = -s, c
    return frame
