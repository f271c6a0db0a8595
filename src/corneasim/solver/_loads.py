"""Boundary conditions and loads as the user states them, and their packed kernel form.

A boundary condition acts on the degrees of freedom (dof = node * dim + component) of a
node set. Each constrained dof gets one row of the constraint table read by the
integrator kernel:

=====================  ===========================================================
kind                   velocity imposed over the step t^n -> t^{n+1}
=====================  ===========================================================
``FIXED`` (0)          v = 0 (also symmetry planes and the axis of symmetry)
``DISPLACEMENT`` (1)   v = (value * a(t^{n+1}) - u^n) / dt, so u^{n+1} is exact
``VELOCITY`` (2)       v = value * a(t^{n+1/2})
=====================  ===========================================================

with a(t) an amplitude (:mod:`corneasim.solver._amplitudes`) packed into a row of an
amplitude table. Components are named ``r``/``z`` in axisymmetric models and
``x``/``y``/``z`` in 3D ones. Cyclic symmetry (:class:`CyclicSymmetry`) couples node pairs of a
half model's cut plane instead (:mod:`corneasim.solver._cyclic`); its axis nodes get fixed
rows. A follower pressure acts on a surface set in the current configuration
(:mod:`corneasim.solver._pressure`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from corneasim.errors import InputError
from corneasim.solver._cyclic import CyclicSymmetry, pair_nodes
from corneasim.solver._amplitudes import Amplitude, Constant

FIXED, DISPLACEMENT, VELOCITY = 0, 1, 2
AXIS_SET = "symmetry_axis"
"""Name under which the automatic axis-of-symmetry condition is reported."""


@dataclass(frozen=True)
class Fixed:
    """Zero displacement of the named components of a node set.

    Attributes
    ----------
    node_set : str
        Name of a node set of the mesh.
    components : str
        Components held, e.g. ``"rz"``, ``"xyz"`` or ``"z"``.
    """

    node_set: str
    components: str


@dataclass(frozen=True)
class SymmetryPlane:
    """Zero normal displacement on a symmetry plane normal to a coordinate axis.

    Attributes
    ----------
    node_set : str
        Nodes on the plane.
    normal : str
        The plane's normal axis, ``"x"``, ``"y"`` or ``"z"`` (``"r"`` or ``"z"`` in an
        axisymmetric model; ``"z"`` there is a mid-plane of symmetry).
    """

    node_set: str
    normal: str


@dataclass(frozen=True)
class Prescribed:
    """Prescribed displacement (mm) or velocity (mm/s) of one component: value * a(t).

    Attributes
    ----------
    node_set : str
        Name of a node set.
    component : str
        One component name (``"z"``).
    kind : str
        ``"displacement"`` or ``"velocity"``.
    value : float
        Magnitude, mm or mm/s, scaled by ``amplitude``.
    amplitude : Amplitude
        Time function, dimensionless (default: constant 1).
    """

    node_set: str
    component: str
    kind: str
    value: float
    amplitude: Amplitude = Constant(1.0)


@dataclass(frozen=True)
class Pressure:
    """Follower pressure (MPa) on a surface set, positive pushing into the surface.

    Attributes
    ----------
    surface_set : str
        Name of a surface set of the mesh (element, local face) rows.
    value : float
        Pressure, MPa (intraocular pressure 17.5 mmHg = 2.333e-3 MPa), scaled by ``amplitude``.
    amplitude : Amplitude
        Time function, dimensionless (default: constant 1).
    """

    surface_set: str
    value: float
    amplitude: Amplitude = Constant(1.0)


def component_index(name: str, axisymmetric: bool, where: str) -> int:
    """Index of a component name (``r``/``z`` or ``x``/``y``/``z``); InputError otherwise."""
    names = "rz" if axisymmetric else "xyz"
    if len(name) != 1 or name not in names:
        raise InputError(f"{where}: component '{name}' is not one of {', '.join(names)}")
    return names.index(name)


def pack_amplitudes(amplitudes: list[Amplitude]) -> np.ndarray:
    """Stack packed amplitudes into a zero-padded table (n_amplitudes, max_length), float64."""
    packed = [amplitude.pack() for amplitude in amplitudes] or [Constant(1.0).pack()]
    table = np.zeros((len(packed), max(p.size for p in packed)))
    for row, values in enumerate(packed):
        table[row, : values.size] = values
    return table


def _node_set(mesh, name: str, where: str) -> np.ndarray:
    if name not in mesh.node_sets:
        raise InputError(f"{where}: node set '{name}' does not exist "
                         f"(node sets: {', '.join(sorted(mesh.node_sets)) or 'none'})")
    return np.asarray(mesh.node_sets[name], dtype=np.int64)


def pack_constraints(mesh, conditions, axis_tolerance: float = 1e-9):
    """Constraint table of a mesh from boundary-condition specs.

    Parameters
    ----------
    mesh : corneasim.mesh.Mesh
    conditions : sequence of Fixed, SymmetryPlane, CyclicSymmetry or Prescribed
    axis_tolerance : float
        Nodes with r below this (mm) are on the axis of an axisymmetric mesh and get u_r = 0.

    Returns
    -------
    dict
        ``dof`` (n_c,) int64, ``kind`` (n_c,) int64, ``value`` (n_c,) float64 (mm or mm/s),
        ``amplitude`` (n_c,) int64 row of ``amplitude_table`` (n_amp, width) float64,
        ``set_names`` list of str and ``set_index`` (n_c,) int64 (the condition's node set,
        for reaction output); ``cyclic_master``, ``cyclic_slave`` (n_pairs,) int64 and
        ``cyclic_held`` (n_pairs, 3) uint8 (1 where both nodes of the pair have the component
        fixed). A dof constrained twice raises InputError unless both hold it fixed; so does
        a node of a cyclic pair that is not held the same way as its image.
    """
    dim = mesh.dim
    rows: dict[int, tuple[int, float, int, int]] = {}
    amplitudes: list[Amplitude] = [Constant(1.0)]
    set_names: list[str] = []
    masters: list[np.ndarray] = []
    slaves: list[np.ndarray] = []

    def add(nodes, component, kind, value, amplitude_row, set_name, where):
        if set_name not in set_names:
            set_names.append(set_name)
        set_row = set_names.index(set_name)
        for node in nodes:
            dof = int(node) * dim + component
            previous = rows.get(dof)
            if previous is not None and not (previous[0] == FIXED and kind == FIXED):
                raise InputError(f"{where}: node {int(node)} component {component} is already "
                                 f"constrained by node set '{set_names[previous[3]]}'")
            if previous is None:
                rows[dof] = (kind, value, amplitude_row, set_row)

    if mesh.axisymmetric:
        axis_nodes = np.flatnonzero(mesh.points[:, 0] <= axis_tolerance)
        add(axis_nodes, 0, FIXED, 0.0, 0, AXIS_SET, "axis of symmetry")
    for number, condition in enumerate(conditions):
        where = f"boundary condition {number} ({type(condition).__name__})"
        if isinstance(condition, Fixed):
            nodes = _node_set(mesh, condition.node_set, where)
            if not condition.components:
                raise InputError(f"{where}: no components given")
            for name in condition.components:
                add(nodes, component_index(name, mesh.axisymmetric, where), FIXED, 0.0, 0,
                    condition.node_set, where)
        elif isinstance(condition, SymmetryPlane):
            nodes = _node_set(mesh, condition.node_set, where)
            add(nodes, component_index(condition.normal, mesh.axisymmetric, where), FIXED, 0.0, 0,
                condition.node_set, where)
        elif isinstance(condition, CyclicSymmetry):
            if mesh.axisymmetric or condition.axis != "z":
                raise InputError(f"{where}: cyclic symmetry is about the z axis of a 3D mesh "
                                 f"(got axis '{condition.axis}' in a {mesh.dim}D mesh)")
            where = f"{where} on node set '{condition.node_set}'"
            master, slave, axis_nodes = pair_nodes(mesh.points, _node_set(mesh, condition.node_set, where),
                                                   where)
            masters.append(master)
            slaves.append(slave)
            for component in (0, 1):
                add(axis_nodes, component, FIXED, 0.0, 0, condition.node_set, where)
        elif isinstance(condition, Prescribed):
            nodes = _node_set(mesh, condition.node_set, where)
            kinds = {"displacement": DISPLACEMENT, "velocity": VELOCITY}
            if condition.kind not in kinds:
                raise InputError(f"{where}: kind '{condition.kind}' is not displacement or velocity")
            if not np.isfinite(condition.value):
                raise InputError(f"{where}: value must be a finite number (mm or mm/s)")
            amplitudes.append(condition.amplitude)
            add(nodes, component_index(condition.component, mesh.axisymmetric, where),
                kinds[condition.kind], float(condition.value), len(amplitudes) - 1,
                condition.node_set, where)
        else:
            raise InputError(f"{where}: not a boundary condition")
    dofs = np.array(sorted(rows), dtype=np.int64)
    table = np.array([rows[d] for d in dofs], dtype=np.float64).reshape(-1, 4)
    master = np.concatenate(masters) if masters else np.zeros(0, np.int64)
    slave = np.concatenate(slaves) if slaves else np.zeros(0, np.int64)
    return {
        "dof": dofs,
        "kind": table[:, 0].astype(np.int64),
        "value": table[:, 1].copy(),
        "amplitude": table[:, 2].astype(np.int64),
        "set_index": table[:, 3].astype(np.int64),
        "set_names": set_names,
        "amplitude_table": pack_amplitudes(amplitudes),
        "cyclic_master": master,
        "cyclic_slave": slave,
        "cyclic_held": _held_components(rows, master, slave, dim),
    }


def _held_components(rows: dict, master: np.ndarray, slave: np.ndarray, dim: int) -> np.ndarray:
    """(n_pairs, dim) uint8: 1 where both nodes of a cyclic pair hold the component fixed.

    A pair is one node of the full model, so its two copies must be constrained alike: only
    fixed components, the same on both (InputError otherwise, naming the node).
    """
    paired = np.concatenate([master, slave])
    if np.unique(paired).size != paired.size:
        values, counts = np.unique(paired, return_counts=True)
        raise InputError(f"cyclic symmetry: node {int(values[counts > 1][0])} belongs to two pairs")
    held = np.zeros((master.size, dim), np.uint8)
    for k, (a, b) in enumerate(zip(master, slave)):
        for i in range(dim):
            row_a, row_b = rows.get(int(a) * dim + i), rows.get(int(b) * dim + i)
            if row_a is None and row_b is None:
                continue
            if row_a is None or row_b is None or row_a[0] != FIXED or row_b[0] != FIXED:
                raise InputError(f"cyclic symmetry: nodes {int(a)} and {int(b)} are one node of the full "
                                 f"model but component {'xyz'[i]} is constrained differently on them "
                                 "(only the same fixed components are allowed on a pair)")
            held[k, i] = 1
    return held


def pack_pressures(mesh, pressures):
    """Pressure faces of a mesh: node indices, owning element, magnitude and amplitude row.

    Returns
    -------
    dict
        ``face_nodes`` (n_f, 2 | 4) int64, ``face_element`` (n_f,) int64, ``value`` (n_f,)
        float64 MPa, ``amplitude`` (n_f,) int64 row of ``amplitude_table``.
    """
    width = 2 if mesh.cell_type == "quad" else 4
    face_nodes, face_element, value, amplitude = [], [], [], []
    amplitudes: list[Amplitude] = []
    for number, pressure in enumerate(pressures):
        where = f"pressure {number}"
        if not isinstance(pressure, Pressure):
            raise InputError(f"{where}: not a Pressure")
        if pressure.surface_set not in mesh.surface_sets:
            raise InputError(f"{where}: surface set '{pressure.surface_set}' does not exist "
                             f"(surface sets: {', '.join(sorted(mesh.surface_sets)) or 'none'})")
        if not np.isfinite(pressure.value):
            raise InputError(f"{where}: value must be a finite number (MPa)")
        amplitudes.append(pressure.amplitude)
        nodes = mesh.face_nodes(pressure.surface_set)
        face_nodes.append(nodes)
        face_element.append(mesh.surface_sets[pressure.surface_set][:, 0])
        value.append(np.full(len(nodes), float(pressure.value)))
        amplitude.append(np.full(len(nodes), len(amplitudes) - 1))
    if not face_nodes:
        return {"face_nodes": np.zeros((0, width), np.int64), "face_element": np.zeros(0, np.int64),
                "value": np.zeros(0), "amplitude": np.zeros(0, np.int64),
                "amplitude_table": pack_amplitudes([])}
    return {
        "face_nodes": np.ascontiguousarray(np.concatenate(face_nodes), dtype=np.int64),
        "face_element": np.concatenate(face_element).astype(np.int64),
        "value": np.concatenate(value),
        "amplitude": np.concatenate(amplitude).astype(np.int64),
        "amplitude_table": pack_amplitudes(amplitudes),
    }
