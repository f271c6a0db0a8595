"""Reference-configuration data of the one-point elements (computed once, NumPy).

Both elements use the Flanagan-Belytschko *mean* (uniform) gradient

.. math::

    b_a = \\frac{1}{V} \\int_{V_e} \\frac{\\partial N_a}{\\partial X}\\, dV ,

integrated exactly by 2x2 (quad) or 2x2x2 (hexahedron) Gauss points: the integrands are
at most cubic in each parent coordinate. For the axisymmetric quad dV = 2 pi r dA, and the
hoop stretch uses the mean of N_a / r,

.. math::

    F_{\\theta\\theta} = \\sum_a r_a h_a, \\qquad
    h_a = \\frac{1}{V}\\int_{V_e} \\frac{N_a}{r}\\, dV = \\frac{2\\pi}{V}\\int_{A_e} N_a\\, dA ,

so that no nodal radius is divided by (nodes on the axis are exact) and every homogeneous
deformation, including u_r = a r, is reproduced exactly on distorted meshes (patch test).
For rectangles h_a = 1/(4 r_c), the centre value u_r / r_c of CAX4R. Flanagan & Belytschko,
Int. J. Numer. Meth. Eng. 17 (1981) 679, doi:10.1002/nme.1620170504.
"""

from __future__ import annotations

import numpy as np

from corneasim.errors import InputError

QUAD_CORNERS = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)
HEX_CORNERS = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                        [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
QUAD_HOURGLASS = np.array([[1.0, -1.0, 1.0, -1.0]])  # (1, 4) the xi*eta pattern
HEX_HOURGLASS = np.stack([HEX_CORNERS[:, 0] * HEX_CORNERS[:, 1],
                          HEX_CORNERS[:, 1] * HEX_CORNERS[:, 2],
                          HEX_CORNERS[:, 2] * HEX_CORNERS[:, 0],
                          HEX_CORNERS[:, 0] * HEX_CORNERS[:, 1] * HEX_CORNERS[:, 2]])  # (4, 8)
GAUSS = 1.0 / np.sqrt(3.0)


def _shape(corners, points):
    """N (n_gp, n_nodes) and dN/dxi (n_gp, n_nodes, dim) of the multilinear element."""
    dim = corners.shape[1]
    factors = 1.0 + points[:, None, :] * corners[None, :, :]  # (n_gp, n_nodes, dim)
    N = np.prod(factors, axis=2) / 2.0**dim
    dN = np.empty(factors.shape)
    for k in range(dim):
        others = np.prod(np.delete(factors, k, axis=2), axis=2)
        dN[:, :, k] = corners[None, :, k] * others / 2.0**dim
    return N, dN


def _gauss_data(X, corners):
    """Shape functions, Jacobian determinants and physical gradients at the Gauss points.

    X (n_e, n_nodes, dim) reference coordinates. Returns N (n_gp, n_nodes),
    det (n_e, n_gp) and dNdX (n_e, n_gp, n_nodes, dim).
    """
    points = GAUSS * corners  # the 2^dim Gauss points sit at the scaled corners
    N, dN = _shape(corners, points)
    jac = np.einsum("eai,gaj->egij", X, dN)  # (n_e, n_gp, dim, dim) dX_i/dxi_j
    det = np.linalg.det(jac)
    if np.any(det <= 0.0):
        element = int(np.argwhere(det <= 0.0)[0, 0])
        raise InputError(f"element {element}: inverted or degenerate in the reference mesh "
                         "(Jacobian <= 0; expected counter-clockwise quads / VTK-ordered hexahedra)")
    dNdX = np.einsum("gaj,egji->egai", dN, np.linalg.inv(jac))
    return N, det, dNdX


def quad_reference(X):
    """Reference data of axisymmetric quads; X (n_e, 4, 2) (r, z) in mm.

    Returns a dict: volume (n_e,) full-ring mm^3; b (n_e, 4, 2) 1/mm; hoop (n_e, 4) 1/mm;
    mass_weights (n_e, 4) mm^3 (2 pi integral of N_a r dA, row-sum lumping);
    gamma (n_e, 1, 4) hourglass vectors; length (n_e,) area / longest diagonal, mm.
    """
    if np.any(X[:, :, 0] < 0.0):
        element = int(np.argwhere(X[:, :, 0] < 0.0)[0, 0])
        raise InputError(f"element {element}: axisymmetric node with r < 0 (expected r >= 0)")
    N, det, dNdX = _gauss_data(X, QUAD_CORNERS)
    r = np.einsum("ga,ea->eg", N, X[:, :, 0])  # (n_e, 4)
    weight = 2.0 * np.pi * r * det  # (n_e, n_gp) dV per unit parent area
    volume = weight.sum(axis=1)
    if np.any(volume <= 0.0):
        element = int(np.argwhere(volume <= 0.0)[0, 0])
        raise InputError(f"element {element}: zero ring volume (all nodes on the axis)")
    b = np.einsum("eg,egai->eai", weight, dNdX) / volume[:, None, None]
    hoop = 2.0 * np.pi * np.einsum("ga,eg->ea", N, det) / volume[:, None]
    mass_weights = np.einsum("ga,eg->ea", N, weight)
    area = det.sum(axis=1)
    diagonal = np.maximum(np.linalg.norm(X[:, 2] - X[:, 0], axis=1),
                          np.linalg.norm(X[:, 3] - X[:, 1], axis=1))
    return dict(volume=volume, b=b, hoop=hoop, mass_weights=mass_weights,
                gamma=_hourglass_vectors(X, b, QUAD_HOURGLASS), length=area / diagonal)


def hex_reference(X):
    """Reference data of hexahedra; X (n_e, 8, 3) in mm (VTK node order).

    Returns a dict: volume (n_e,) mm^3; b (n_e, 8, 3) 1/mm; mass_weights (n_e, 8) mm^3;
    gamma (n_e, 4, 8) hourglass vectors; length (n_e,) volume / largest face area, mm.
    """
    N, det, dNdX = _gauss_data(X, HEX_CORNERS)
    volume = det.sum(axis=1)
    b = np.einsum("eg,egai->eai", det, dNdX) / volume[:, None, None]
    mass_weights = np.einsum("ga,eg->ea", N, det)
    return dict(volume=volume, b=b, mass_weights=mass_weights,
                gamma=_hourglass_vectors(X, b, HEX_HOURGLASS),
                length=volume / hex_face_areas(X).max(axis=1))


HEX_FACES = np.array([[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4],
                      [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]])


def hex_face_areas(x):
    """Areas (n_e, 6) of the six faces, half the cross product of the face diagonals."""
    p = x[:, HEX_FACES]  # (n_e, 6, 4, 3)
    cross = np.cross(p[:, :, 2] - p[:, :, 0], p[:, :, 3] - p[:, :, 1])
    return 0.5 * np.linalg.norm(cross, axis=2)


def _hourglass_vectors(X, b, patterns):
    """Flanagan-Belytschko gamma_alpha = (h_alpha - sum_j (h_alpha . X_j) b_j) / n_nodes.

    Orthogonal to every linear field (gamma . X_j = 0), so homogeneous deformations and
    rigid motions excite no hourglass force. Returns (n_e, n_modes, n_nodes).
    """
    n_nodes = X.shape[1]
    hX = np.einsum("ma,eaj->emj", patterns, X)  # (n_e, n_modes, dim)
    return (patterns[None] - np.einsum("emj,eaj->ema", hX, b)) / n_nodes
