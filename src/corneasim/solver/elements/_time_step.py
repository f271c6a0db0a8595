"""Element stable time steps from the current geometry (one parallel kernel, no temporaries).

dt_e = (L_e / c_e)(sqrt(1 + b1^2) - b1), L_e = area / longest diagonal (quad) or volume /
largest face area (hexahedron), c_e = sqrt((K max(J, 1) + 4/3 mu_t) / rho) with the
instantaneous moduli (``docs/elements.md``).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from corneasim.materials._kernel_form import P_C01, P_C10, P_C20, P_C30, P_D1, P_DENSITY
from corneasim.solver.elements._constitutive import cube_root, tangent_shear_modulus

# hexahedron faces (VTK node order), each as a cycle of four nodes
FACES = ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))


@njit(cache=True)
def _hex_largest_face_area(x, cells, e):
    """Largest of the six face areas, each half the cross product of its diagonals."""
    largest = 0.0
    for f in range(6):
        a, b, c, d = FACES[f]
        n0, n1, n2, n3 = cells[e, a], cells[e, b], cells[e, c], cells[e, d]
        p0 = x[n2, 0] - x[n0, 0]
        p1 = x[n2, 1] - x[n0, 1]
        p2 = x[n2, 2] - x[n0, 2]
        q0 = x[n3, 0] - x[n1, 0]
        q1 = x[n3, 1] - x[n1, 1]
        q2 = x[n3, 2] - x[n1, 2]
        c0 = p1 * q2 - p2 * q1
        c1 = p2 * q0 - p0 * q2
        c2 = p0 * q1 - p1 * q0
        largest = max(largest, 0.5 * np.sqrt(c0 * c0 + c1 * c1 + c2 * c2))
    return largest


@njit(cache=True, parallel=True)
def stable_time_steps_kernel(points, cells, b, hoop, volume, element_material, table, u,
                             b1, out):
    """Fill out (n_e,) with the element stable time steps, s."""
    n_e, n_per = cells.shape
    dim = points.shape[1]
    x = points + u
    factor = np.sqrt(1.0 + b1 * b1) - b1
    for e in prange(n_e):
        G11 = G12 = G13 = G21 = G22 = G23 = G31 = G32 = G33 = 0.0
        for a in range(n_per):
            n = cells[e, a]
            if dim == 2:
                G11 += u[n, 0] * b[e, a, 0]
                G12 += u[n, 0] * b[e, a, 1]
                G21 += u[n, 1] * b[e, a, 0]
                G22 += u[n, 1] * b[e, a, 1]
                G33 += u[n, 0] * hoop[e, a]
            else:
                for j in range(3):
                    bj = b[e, a, j]
                    if j == 0:
                        G11 += u[n, 0] * bj
                        G21 += u[n, 1] * bj
                        G31 += u[n, 2] * bj
                    elif j == 1:
                        G12 += u[n, 0] * bj
                        G22 += u[n, 1] * bj
                        G32 += u[n, 2] * bj
                    else:
                        G13 += u[n, 0] * bj
                        G23 += u[n, 1] * bj
                        G33 += u[n, 2] * bj
        F11, F12, F13 = 1.0 + G11, G12, G13
        F21, F22, F23 = G21, 1.0 + G22, G23
        F31, F32, F33 = G31, G32, 1.0 + G33
        J = (F11 * (F22 * F33 - F23 * F32) - F12 * (F21 * F33 - F23 * F31)
             + F13 * (F21 * F32 - F22 * F31))
        if dim == 2:
            r0, z0 = x[cells[e, 0], 0], x[cells[e, 0], 1]
            r1, z1 = x[cells[e, 1], 0], x[cells[e, 1], 1]
            r2, z2 = x[cells[e, 2], 0], x[cells[e, 2], 1]
            r3, z3 = x[cells[e, 3], 0], x[cells[e, 3], 1]
            area = 0.5 * abs((r2 - r0) * (z3 - z1) - (r3 - r1) * (z2 - z0))
            diagonal = max(np.sqrt((r2 - r0) ** 2 + (z2 - z0) ** 2),
                           np.sqrt((r3 - r1) ** 2 + (z3 - z1) ** 2))
            length = area / diagonal
        else:
            length = volume[e] * J / _hex_largest_face_area(x, cells, e)
        I1 = (F11 * F11 + F12 * F12 + F13 * F13 + F21 * F21 + F22 * F22 + F23 * F23
              + F31 * F31 + F32 * F32 + F33 * F33)
        I1b = I1 / cube_root(J * J) if J > 0.0 else 3.0
        m = element_material[e]
        mu_t = tangent_shear_modulus(I1b, table[m, P_C10], table[m, P_C01], table[m, P_C20],
                                     table[m, P_C30])
        modulus = 2.0 / table[m, P_D1] * max(J, 1.0) + 4.0 / 3.0 * mu_t
        out[e] = length / np.sqrt(modulus / table[m, P_DENSITY]) * factor
