"""Cohesive ties: node pairs of a split mesh held together until a cut separates them.

Not used by the built-in scenarios (they separate tissue by element deletion); tested by the
slow tests (``pytest -m slow``).

Each pair (a, b) of :func:`corneasim.fracture._split.split_nodes` stands for the tributary area
A of the split surface around its node (mm^2; the full ring in an axisymmetric model). Each
pair carries the traction-separation law of :mod:`corneasim.fracture._law`, isotropic in
the opening vector delta = x_b - x_a (mixed mode, one strength and one toughness for opening
and sliding alike), with \\bar\\delta = max over the history of |delta|: the force on b is
-A T(\\bar\\delta) delta / \\bar\\delta, and -1 times it on a. A tie that opens fully dissipates
G_c A whatever the mesh: the cut costs the fracture energy per unit area of new surface.

The elastic branch is an artefact (the uncut tissue is continuous): its stiffness k = A
sigma_c / delta_0 is made as large as the explicit step allows. Two nodes tied by a spring
oscillate at omega^2 = k / m* (m* = m_a m_b / (m_a + m_b)), so with k = beta m* / dt^2 the
pair's (omega dt)^2 grows by beta; the contact penalty has the same form and bound
(``interaction.stable_penalty_fraction``: beta < 4 (1 - s^2), 0.76 for the safety factor
0.9). delta_0 = A sigma_c / k then follows; a pair with delta_0 >= delta_f cannot soften
within its toughness and breaks at its peak (brittle), dissipating A sigma_c delta_0 / 2 >
G_c A: the constructor warns.

The ties are an external-force hook (``docs/solver.md``, "External-force hooks"): their work,
-(stored + dissipated), is part of the external work the solver books, and their stored
(elastic) and dissipated energies are history outputs; counted apart, internal + kinetic +
stored + dissipated = reaction work + the other loads' work. After a tie breaks nothing keeps
its two faces from passing through each other (no contact between the crack faces).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from numba import njit

from corneasim.errors import InputError
from corneasim.mesh import HEXAHEDRON_FACES, QUAD_FACES
from corneasim.contact import stable_penalty_fraction
from corneasim.fracture._law import dissipated_density, envelope_traction

STORED, DISSIPATED, BROKEN, SOFTENING, N_OUTPUTS = 0, 1, 2, 3, 4
"""Entries of the kernel's output array: stored and dissipated energy (mJ), broken and
softening ties (counts)."""


@njit(cache=True)
def cohesive_forces(points, u, pairs, area, stiffness, strength, separation, opening_max, f_ext, out):
    """Add the ties' forces to ``f_ext`` and advance their damage (module notes).

    Parameters
    ----------
    points, u : ndarray (n_nodes, dim) float64
        Reference coordinates and displacements, mm.
    pairs : ndarray (n_pairs, 2) int64
        (a, b) node pairs.
    area : ndarray (n_pairs,) float64
        Tributary area A, mm^2.
    stiffness : ndarray (n_pairs,) float64
        k of the elastic branch, N/mm.
    strength, separation : ndarray (n_pairs,) float64
        sigma_c (MPa) and delta_f = 2 G_c / sigma_c (mm).
    opening_max : ndarray (n_pairs,) float64
        In/out: the largest opening so far, mm.
    f_ext : ndarray (n_nodes, dim) float64
        In/out: external forces, N.
    out : ndarray (N_OUTPUTS,) float64
        Out: stored and dissipated energy (mJ), broken and softening ties.
    """
    dim = u.shape[1]
    out[:] = 0.0
    for i in range(pairs.shape[0]):
        a = pairs[i, 0]
        b = pairs[i, 1]
        length2 = 0.0
        for c in range(dim):
            d = points[b, c] + u[b, c] - points[a, c] - u[a, c]
            length2 += d * d
        length = math.sqrt(length2)
        reached = max(opening_max[i], length)
        opening_max[i] = reached
        peak = strength[i] * area[i] / stiffness[i]
        if reached <= peak:
            secant = stiffness[i]
        else:
            secant = area[i] * envelope_traction(reached, strength[i], peak, separation[i]) / reached
            if secant > 0.0:
                out[SOFTENING] += 1.0
            else:
                out[BROKEN] += 1.0
        for c in range(dim):
            f = secant * (points[b, c] + u[b, c] - points[a, c] - u[a, c])
            f_ext[a, c] += f
            f_ext[b, c] -= f
        out[STORED] += 0.5 * secant * length2
        out[DISSIPATED] += area[i] * dissipated_density(reached, strength[i], peak, separation[i])


def tie_areas(mesh, pairs: np.ndarray) -> np.ndarray:
    """Tributary area of each pair's copy on the split surface, mm^2.

    The split surface is made of the element faces of ``mesh`` whose nodes are all copies
    (second column of ``pairs``; only the moved elements use copies, so each such face is
    theirs and counted once). A hexahedron face of area S gives S / 4 to each of its nodes
    (S = |(x_2 - x_0) x (x_3 - x_1)| / 2, exact for a plane face); an axisymmetric segment
    a-b of length L gives the ring areas 2 pi L (2 r_a + r_b) / 6 and 2 pi L (r_a + 2 r_b) / 6.
    """
    copies = np.zeros(mesh.n_nodes, bool)
    copies[pairs[:, 1]] = True
    slot = np.full(mesh.n_nodes, -1, np.int64)
    slot[pairs[:, 1]] = np.arange(len(pairs))
    area = np.zeros(len(pairs))
    for local in (QUAD_FACES if mesh.cell_type == "quad" else HEXAHEDRON_FACES):
        nodes = mesh.cells[:, local]
        nodes = nodes[copies[nodes].all(axis=1)]  # faces on the split surface, in their node order
        x = mesh.points[nodes]
        if mesh.cell_type == "quad":
            length = np.linalg.norm(x[:, 1] - x[:, 0], axis=1)
            r_a, r_b = x[:, 0, 0], x[:, 1, 0]
            np.add.at(area, slot[nodes[:, 0]], 2 * np.pi * length * (2 * r_a + r_b) / 6)
            np.add.at(area, slot[nodes[:, 1]], 2 * np.pi * length * (r_a + 2 * r_b) / 6)
        else:
            face_area = 0.5 * np.linalg.norm(np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1]), axis=1)
            for corner in range(4):
                np.add.at(area, slot[nodes[:, corner]], face_area / 4)
    return area


class CohesiveTies:
    """External-force hook holding node pairs together by the cohesive law (module notes).

    Parameters
    ----------
    model : corneasim.solver.Model
        The split mesh's model (its lumped masses and stable step set the stiffness).
    pairs : ndarray (n_pairs, 2) int64
        (original, copy) node pairs (:func:`corneasim.fracture._split.split_nodes`).
    area : ndarray (n_pairs,) float64
        Tributary areas, mm^2 (:func:`tie_areas`).
    strength : float or ndarray (n_pairs,)
        Cohesive strength sigma_c, MPa (> 0).
    fracture_energy : float or ndarray (n_pairs,)
        Toughness G_c, N/mm (> 0).
    penalty_fraction : float
        beta of k = beta m* / dt^2 (0 < beta < 4 (1 - s^2)).
    name : str
        Prefix of the history columns.
    """

    def __init__(self, model, pairs, area, strength, fracture_energy, penalty_fraction: float = 0.3,
                 name: str = "cut"):
        pairs = np.ascontiguousarray(pairs, dtype=np.int64).reshape(-1, 2)
        n = len(pairs)
        self.name = name
        self.pairs = pairs
        self.area = np.ascontiguousarray(np.broadcast_to(np.asarray(area, dtype=float), (n,)))
        self.strength = np.ascontiguousarray(np.broadcast_to(np.asarray(strength, dtype=float), (n,)))
        toughness = np.broadcast_to(np.asarray(fracture_energy, dtype=float), (n,))
        limit = stable_penalty_fraction(model.safety_factor)
        for key, values in (("area", self.area), ("strength", self.strength),
                            ("fracture_energy", toughness)):
            if not np.all(values > 0.0):
                raise InputError(f"cohesive ties: {key} must be > 0")
        if not 0.0 < penalty_fraction < limit:
            raise InputError(f"cohesive ties: penalty_fraction must be in (0, {limit:.3g}), got {penalty_fraction}")
        mass_a, mass_b = model.mass[pairs[:, 0]], model.mass[pairs[:, 1]]
        reduced = mass_a * mass_b / (mass_a + mass_b)
        time_step = model.time_step if model.time_step is not None else model.stable_time_step()[0]
        self.stiffness = penalty_fraction * reduced / time_step ** 2
        self.separation = 2.0 * toughness / self.strength
        brittle = int(np.sum(self.strength * self.area / self.stiffness >= self.separation))
        if brittle:
            warnings.warn(f"cohesive ties: {brittle} of {n} ties are too soft for their toughness "
                          "(delta_0 >= 2 G_c / sigma_c) and break at their peak", stacklevel=2)
        self.opening_max = np.zeros(n)
        self.out = np.zeros(N_OUTPUTS)

    def add_forces(self, model, state, time: float, time_step: float, f_ext: np.ndarray) -> None:
        """Add the ties' forces (N) to ``f_ext`` at the current displacements."""
        cohesive_forces(model.mesh.points, state.u, self.pairs, self.area, self.stiffness, self.strength,
                        self.separation, self.opening_max, f_ext, self.out)

    def outputs(self) -> dict[str, float]:
        """History columns ``<name>_stored_energy_mJ``, ``_dissipated_energy_mJ``,
        ``_broken_ties``, ``_softening_ties``."""
        return {f"{self.name}_stored_energy_mJ": float(self.out[STORED]),
                f"{self.name}_dissipated_energy_mJ": float(self.out[DISSIPATED]),
                f"{self.name}_broken_ties": float(self.out[BROKEN]),
                f"{self.name}_softening_ties": float(self.out[SOFTENING])}

    def checkpoint(self) -> dict[str, np.ndarray]:
        """The damage state (largest openings) and the last outputs."""
        return {"opening_max": self.opening_max.copy(), "out": self.out.copy()}

    def restore(self, arrays: dict[str, np.ndarray]) -> None:
        """Restore what :meth:`checkpoint` saved."""
        self.opening_max[:] = arrays["opening_max"]
        self.out[:] = arrays["out"]
