"""Meshes and closed forms shared by the element tests (independent of the kernels)."""

from __future__ import annotations

import numpy as np

from corneasim.materials import KernelMaterial, kernel_table

RHO = 1.062e-9


def grid_quad(nr, nz, r0=0.0, width=2.0, height=2.0, jitter=0.0, seed=0):
    """(nr+1)x(nz+1) nodes, counter-clockwise quads; interior nodes moved by ``jitter``."""
    r, z = np.meshgrid(np.linspace(r0, r0 + width, nr + 1), np.linspace(0, height, nz + 1), indexing="ij")
    points = np.stack([r.ravel(), z.ravel()], axis=1)
    rng = np.random.default_rng(seed)
    interior = ((points[:, 0] > r0) & (points[:, 0] < r0 + width)
                & (points[:, 1] > 0) & (points[:, 1] < height))
    h = width / nr
    points[interior] += jitter * h * rng.uniform(-1, 1, (interior.sum(), 2))
    node = lambda i, j: i * (nz + 1) + j  # noqa: E731
    cells = [[node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)]
             for i in range(nr) for j in range(nz)]
    return points, np.array(cells)


def grid_hex(n, size=2.0, jitter=0.0, seed=0):
    """(n+1)^3 nodes of a cube of edge ``size``; VTK-ordered hexahedra; interior jittered."""
    g = np.linspace(0, size, n + 1)
    x, y, z = np.meshgrid(g, g, g, indexing="ij")
    points = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    interior = np.all((points > 0) & (points < size), axis=1)
    rng = np.random.default_rng(seed)
    points[interior] += jitter * size / n * rng.uniform(-1, 1, (interior.sum(), 3))
    node = lambda i, j, k: (i * (n + 1) + j) * (n + 1) + k  # noqa: E731
    cells = []
    for i in range(n):
        for j in range(n):
            for k in range(n):
                cells.append([node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k),
                              node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1),
                              node(i, j + 1, k + 1)])
    return points, np.array(cells)


def materials(**kwargs):
    """A Yeoh/Mooney-Rivlin member of the family (MPa), with optional overrides."""
    base = dict(density=RHO, c10=0.05, c01=0.02, c20=0.3, c30=0.1, d1=0.2)
    base.update(kwargs)
    return kernel_table([KernelMaterial(**base)])


def cauchy_closed_form(F, row, relax=1.0):
    """Cauchy stress of the family (3x3), relax multiplies the isochoric part.

    sigma = (2/J) dev[(W1 + I1b W2) bbar - W2 bbar^2] + K (J - 1) I (Holzapfel 2000, 6.4).
    """
    from corneasim.materials._kernel_form import P_C01, P_C10, P_C20, P_C30, P_D1
    J = np.linalg.det(F)
    bbar = J ** (-2 / 3) * F @ F.T
    I1b = np.trace(bbar)
    W1 = row[P_C10] + 2 * row[P_C20] * (I1b - 3) + 3 * row[P_C30] * (I1b - 3) ** 2
    W2 = row[P_C01]
    A = (W1 + I1b * W2) * bbar - W2 * bbar @ bbar
    dev = A - np.trace(A) / 3 * np.eye(3)
    return relax * 2 / J * dev + 2 / row[P_D1] * (J - 1) * np.eye(3)


def fibre_cauchy_closed_form(F, k1, k2, kappa, angle):
    """Cauchy stress (3x3) of two fibre families in the e1-e2 plane at +-angle (rad) from e1.

    sigma_f = (2/J) Psi'(E) dev h_bar, h_bar = kappa b_bar + (1 - 3 kappa) a_bar (x) a_bar,
    a_bar = J^-1/3 F a_0, Psi'(E) = k1 E exp(k2 E^2) while E > 0 (Gasser, Ogden & Holzapfel
    2006, doi:10.1098/rsif.2005.0073, eqs. 2.5-2.11), written in the spatial form the
    library does not use.
    """
    J = np.linalg.det(F)
    Fbar = J ** (-1 / 3) * F
    bbar = Fbar @ Fbar.T
    sigma = np.zeros((3, 3))
    for sign in (1.0, -1.0):
        a = Fbar @ np.array([np.cos(angle), sign * np.sin(angle), 0.0])
        E = kappa * (np.trace(bbar) - 3) + (1 - 3 * kappa) * (a @ a - 1)
        if E > 0:
            h = kappa * bbar + (1 - 3 * kappa) * np.outer(a, a)
            sigma += 2 / J * k1 * E * np.exp(k2 * E * E) * (h - np.trace(h) / 3 * np.eye(3))
    return sigma


def voigt(s):
    """3x3 -> (11, 22, 33, 12, 23, 31)."""
    return np.array([s[0, 0], s[1, 1], s[2, 2], s[0, 1], s[1, 2], s[2, 0]])
