"""The element API the integrator calls (contract: ``docs/dev/solver-api.md``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from corneasim.errors import InputError
from corneasim.materials.kernel import (
    MAX_PRONY_TERMS, N_PARAMETERS, P_C01, P_C10, P_D1, P_DENSITY, P_FIBRE_K1, elastic_energy)
from corneasim.solver.elements import _geometry, _reference
from corneasim.solver.elements._jacobian import centre_jacobians
from corneasim.solver.elements._layout import BLOCK_SIZES
from corneasim.solver.elements._material_point import step_prony_coefficients
from corneasim.solver.elements._schedule import kernel_threads
from corneasim.solver.elements._time_step import hex_stable_time_steps, quad_stable_time_steps

KINDS = {"quad": (4, 2), "hexahedron": (8, 3)}


@dataclass
class ElementSet:
    """Reference data of one element type (arrays indexed by element, SI-mm units).

    Attributes
    ----------
    kind : str
        ``"quad"`` (axisymmetric, (r, z), full ring) or ``"hexahedron"``.
    points : ndarray (n_nodes, dim)
        Reference coordinates, mm.
    cells : ndarray (n_elements, 4 | 8) int64
        Node indices (counter-clockwise quads; VTK-ordered hexahedra).
    element_material : ndarray (n_elements,) int64
        Row of ``material_table`` per element.
    material_table : ndarray (n_materials, N_PARAMETERS)
        ``materials.kernel_table`` layout.
    volume : ndarray (n_elements,)
        Reference volume, mm^3 (full ring for quads).
    b, hoop, gamma : ndarray
        Mean gradients (n_e, n, dim) 1/mm, hoop weights (n_e, 4) 1/mm (quads; (0, 0) for
        hexahedra), hourglass vectors (n_e, n_modes, n).
    mass_weights : ndarray (n_elements, n)
        Integral of N_a dV, mm^3 (row-sum lumping).
    length : ndarray (n_elements,)
        Reference characteristic length, mm.
    hourglass_stiffness : ndarray (n_elements,)
        k_e = Q mu_0 V_e (b:b), N/mm.
    bulk_linear, bulk_quadratic : ndarray (n_elements,)
        b1 rho c_d L (MPa s) and rho (b2 L)^2 (MPa s^2), reference values.
    bulk_viscosity_linear : float
        b1, dimensionless (reduces the stable step by sqrt(1 + b1^2) - b1).
    kernel : str
        ``"fast"`` or ``"reference"``.
    n_history : int
        History fields per element: n_comp (1 + MAX_PRONY_TERMS) + 2 with n_comp = 4
        (quad) or 6: the Prony history, then J^n - 1 and the volumetric rate (``_rate``).
    fibre_frame : ndarray (n_elements, 6)
        Per element two orthogonal unit vectors (m, n) of the lamellar plane in the
        reference configuration, (m_1, m_2, m_3, n_1, n_2, n_3): the fibre families of a
        fibre material lie along cos(angle) m +- sin(angle) n. Quads: m = (m_r, m_z, 0) in
        the section and n = (0, 0, 1) the hoop direction. Zero rows for elements whose
        material has no fibres.
    """

    kind: str
    points: np.ndarray
    cells: np.ndarray
    element_material: np.ndarray
    material_table: np.ndarray
    volume: np.ndarray
    b: np.ndarray
    hoop: np.ndarray
    gamma: np.ndarray
    mass_weights: np.ndarray
    length: np.ndarray
    hourglass_stiffness: np.ndarray
    bulk_linear: np.ndarray
    bulk_quadratic: np.ndarray
    bulk_viscosity_linear: float
    kernel: str
    n_history: int
    fibre_frame: np.ndarray = None
    fast: object = None

    @property
    def n_elements(self) -> int:
        return self.cells.shape[0]

    @property
    def block_size(self) -> int:
        """Elements per block of the history and the fast kernels (32 quads, 16 hexahedra)."""
        return BLOCK_SIZES[self.kind]

    @property
    def n_blocks(self) -> int:
        return -(-self.n_elements // self.block_size)


def _check_inputs(points, cells, cell_type, element_material, material_table):
    if cell_type not in KINDS:
        raise InputError(f"cell_type {cell_type!r}: expected 'quad' or 'hexahedron'")
    n_per, dim = KINDS[cell_type]
    points = np.ascontiguousarray(points, dtype=np.float64)
    cells = np.ascontiguousarray(cells, dtype=np.int64)
    element_material = np.ascontiguousarray(element_material, dtype=np.int64)
    table = np.ascontiguousarray(material_table, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != dim:
        raise InputError(f"points: expected shape (n_nodes, {dim}) for {cell_type}, "
                         f"got {points.shape}")
    if cells.ndim != 2 or cells.shape[1] != n_per:
        raise InputError(f"cells: expected shape (n_elements, {n_per}) for {cell_type}, "
                         f"got {cells.shape}")
    if cells.size and (cells.min() < 0 or cells.max() >= points.shape[0]):
        raise InputError(f"cells: node index outside 0..{points.shape[0] - 1}")
    if element_material.shape != (cells.shape[0],):
        raise InputError(f"element_material: expected shape ({cells.shape[0]},), "
                         f"got {element_material.shape}")
    if table.ndim != 2 or table.shape[1] != N_PARAMETERS:
        raise InputError(f"material_table: expected shape (n_materials, {N_PARAMETERS})")
    if element_material.size and (element_material.min() < 0
                                  or element_material.max() >= table.shape[0]):
        raise InputError(f"element_material: index outside 0..{table.shape[0] - 1}")
    for m, row in enumerate(table):
        if not (row[P_DENSITY] > 0.0 and row[P_D1] > 0.0):
            raise InputError(f"material_table row {m}: density and D1 must be > 0")
    return points, cells, element_material, table


def _check_fibre_frame(fibre_frame, cell_type, element_material, table):
    """The (n_e, 6) fibre frame: zeros where the material has no fibres; InputError unless
    every element of a fibre material has two orthogonal unit vectors (quads: m in the
    section, n = e_theta)."""
    n_e = element_material.shape[0]
    fibrous = table[element_material, P_FIBRE_K1] > 0.0
    if fibre_frame is None:
        if np.any(fibrous):
            raise InputError("fibre_frame: a fibre material (k1 > 0) needs the fibre directions "
                             "of its elements; none were given")
        return np.zeros((n_e, 6))
    frame = np.array(fibre_frame, dtype=np.float64)
    if frame.shape != (n_e, 6):
        raise InputError(f"fibre_frame: expected shape ({n_e}, 6), got {frame.shape}")
    frame[~fibrous] = 0.0
    m, n = frame[fibrous, :3], frame[fibrous, 3:]
    tolerance = 1e-9
    if not (np.all(np.abs(np.einsum("ei,ei->e", m, m) - 1.0) < tolerance)
            and np.all(np.abs(np.einsum("ei,ei->e", n, n) - 1.0) < tolerance)
            and np.all(np.abs(np.einsum("ei,ei->e", m, n)) < tolerance)):
        raise InputError("fibre_frame: expected two orthogonal unit vectors (m, n) per element "
                         "of a fibre material")
    if cell_type == "quad" and not (np.all(m[:, 2] == 0.0) and np.all(n[:, 2] == 1.0)):
        raise InputError("fibre_frame: for quads m must lie in the (r, z) section and n be the "
                         "hoop direction (0, 0, 1)")
    return np.ascontiguousarray(frame)


def prepare(points, cells, cell_type, element_material, material_table,
            hourglass_coefficient=0.1, bulk_viscosity_linear=0.06,
            bulk_viscosity_quadratic=1.2, kernel="fast", fibre_frame=None):
    """Precompute the reference data of a mesh of one element type.

    Parameters
    ----------
    points : array (n_nodes, 2 | 3)
        Reference coordinates, mm ((r, z) for quads).
    cells : array (n_elements, 4 | 8) int
        Node indices.
    cell_type : {"quad", "hexahedron"}
    element_material : array (n_elements,) int
        Row of ``material_table`` per element.
    material_table : array (n_materials, N_PARAMETERS)
        From ``materials.kernel_table``.
    hourglass_coefficient : float or array (n_elements,)
        Q in k_e = Q mu_0 V_e (b:b), dimensionless (per element: ``solver._hourglass``).
    bulk_viscosity_linear, bulk_viscosity_quadratic : float
        b1 and b2, dimensionless (Abaqus defaults 0.06 and 1.2).
    kernel : {"fast", "reference"}
        Which kernels evaluate forces (same results to round-off).
    fibre_frame : array (n_elements, 6), optional
        The lamellar frame (m, n) of each element (``ElementSet.fibre_frame``); needed when
        a material has fibres (k1 > 0), ignored for the other elements.

    Returns
    -------
    ElementSet
    """
    points, cells, element_material, table = _check_inputs(
        points, cells, cell_type, element_material, material_table)
    if kernel not in ("fast", "reference"):
        raise InputError(f"kernel {kernel!r}: expected 'fast' or 'reference'")
    for name, value in (("hourglass_coefficient", hourglass_coefficient),
                        ("bulk_viscosity_linear", bulk_viscosity_linear),
                        ("bulk_viscosity_quadratic", bulk_viscosity_quadratic)):
        if not np.all(np.asarray(value) >= 0.0):
            raise InputError(f"{name}: expected >= 0, got {value}")
    X = points[cells]
    if cell_type == "quad":
        ref = _geometry.quad_reference(X)
        hoop = ref["hoop"]
    else:
        ref = _geometry.hex_reference(X)
        hoop = np.zeros((0, 0))
    mat = table[element_material]
    mu0 = 2.0 * (mat[:, P_C10] + mat[:, P_C01])
    bulk = 2.0 / mat[:, P_D1]
    c_d = np.sqrt((bulk + 4.0 / 3.0 * np.abs(mu0)) / mat[:, P_DENSITY])
    bb = np.einsum("eai,eai->e", ref["b"], ref["b"])
    length = ref["length"]
    elements = ElementSet(
        kind=cell_type, points=points, cells=cells, element_material=element_material,
        material_table=table, volume=ref["volume"], b=np.ascontiguousarray(ref["b"]),
        hoop=np.ascontiguousarray(hoop), gamma=np.ascontiguousarray(ref["gamma"]),
        mass_weights=ref["mass_weights"], length=length,
        hourglass_stiffness=hourglass_coefficient * np.abs(mu0) * ref["volume"] * bb,
        bulk_linear=bulk_viscosity_linear * mat[:, P_DENSITY] * c_d * length,
        bulk_quadratic=mat[:, P_DENSITY] * (bulk_viscosity_quadratic * length) ** 2,
        bulk_viscosity_linear=float(bulk_viscosity_linear), kernel=kernel,
        n_history=(4 if cell_type == "quad" else 6) * (MAX_PRONY_TERMS + 1) + 2,
        fibre_frame=_check_fibre_frame(fibre_frame, cell_type, element_material, table))
    if kernel == "fast":
        from corneasim.solver.elements import _fast
        elements.fast = _fast.pack(elements, elements.block_size)
    return elements


def new_history(elements: ElementSet) -> np.ndarray:
    """Zero history, float64 (n_blocks, n_history, block_size); opaque to the integrator."""
    return np.zeros((elements.n_blocks, elements.n_history, elements.block_size))


def lumped_masses(elements: ElementSet, density_scale=None) -> np.ndarray:
    """Row-sum lumped nodal masses (n_nodes,), tonne: m_a = sum_e s_e rho_e int N_a dV.

    ``density_scale`` (n_elements,) >= 1 multiplies each element's density (mass scaling).
    """
    rho = elements.material_table[elements.element_material, P_DENSITY]
    if density_scale is not None:
        density_scale = np.asarray(density_scale, dtype=np.float64)
        if density_scale.shape != rho.shape:
            raise InputError(f"density_scale: expected shape {rho.shape}, "
                             f"got {density_scale.shape}")
        rho = rho * density_scale
    masses = np.zeros(elements.points.shape[0])
    _assemble_masses(elements.cells, rho, elements.mass_weights, masses)
    return masses


@njit(cache=True)
def _assemble_masses(cells, rho, weights, masses):
    """masses[cells[e, a]] += rho[e] weights[e, a] (``np.add.at`` took 1.3 ms per call on the
    needle mesh, and variable mass scaling calls this after every deletion)."""
    for e in range(cells.shape[0]):
        for a in range(cells.shape[1]):
            masses[cells[e, a]] += rho[e] * weights[e, a]


def stable_time_steps(elements: ElementSet, u) -> np.ndarray:
    """Element stable time steps (n_elements,), s, without safety factor or mass scaling.

    dt_e = (L_e / c_e)(sqrt(1 + b1^2) - b1) with L_e the current characteristic length
    (quad: area / longest diagonal; hexahedron: the Flanagan-Belytschko bound
    1 / sqrt(2 sum_a |grad_x N_a|^2), h / sqrt(3) for a cube) and c_e the
    current dilatational wave speed sqrt((K max(J, 1) + 4/3 mu_t + M_f) / rho) with the
    instantaneous (unrelaxed) moduli and the fibres' current tangent M_f
    (``_time_step``). With density scale s_e the step is dt_e sqrt(s_e).
    """
    out = np.empty(elements.n_elements)
    u = np.ascontiguousarray(u, dtype=np.float64)
    if elements.kind == "quad":
        quad_stable_time_steps(elements.points, elements.cells, elements.b, elements.hoop,
                               elements.element_material, elements.material_table,
                               elements.fibre_frame, u, elements.bulk_viscosity_linear, out,
                               kernel_threads(elements))
    else:
        hex_stable_time_steps(elements.points, elements.cells, elements.b, elements.element_material,
                              elements.material_table, elements.fibre_frame, u,
                              elements.bulk_viscosity_linear, out, kernel_threads(elements))
    return out


def eval_internal_forces(elements: ElementSet, u, dt, alive, history, f_int,
                         failure_ratio, energy_rates, relaxed: bool = False):
    """Internal nodal forces and per-element failure ratios; advances the element history.

    Parameters
    ----------
    u : ndarray (n_nodes, dim)
        Displacement at the new time, mm.
    dt : float
        The step just taken, s: the Prony terms relax over it and the volumetric rate of
        bulk viscosity is the change of J over it (``_rate``). 0 evaluates without
        advancing the history (same rate as the last step).
    alive : ndarray (n_elements,) uint8 or bool
        1 = alive; dead elements give zero force and keep their history.
    history : ndarray
        From ``new_history``; updated in place.
    f_int : ndarray (n_nodes, dim)
        Out: internal forces, N (full ring for quads).
    failure_ratio : ndarray (n_elements,)
        Out: criterion / limit (0 for dead elements or no criterion).
    energy_rates : ndarray (3,)
        Out: the hourglass energy (mJ: stiffness-type hourglass control stores
        k_e |q|^2 / 2) and the bulk-viscous and viscoelastic dissipation power (mJ/s).
    relaxed : bool
        The Prony terms relax fully within the step (``step_prony_coefficients``): the
        long-term stress, for a preload that stands for a load held long before.
    """
    if elements.fast is not None:
        from corneasim.solver.elements import _fast
        _fast.internal_forces(elements, float(dt), u, alive, history, f_int, failure_ratio,
                              energy_rates, relaxed)
        return
    prony_a, prony_b = step_prony_coefficients(elements.material_table, float(dt), relaxed)
    _reference.internal_forces_reference(
        elements.points, elements.cells, elements.b, elements.hoop, elements.gamma,
        elements.volume, elements.hourglass_stiffness, elements.bulk_linear,
        elements.bulk_quadratic, elements.element_material, elements.material_table,
        elements.fibre_frame, prony_a, prony_b, elements.block_size, u, float(dt), alive, history,
        f_int,
        failure_ratio, energy_rates)


def element_stress(elements: ElementSet, u, history) -> np.ndarray:
    """Cauchy stress (n_elements, 6), MPa, [xx, yy, zz, xy, yz, zx]; quads [rr, zz, thth, rz, 0, 0].

    Material stress from u and the stored Prony history (no bulk viscosity). Field output.
    """
    cauchy = np.zeros((elements.n_elements, 6))
    _reference.stress_reference(elements.points, elements.cells, elements.b, elements.hoop,
                                elements.element_material, elements.material_table,
                                elements.fibre_frame, elements.block_size,
                                np.asarray(u, dtype=np.float64), history,
                                cauchy)
    return cauchy


def element_jacobians(elements: ElementSet, u) -> np.ndarray:
    """J = det F at the element centre (mean gradient), (n_elements,); parallel kernel
    (threads: ``_schedule.kernel_threads``)."""
    out = np.empty(elements.n_elements)
    centre_jacobians(elements.cells, elements.b, elements.hoop, np.asarray(u, dtype=np.float64), out,
                     kernel_threads(elements))
    return out


def stored_energy(elements: ElementSet, u) -> float:
    """Elastic (instantaneous) plus hourglass energy, mJ; for checks (no Prony terms).

    sum_e V_e W(F_e) + k_e/2 sum_alpha |q_alpha|^2, W with the fibre families' energy.
    """
    return _stored_energy(elements.points, elements.cells, elements.b, elements.hoop,
                          elements.gamma, elements.volume, elements.hourglass_stiffness,
                          elements.element_material, elements.material_table,
                          elements.fibre_frame, np.asarray(u, dtype=np.float64))


@njit(cache=True)
def _stored_energy(points, cells, b, hoop, gamma, volume, stiffness, element_material, table,
                   fibre_frame, u):
    total = 0.0
    F = np.empty((3, 3))
    dim = points.shape[1]
    for e in range(cells.shape[0]):
        _reference._deformation_gradient(cells, b, hoop, u, e, F)
        total += volume[e] * elastic_energy(F, table[element_material[e]], fibre_frame[e])
        for mode in range(gamma.shape[1]):
            for i in range(dim):
                q = 0.0
                for a in range(cells.shape[1]):
                    q += gamma[e, mode, a] * u[cells[e, a], i]
                total += 0.5 * stiffness[e] * q * q
    return total
