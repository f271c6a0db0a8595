"""Physical hourglass stiffness: the Flanagan-Belytschko coefficient that gives an element its bending stiffness.

One-point elements see no strain in their hourglass (bending) modes; the stiffness-type
control resists a mode with k_e = Q mu_0 V_e (b : b) (``elements/_api.py``). A physical
stabilisation (Belytschko & Bindeman 1991, Comput. Methods Appl. Mech. Eng. 88:311; the
assumed-strain stiffness that makes the element exact in pure bending) chooses k_e from the
material instead of a small numerical Q. For a rectangle of half-sides a x b in its x-mode
u_x = q xi eta the exact (incompatible-mode) bending energy is the beam's,

    U = 1/2 E' (q / a)^2 integral(eta^2 dA) = 1/2 (E' V / (3 a^2)) q^2,   E' = E / (1 - nu^2)

(curvature q / (a b), I = (2b)^3 / 12 per unit width; plane strain, as an axisymmetric ring
far from the axis), while the kernels store 1/2 k_e q^2 with q = gamma . u = q for
gamma = h / 4 and b : b = (1 / a^2 + 1 / b^2) / 4. Equal for a square (a = b):

    Q = 2 E' / (3 mu_0) = 4 / (3 (1 - nu)),

1.90 for nu = 0.3, 2.6 for nu = 0.49 (the default Q = 0.1 is 20x softer in bending). For
elongated elements the single k_e of both components is too stiff in the long direction's
mode and too soft in the other (the assumed-strain form has one stiffness per component),
so the square-element value is the compromise; ``docs/quasi-static.md`` gives its effect on a
plate in bending and on the punch sequence.
"""

from __future__ import annotations

import numpy as np


def physical_hourglass_coefficient(material) -> float:
    """Q = 4 / (3 (1 - nu)) of a material (``KernelMaterial``; nu from K and mu_0), dimensionless."""
    mu, bulk = abs(material.initial_shear_modulus), material.bulk_modulus
    nu = (3.0 * bulk - 2.0 * mu) / (2.0 * (3.0 * bulk + mu))
    return 4.0 / (3.0 * (1.0 - nu))


def physical_hourglass_coefficients(mesh, materials: dict) -> np.ndarray:
    """Q of every element of ``mesh`` (n_elements,) from its block's material (block name -> KernelMaterial)."""
    per_block = np.array([physical_hourglass_coefficient(materials[name]) for name in mesh.block_names])
    return per_block[mesh.element_block]
