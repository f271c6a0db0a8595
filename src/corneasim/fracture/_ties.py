"""Cohesive ties: node pairs of a split mesh held together until a cut separates them.

Each pair (a, b) of :func:`corneasim.fracture._split.split_nodes` stands for the tributary area
A of the split surface around its node (mm^2; the full ring in an axisymmetric model) and its
unit normal n, from the side of the originals a to the side of the copies b. The opening
delta = x_b - x_a splits into the normal part delta_n = delta . n and the sliding part
delta_t = delta - delta_n n. The pair carries the traction-separation law of
:mod:`corneasim.fracture._law` on the effective opening (mixed mode, one strength and one
toughness for opening and sliding alike; Camanho and Davila, NASA/TM-2002-211737)

.. math::

    \\lambda = \\sqrt{\\langle\\delta_n\\rangle^2 + |\\delta_t|^2}, \\qquad
    \\bar\\lambda = \\max_{\\text{history}} \\lambda,

with the force on b -A T(\\bar\\lambda) delta_open / \\bar\\lambda (delta_open = delta - min(delta_n, 0) n)
and -1 times it on a; a closing pair (delta_n < 0) is pushed apart by the penalty k delta_n n
of the elastic branch whatever its damage, so the faces of a cut stay in contact and do not
pass through each other (the crack faces' frictionless contact). A tie that opens fully
dissipates G_c A whatever the mesh: the cut costs the fracture energy per unit area of new
surface. A cutting edge pays part or all of it (``fracture._edge_work``: the work the edge
does on the pair's nodes): a tie is cut once its own dissipation and the energy supplied to it
together reach G_c A, and carries no tension or sliding from then on.

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
(elastic and contact) and dissipated energies are history outputs; counted apart, internal +
kinetic + stored + dissipated = reaction work + the other loads' work.
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

STORED, DISSIPATED, BROKEN, SOFTENING, SUPPLIED, N_OUTPUTS = 0, 1, 2, 3, 4, 5
"""Entries of the kernel's output array: stored and dissipated energy (mJ), broken and
softening ties (counts), the energy a cutting edge supplied to the ties (mJ)."""


@njit(cache=True)
def cohesive_forces(points, u, pairs, normal, area, stiffness, strength, separation, opening_max, supplied, cut,
                    f_ext, out):
    """Add the ties' forces to ``f_ext`` and advance their damage (module notes).

    Parameters
    ----------
    points, u : ndarray (n_nodes, dim) float64
        Reference coordinates and displacements, mm.
    pairs : ndarray (n_pairs, 2) int64
        (a, b) node pairs.
    normal : ndarray (n_pairs, dim) float64
        Unit normal n of the split surface at each pair, from a's side to b's.
    area : ndarray (n_pairs,) float64
        Tributary area A, mm^2.
    stiffness : ndarray (n_pairs,) float64
        k of the elastic branch, N/mm.
    strength, separation : ndarray (n_pairs,) float64
        sigma_c (MPa) and delta_f = 2 G_c / sigma_c (mm).
    opening_max : ndarray (n_pairs,) float64
        In/out: the largest effective opening so far, \\bar\\lambda, mm.
    supplied : ndarray (n_pairs,) float64
        Energy a cutting edge has delivered to each tie, mJ (``fracture._edge_work``; zeros
        without one).
    cut : ndarray (n_pairs,) uint8
        In/out: 1 for a tie cut through, once its opening's dissipation and the supplied
        energy together reach G_c A; a cut tie carries no tension or sliding (its faces'
        contact remains), and its damage no longer changes.
    f_ext : ndarray (n_nodes, dim) float64
        In/out: external forces, N.
    out : ndarray (N_OUTPUTS,) float64
        Out: stored and dissipated energy (mJ), broken and softening ties.
    """
    dim = u.shape[1]
    out[:] = 0.0
    delta = np.empty(dim)
    for i in range(pairs.shape[0]):
        a = pairs[i, 0]
        b = pairs[i, 1]
        delta_n = 0.0
        for c in range(dim):
            delta[c] = points[b, c] + u[b, c] - points[a, c] - u[a, c]
            delta_n += delta[c] * normal[i, c]
        closing = min(delta_n, 0.0)
        length2 = 0.0
        for c in range(dim):
            delta[c] -= closing * normal[i, c]  # delta_open
            length2 += delta[c] * delta[c]
        length = math.sqrt(length2)
        if cut[i]:
            reached = opening_max[i]
        else:
            reached = max(opening_max[i], length)
            opening_max[i] = reached
        peak = strength[i] * area[i] / stiffness[i]
        dissipated = area[i] * dissipated_density(reached, strength[i], peak, separation[i])
        if not cut[i] and supplied[i] + dissipated >= 0.5 * strength[i] * separation[i] * area[i]:
            cut[i] = 1
        out[SUPPLIED] += supplied[i]
        if cut[i]:
            secant = 0.0
            out[BROKEN] += 1.0
        elif reached <= peak:
            secant = stiffness[i]
        else:
            secant = area[i] * envelope_traction(reached, strength[i], peak, separation[i]) / reached
            if secant > 0.0:
                out[SOFTENING] += 1.0
            else:
                out[BROKEN] += 1.0
        for c in range(dim):
            f = secant * delta[c] + stiffness[i] * closing * normal[i, c]
            f_ext[a, c] += f
            f_ext[b, c] -= f
        out[STORED] += 0.5 * secant * length2 + 0.5 * stiffness[i] * closing * closing
        out[DISSIPATED] += dissipated


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


def tie_normals(mesh, pairs: np.ndarray) -> np.ndarray:
    """Unit normal of the split surface at each pair, from the originals' side to the copies',
    (n_pairs, dim).

    The area-weighted mean of the normals of the split surface's faces at the pair's copy
    (the faces of :func:`tie_areas`), each oriented into the element that owns it (the side of
    the copies): n = N / |N|, N = sum over the faces at the node of S n_face. A hexahedron
    face's vector area is (x_2 - x_0) x (x_3 - x_1) / 2; an axisymmetric segment's normal is
    its direction turned by 90 degrees in (r, z).
    """
    copies = np.zeros(mesh.n_nodes, bool)
    copies[pairs[:, 1]] = True
    slot = np.full(mesh.n_nodes, -1, np.int64)
    slot[pairs[:, 1]] = np.arange(len(pairs))
    dim = mesh.points.shape[1]
    total = np.zeros((len(pairs), dim))
    centroid = mesh.points[mesh.cells].mean(axis=1)
    for local in (QUAD_FACES if mesh.cell_type == "quad" else HEXAHEDRON_FACES):
        nodes = mesh.cells[:, local]
        on_split = copies[nodes].all(axis=1)
        nodes = nodes[on_split]
        x = mesh.points[nodes]
        if mesh.cell_type == "quad":
            along = x[:, 1] - x[:, 0]
            vector = np.stack([along[:, 1], -along[:, 0]], axis=1)
        else:
            vector = 0.5 * np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1])
        inward = centroid[on_split] - x.mean(axis=1)
        vector *= np.where(np.einsum("ij,ij->i", vector, inward) < 0.0, -1.0, 1.0)[:, None]
        for corner in range(nodes.shape[1]):
            np.add.at(total, slot[nodes[:, corner]], vector)
    length = np.linalg.norm(total, axis=1)
    if np.any(length == 0.0):
        raise InputError("cohesive ties: a pair's copy lies on no face of the split surface")
    return total / length[:, None]


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
    normal : ndarray (n_pairs, dim), optional
        Unit normals of the split surface from the originals' side to the copies'
        (default: :func:`tie_normals` of the model's mesh).
    """

    def __init__(self, model, pairs, area, strength, fracture_energy, penalty_fraction: float = 0.3,
                 name: str = "cut", normal=None):
        pairs = np.ascontiguousarray(pairs, dtype=np.int64).reshape(-1, 2)
        n = len(pairs)
        self.name = name
        self.pairs = pairs
        # copies, writable whatever was given (a read-only array would compile cohesive_forces apart)
        self.area = np.broadcast_to(np.asarray(area, dtype=float), (n,)).copy()
        self.strength = np.broadcast_to(np.asarray(strength, dtype=float), (n,)).copy()
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
        self.normal = np.ascontiguousarray(tie_normals(model.mesh, pairs) if normal is None else normal,
                                           dtype=float).reshape(n, -1)
        self.opening_max = np.zeros(n)
        self.supplied = np.zeros(n)
        self.cut = np.zeros(n, np.uint8)
        self.out = np.zeros(N_OUTPUTS)

    def add_forces(self, model, state, time: float, time_step: float, f_ext: np.ndarray) -> None:
        """Add the ties' forces (N) to ``f_ext`` at the current displacements."""
        cohesive_forces(model.mesh.points, state.u, self.pairs, self.normal, self.area, self.stiffness, self.strength,
                        self.separation, self.opening_max, self.supplied, self.cut, f_ext, self.out)

    def outputs(self) -> dict[str, float]:
        """History columns ``<name>_stored_energy_mJ``, ``_dissipated_energy_mJ``,
        ``_broken_ties``, ``_softening_ties`` and ``_edge_energy_mJ`` (supplied by a cutting edge)."""
        return {f"{self.name}_stored_energy_mJ": float(self.out[STORED]),
                f"{self.name}_edge_energy_mJ": float(self.out[SUPPLIED]),
                f"{self.name}_dissipated_energy_mJ": float(self.out[DISSIPATED]),
                f"{self.name}_broken_ties": float(self.out[BROKEN]),
                f"{self.name}_softening_ties": float(self.out[SOFTENING])}

    def checkpoint(self) -> dict[str, np.ndarray]:
        """The damage state (largest openings, supplied energies, cut flags) and the last outputs."""
        return {"opening_max": self.opening_max.copy(), "supplied": self.supplied.copy(), "cut": self.cut.copy(),
                "out": self.out.copy()}

    def restore(self, arrays: dict[str, np.ndarray]) -> None:
        """Restore what :meth:`checkpoint` saved."""
        self.opening_max[:] = arrays["opening_max"]
        self.supplied[:] = arrays["supplied"]
        self.cut[:] = arrays["cut"]
        self.out[:] = arrays["out"]
