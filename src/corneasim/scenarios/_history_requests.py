"""History requests: extra ``history.csv`` columns of node sets and element sets.

A ``[[history]]`` entry of a scenario asks for one quantity of one set, reduced over the set
(``docs/scenario-format.md``, "History requests"):

* node set: ``displacement`` (mm), ``velocity`` (mm/s, at the half step of central
  differences), ``reaction`` (N: f_int - f_ext on the set's nodes, the force the body exerts
  on its supports where the set is constrained, full ring when axisymmetric; on free nodes it
  is the out-of-balance (inertia and damping) force), per component, reduced by ``sum``,
  ``mean``, ``min``, ``max`` or ``nodes`` (one column per node);
* element set or block: ``stress`` (Cauchy, MPa; components rr, zz, tt, rz axisymmetric, xx,
  yy, zz, xy, yz, zx in 3D, and ``mises``), reduced by a volume-weighted ``mean``, ``min``,
  ``max``; ``strain_energy`` (mJ): the sum over the set of W(F) V_e, W the instantaneous
  hyperelastic energy density of the block's law at the element centre's deformation
  gradient (one-point estimate; axisymmetric V_e = 2 pi r_c A_e).

Every prescribed displacement or velocity is logged as ``prescribed_<set>_<component>_mm``:
the mean displacement of the set's nodes in that component (equal to value x a(t) for a
prescribed displacement).

The columns come from a probe that the time loop calls like an external-force hook (it adds
no force); before the first step it reports the reference state (zeros).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from pydantic import Field

from corneasim.errors import InputError
from corneasim.materials.kernel import elastic_energy
from corneasim.mesh import element_measures
from corneasim.schema import StrictModel

NODE_QUANTITIES = {"displacement": "mm", "velocity": "mm_per_s", "reaction": "N"}
ELEMENT_QUANTITIES = {"stress": "MPa", "strain_energy": "mJ"}
STRESS_COMPONENTS = {True: ("rr", "zz", "tt", "rz"), False: ("xx", "yy", "zz", "xy", "yz", "zx")}
"""Stress components by ``axisymmetric``, in the order of the kernels' Cauchy stress rows."""


class HistoryRequest(StrictModel):
    """A history column (or columns): one quantity of a node set or an element set."""

    name: str = Field(description="Column prefix: columns are NAME_COMPONENT_UNIT (NAME_COMPONENT_NODE_UNIT "
                      "per node).")
    node_set: str | None = Field(None, description="Node set of a displacement, velocity or reaction.")
    element_set: str | None = Field(None, description="Element set or block of a stress or strain energy.")
    quantity: Literal["displacement", "velocity", "reaction", "stress", "strain_energy"] = Field(
        description="displacement (mm), velocity (mm/s), reaction (N) of a node set; stress (MPa), "
        "strain_energy (mJ) of an element set.")
    components: list[str] = Field([], description="Components: r, z (axisymmetric) or x, y, z for node "
                                  "quantities; rr, zz, tt, rz or xx, yy, zz, xy, yz, zx and mises for stress; "
                                  "empty: all (strain_energy has none).")
    reduce: Literal["sum", "mean", "min", "max", "nodes"] | None = Field(
        None, description="Over the set: sum, mean, min, max, or nodes (a column per node; node sets only); "
        "default: sum for reaction and strain_energy, mean otherwise (volume-weighted for stress).")


@dataclass(frozen=True)
class _Item:
    """One column (or one per node): what to read and how to reduce it."""

    kind: str  # node, stress or energy
    stem: str
    unit: str
    quantity: str
    members: np.ndarray
    component: int
    how: str


def _reduce(values: np.ndarray, how: str, weights: np.ndarray | None = None) -> float:
    if how == "sum":
        return float(values.sum())
    if how == "min":
        return float(values.min())
    if how == "max":
        return float(values.max())
    if weights is not None:
        return float(np.dot(values, weights) / weights.sum())
    return float(values.mean())


class HistoryProbe:
    """The columns of a scenario's history requests and prescribed motions (module notes).

    Parameters
    ----------
    requests : list of HistoryRequest
    mesh : Mesh
    model : Model
        Its ``material_table`` and ``element_material`` give the strain-energy laws.
    prescribed : list of (str, str)
        (node set, component) of every prescribed motion.
    """

    name = "history"

    def __init__(self, requests, mesh, model, prescribed=()):
        self.mesh, self.model = mesh, model
        self.state = None
        axes = "rz" if mesh.axisymmetric else "xyz"
        self.items = []
        for k, request in enumerate(requests):
            where = f"history[{k}] ('{request.name}')"
            if (request.node_set is None) == (request.element_set is None):
                raise InputError(f"{where}: give exactly one of node_set or element_set")
            if request.node_set is not None:
                self.items.append(self._node_item(request, where, axes))
            else:
                self.items.append(self._element_item(request, where))
        for node_set, component in prescribed:
            self.items.append([_Item("node", f"prescribed_{node_set}_{component}", "mm", "displacement",
                                     mesh.node_sets[node_set], axes.index(component), "mean")])
        self._volumes = None

    def _node_item(self, request, where, axes):
        if request.quantity not in NODE_QUANTITIES:
            raise InputError(f"{where}: a node set has displacement, velocity or reaction, not {request.quantity}")
        if request.node_set not in self.mesh.node_sets:
            raise InputError(f"{where}: node set '{request.node_set}' does not exist "
                             f"(node sets: {', '.join(self.mesh.node_sets) or 'none'})")
        components = request.components or list(axes)
        for component in components:
            if component not in axes:
                raise InputError(f"{where}: component '{component}' is not one of {', '.join(axes)}")
        how = request.reduce or ("sum" if request.quantity == "reaction" else "mean")
        nodes = self.mesh.node_sets[request.node_set]
        unit = NODE_QUANTITIES[request.quantity]
        return [_Item("node", f"{request.name}_{c}", unit, request.quantity, nodes, axes.index(c), how)
                for c in components]

    def _element_item(self, request, where):
        if request.quantity not in ELEMENT_QUANTITIES:
            raise InputError(f"{where}: an element set has stress or strain_energy, not {request.quantity}")
        mesh = self.mesh
        if request.element_set in mesh.block_names:
            elements = mesh.block_elements(request.element_set)
        elif request.element_set in mesh.element_sets:
            elements = mesh.element_sets[request.element_set]
        else:
            raise InputError(f"{where}: element set '{request.element_set}' is neither a block nor an element set "
                             f"(blocks: {', '.join(mesh.block_names)}; element sets: "
                             f"{', '.join(mesh.element_sets) or 'none'})")
        if request.reduce in ("nodes",):
            raise InputError(f"{where}: reduce = 'nodes' is for node sets")
        if request.quantity == "strain_energy":
            return [_Item("energy", request.name, "mJ", "strain_energy", elements, 0, request.reduce or "sum")]
        names = STRESS_COMPONENTS[mesh.axisymmetric]
        components = request.components or [*names, "mises"]
        for component in components:
            if component not in (*names, "mises"):
                raise InputError(f"{where}: stress component '{component}' is not one of {', '.join(names)}, mises")
        how = request.reduce or "mean"
        return [_Item("stress", f"{request.name}_{c}", "MPa", c, elements, names.index(c) if c != "mises" else -1,
                      how) for c in components]

    def add_forces(self, model, state, time, time_step, f_ext) -> None:
        """No force: keep the state whose columns :meth:`outputs` reports."""
        self.state = state

    def outputs(self) -> dict[str, float]:
        """The requested columns at the time of the kept state (zeros before the first step)."""
        row = {}
        stress = None
        for item in (item for items in self.items for item in items):
            column = f"{item.stem}_{item.unit}"
            if item.kind == "node":
                values = self._node_values(item.quantity, item.members, item.component)
                if item.how == "nodes":
                    row.update({f"{item.stem}_{node}_{item.unit}": float(v) for node, v in zip(item.members, values)})
                else:
                    row[column] = _reduce(values, item.how)
            elif item.kind == "stress":
                if stress is None:
                    stress = self._stress()
                members = item.members
                values = self._mises(stress[members]) if item.component < 0 else stress[members, item.component]
                row[column] = _reduce(values, item.how, self.volumes[members])
            else:
                row[column] = _reduce(self._energy(item.members), item.how)
        return row

    def _node_values(self, quantity, nodes, component):
        state = self.state
        if state is None:
            return np.zeros(nodes.size)
        if quantity == "displacement":
            return state.u[nodes, component]
        if quantity == "velocity":
            return state.v[nodes, component]
        return state.f_int[nodes, component] - state.f_ext[nodes, component]

    def _stress(self) -> np.ndarray:
        from corneasim.solver import elements as element_kernels

        if self.state is None:
            return np.zeros((self.mesh.n_elements, 6))
        sigma = element_kernels.element_stress(self.model.elements, self.state.u, self.state.history)
        return sigma * (self.state.alive != 0)[:, None]

    @staticmethod
    def _mises(sigma: np.ndarray) -> np.ndarray:
        s11, s22, s33, s12, s23, s31 = sigma.T  # axisymmetric: rr, zz, tt, rz, 0, 0
        return np.sqrt(0.5 * ((s11 - s22) ** 2 + (s22 - s33) ** 2 + (s33 - s11) ** 2)
                       + 3.0 * (s12 ** 2 + s23 ** 2 + s31 ** 2))

    @property
    def volumes(self) -> np.ndarray:
        """Reference element volumes, mm^3 (axisymmetric: 2 pi r_c A_e, the full ring)."""
        if self._volumes is None:
            measures = element_measures(self.mesh)
            if self.mesh.axisymmetric:
                measures = 2.0 * np.pi * self.mesh.points[self.mesh.cells][..., 0].mean(axis=1) * measures
            self._volumes = measures
        return self._volumes

    def _energy(self, elements: np.ndarray) -> np.ndarray:
        if self.state is None:
            return np.zeros(elements.size)
        gradients = centre_gradients(self.mesh, self.state.u, elements)
        table, material = self.model.material_table, self.model.element_material
        alive = self.state.alive[elements] != 0
        frames = self.model.elements.fibre_frame  # None: no fibre material in the mesh
        density = np.array([
            elastic_energy(F, table[material[e]], None if frames is None else frames[e])
            for F, e in zip(gradients, elements)])
        return density * self.volumes[elements] * alive


def centre_gradients(mesh, u: np.ndarray, elements: np.ndarray) -> np.ndarray:
    """Deformation gradients (n, 3, 3) at the centres of ``elements`` (bilinear / trilinear shape functions).

    Axisymmetric: the (r, z) block from the quad's shape functions at xi = eta = 0 and
    F_tt = 1 + u_r / r at the centre (r > 0 there).
    """
    cells = mesh.cells[elements]
    X, U = mesh.points[cells], u[cells]
    if mesh.cell_type == "quad":
        d_natural = 0.25 * np.array([[-1.0, 1.0, 1.0, -1.0], [-1.0, -1.0, 1.0, 1.0]])  # (2, 4)
    else:
        signs = np.array([[-1, 1, 1, -1, -1, 1, 1, -1], [-1, -1, 1, 1, -1, -1, 1, 1], [-1, -1, -1, -1, 1, 1, 1, 1]])
        d_natural = 0.125 * signs.astype(float)
    jacobian = np.einsum("ka,nai->nki", d_natural, X)  # dX_i / dxi_k
    d_x = np.linalg.solve(jacobian, np.broadcast_to(d_natural, (len(cells), *d_natural.shape)))  # dN_a / dX_k
    grad = np.einsum("nka,nai->nik", d_x, U)  # du_i / dX_k
    dim = mesh.dim
    F = np.tile(np.eye(3), (len(cells), 1, 1))
    F[:, :dim, :dim] += grad
    if mesh.axisymmetric:
        F[:, 2, 2] = 1.0 + U[..., 0].mean(axis=1) / X[..., 0].mean(axis=1)
    return F
