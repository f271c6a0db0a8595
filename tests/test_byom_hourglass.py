"""Physical hourglass stiffness: a square element in its bending mode stores the beam's energy.

Truth: a rectangle of half-sides a x b bent as u_r = q xi eta has the curvature q / (a b)
and the exact (incompatible-mode) energy (E / (1 - nu^2)) (2 b)^3 / 12 (q / (a b))^2 / 2 per
unit length, i.e. U = 2 pi r (2 a) E b q^2 / (3 a^2 (1 - nu^2)) for an axisymmetric ring at
r >> a (plane strain). A one-point element sees no strain in this mode: all of its energy is
the hourglass energy, exact with the physical coefficient, 20x too small with Q = 0.1.
"""

import numpy as np
import pytest

from corneasim.materials import KernelMaterial, kernel_table
from corneasim.materials._hyperelastic import linear_elastic_to_neo_hooke
from corneasim.solver import elements as element_kernels
from corneasim.solver import physical_hourglass_coefficient

E, NU = 1.0, 0.3


def _material():
    c10, d1 = linear_elastic_to_neo_hooke(E, NU)
    return KernelMaterial(density=1e-9, c10=c10, d1=d1)


def test_coefficient_from_poisson_ratio():
    assert physical_hourglass_coefficient(_material()) == pytest.approx(4.0 / (3.0 * 0.7), rel=1e-9)


@pytest.mark.parametrize("half", [0.5, 0.05])
def test_square_ring_element_stores_the_bending_energy(half):
    r = 1000.0
    points = np.array([[r - half, -half], [r + half, -half], [r + half, half], [r - half, half]])
    cells = np.array([[0, 1, 2, 3]])
    material = _material()
    elements = element_kernels.prepare(points, cells, "quad", np.zeros(1, np.int64), kernel_table([material]),
                                       hourglass_coefficient=physical_hourglass_coefficient(material))
    q = 1e-6 * half
    xi, eta = np.array([-1.0, 1.0, 1.0, -1.0]), np.array([-1.0, -1.0, 1.0, 1.0])
    u = np.column_stack([q * xi * eta, np.zeros(4)])
    exact = 2 * np.pi * r * (2 * half) * E * half * q ** 2 / (3 * half ** 2 * (1 - NU ** 2))
    assert element_kernels.stored_energy(elements, u) == pytest.approx(exact, rel=0.01)
