"""A ring of hexahedra about the z axis, for the trephine's edge tests."""

import numpy as np

from corneasim.mesh import Mesh


def ring_mesh(radii, n_theta, layers, top=None):
    """Hexahedra between the ``radii`` (mm) over the full circle (``n_theta`` sectors) and the
    ``layers`` (z, mm, bottom first); ``top(r)`` shifts every layer by a height profile (mm).
    Node sets: ``bottom`` (the lowest layer), ``top`` (the highest)."""
    theta = np.linspace(0, 2 * np.pi, n_theta, endpoint=False)
    R, T, Z = np.meshgrid(radii, theta, layers, indexing="ij")
    if top is not None:
        Z = Z + top(R)
    index = np.arange(R.size).reshape(R.shape)
    cells = []
    for i in range(len(radii) - 1):
        for j in range(n_theta):
            k = (j + 1) % n_theta
            for m in range(len(layers) - 1):
                cells.append([index[i, j, m], index[i + 1, j, m], index[i + 1, k, m], index[i, k, m],
                              index[i, j, m + 1], index[i + 1, j, m + 1], index[i + 1, k, m + 1],
                              index[i, k, m + 1]])
    points = np.column_stack([(R * np.cos(T)).ravel(), (R * np.sin(T)).ravel(), Z.ravel()])
    return Mesh(points, np.array(cells, np.int64), "hexahedron", np.zeros(len(cells), np.int64), ["layer"],
                node_sets={"bottom": index[:, :, 0].ravel(), "top": index[:, :, -1].ravel()})
