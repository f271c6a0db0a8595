"""The static model: everything about a simulation that does not change during the run.

Built once from a :class:`~corneasim.mesh.Mesh`, a material per block, boundary conditions
and pressures, and not changed afterwards: everything a run changes (element deletion and
damage, the time, displacements and forces, the masses of variable mass scaling, released
pressure amplitudes, event times) lives in the :class:`~corneasim.solver.State`, which starts
from the model's values (:func:`~corneasim.solver.new_state`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from corneasim.errors import InputError
from corneasim.materials import KernelMaterial, kernel_table
from corneasim.materials._kernel_form import FAILURE_VON_MISES
from corneasim.mesh import Mesh
from corneasim.solver import elements as element_kernels
from corneasim.mesh import element_sizes
from corneasim.solver._deletion import reference_corner_inverse
from corneasim.solver._softening import Softening
from corneasim.solver._cyclic import pair_copies
from corneasim.solver._loads import pack_constraints, pack_pressures
from corneasim.solver._stable_step import (
    check_fixed_time_step, density_scale_for_target, stable_time_step)


@dataclass
class Model:
    """Static data of a simulation (arrays are read-only by convention).

    Attributes
    ----------
    mesh : Mesh
        Reference geometry, blocks and sets.
    elements : corneasim.solver.elements.ElementSet
        Reference data of the element kernels (opaque).
    material_table : ndarray (n_blocks, N_PARAMETERS) float64
        Kernel material of each block (row = block index).
    element_material : ndarray (n_elements,) int64
        Row of ``material_table`` of each element (its block).
    density_scale : ndarray (n_elements,) float64
        Mass-scaling factor of each element's density in the reference configuration, >= 1
        (a run starts from it; variable mass scaling raises the state's copy).
    mass : ndarray (n_nodes,) float64
        Lumped scaled nodal masses in the reference configuration, tonne (full ring when
        axisymmetric).
    dof_mass, dof_inverse_mass : ndarray (n_nodes * dim,) float64
        The masses repeated per dof (tonne) and their inverses (0 for nodes in no element),
        1/tonne.
    added_mass_fraction : float
        (scaled mass - physical mass) / physical mass in the reference configuration,
        dimensionless.
    element_time_step : ndarray (n_elements,) float64
        Unscaled element stable steps in the reference configuration, s.
    safety_factor : float
        Fraction of the stable step used, dimensionless.
    target_time_step : float or None
        Mass-scaling target Δt*, s (None: no mass scaling).
    variable_mass_scaling : bool
        Re-apply mass scaling in the deformed geometry whenever the stable step is recomputed
        (elements crushed below Δt* get denser; Abaqus/Explicit's scaling "throughout the step").
    physical_mass_total : float
        Total unscaled mass, tonne (for ``added_mass_fraction``).
    distortion_limit : float
        Element erosion: a live element whose smallest corner Jacobian ratio falls below this
        is deleted (``_deletion.delete_distorted_elements``), dimensionless; 0 switches it off.
    corner_inverse : ndarray (n_elements, 4 | 8) float64
        1 / reference corner Jacobians for the distortion control (empty when it is off).
    softening : Softening or None
        Fracture energies and sizes of the softening elements (``_softening``; their material
        rows are the state's); None when no block has a fracture energy (every failure is brittle).
    time_step : float or None
        User-fixed step, s (None: the stable step, recomputed every ``time_step_every`` steps).
    time_step_every : int
        Steps between recomputations of the stable step in the current geometry.
    constraint_dof, constraint_kind, constraint_amplitude, constraint_set : ndarray (n_c,) int64
        Constrained dof (node * dim + component), kind (``_loads.FIXED`` ...), amplitude row,
        index into ``constraint_set_names``.
    constraint_value : ndarray (n_c,) float64
        Imposed displacement (mm) or velocity (mm/s) before the amplitude.
    constraint_set_names : list of str
        Node sets that carry constraints (reaction-force output).
    amplitude_table : ndarray (n_amp, width) float64
        Packed amplitudes of the constraints.
    dof_constrained : ndarray (n_nodes, dim) uint8
        1 where a dof is constrained.
    cyclic_master, cyclic_slave : ndarray (n_pairs,) int64
        Node pairs (x, 0, z), (-x, 0, z) of a cyclic-symmetry cut plane (``_cyclic``; empty
        without one).
    cyclic_held : ndarray (n_pairs, 3) uint8
        1 where both nodes of a pair have the component fixed.
    free_translation : ndarray (dim,) uint8 or None
        Components in which the whole model may translate (held by elastic supports, not
        fixed): the mass-proportional damping acts on the velocity relative to the model's
        mean velocity in them (``_integrate.integrate_acceleration``; ``State.reference_velocity``).
        None: no such component.
    radial_cracks : corneasim.fracture.RadialCracks or None
        The cut band of an axisymmetric model (``fracture._cut_band``): elements the fast kernels
        skip and a pass of their own evaluates, with smeared radial cracks; None without one.
    pressure_face_nodes : ndarray (n_faces, 2 | 4) int64
    pressure_face_element : ndarray (n_faces,) int64
    pressure_value : ndarray (n_faces,) float64
        MPa.
    pressure_amplitude : ndarray (n_faces,) int64
    pressure_amplitude_table : ndarray (n_amp, width) float64
    """

    mesh: Mesh
    elements: object
    material_table: np.ndarray
    element_material: np.ndarray
    density_scale: np.ndarray
    mass: np.ndarray
    dof_mass: np.ndarray
    dof_inverse_mass: np.ndarray
    added_mass_fraction: float
    element_time_step: np.ndarray
    safety_factor: float
    time_step: float | None
    time_step_every: int
    constraint_dof: np.ndarray
    constraint_kind: np.ndarray
    constraint_value: np.ndarray
    constraint_amplitude: np.ndarray
    constraint_set: np.ndarray
    constraint_set_names: list[str]
    amplitude_table: np.ndarray
    dof_constrained: np.ndarray
    pressure_face_nodes: np.ndarray
    pressure_face_element: np.ndarray
    pressure_value: np.ndarray
    pressure_amplitude: np.ndarray
    pressure_amplitude_table: np.ndarray
    target_time_step: float | None = None
    variable_mass_scaling: bool = False
    physical_mass_total: float = 0.0
    distortion_limit: float = 0.0
    corner_inverse: np.ndarray | None = None
    softening: object = None
    cyclic_master: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    cyclic_slave: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    cyclic_held: np.ndarray = field(default_factory=lambda: np.zeros((0, 3), np.uint8))
    free_translation: np.ndarray | None = None
    radial_cracks: object = None

    @property
    def n_nodes(self) -> int:
        return self.mesh.n_nodes

    @property
    def n_elements(self) -> int:
        return self.mesh.n_elements

    @property
    def dim(self) -> int:
        return self.mesh.dim

    @cached_property
    def constraint_node(self) -> np.ndarray:
        """Node of each constrained dof, (n_c,) int64."""
        return self.constraint_dof // self.dim

    @cached_property
    def reaction_groups(self) -> list[tuple[str, int, np.ndarray]]:
        """(node set name, component, its constrained dofs) for each constrained set and component
        (the reaction outputs, ``_outputs.reaction_forces``)."""
        groups = []
        for index, name in enumerate(self.constraint_set_names):
            for component in range(self.dim):
                rows = (self.constraint_set == index) & (self.constraint_dof % self.dim == component)
                if rows.any():
                    groups.append((name, component, self.constraint_dof[rows]))
        return groups

    def block_of(self, element: int) -> str:
        """Name of the block of ``element``."""
        return self.mesh.block_names[int(self.mesh.element_block[element])]

    def stable_time_step(self, alive=None) -> tuple[float, int]:
        """Reference-configuration stable step with safety factor (s) and its element."""
        alive = np.ones(self.n_elements, np.uint8) if alive is None else alive
        return stable_time_step(self.element_time_step, self.density_scale, alive, self.safety_factor)


def build_model(mesh: Mesh, materials: dict[str, KernelMaterial], boundary_conditions=(),
                pressures=(), *, safety_factor: float = 0.9, target_time_step: float | None = None,
                time_step: float | None = None, time_step_every: int = 100,
                variable_mass_scaling: bool = False, distortion_limit: float = 0.0,
                fracture_energy: dict[str, float] | None = None, free_translation=(),
                node_copies: np.ndarray | None = None,
                hourglass_coefficient: float = 0.1, bulk_viscosity_linear: float = 0.06,
                bulk_viscosity_quadratic: float = 1.2) -> Model:
    """Build the static model.

    Parameters
    ----------
    mesh : Mesh
        Validated here.
    materials : dict of str to KernelMaterial
        One material per block name of the mesh.
    boundary_conditions : sequence of Fixed, SymmetryPlane, CyclicSymmetry, Prescribed
        See :mod:`corneasim.solver._loads`; the axis of an axisymmetric mesh is held
        automatically (u_r = 0 at r = 0).
    pressures : sequence of Pressure
        Follower pressures on surface sets.
    safety_factor : float
        Fraction of the stable step, 0 < s <= 1 (default 0.9).
    target_time_step : float, optional
        Mass-scaling target Δt*, s: elements below it are made heavier to reach it.
    variable_mass_scaling : bool
        Also scale, during the run, elements whose deformed stable step falls below
        ``target_time_step`` (:func:`corneasim.solver._mass_scaling.rescale_masses`).
    time_step : float, optional
        Fixed time step, s; InputError if above the stable step (after mass scaling).
    time_step_every : int
        Steps between stable-step updates in the current geometry (default 100).
    distortion_limit : float
        Erode elements whose smallest corner Jacobian ratio falls below this, 0 <= value < 1
        (dimensionless; 0: off). See :mod:`corneasim.solver._deletion`.
    fracture_energy : dict of str to float, optional
        G_f per block name, N/mm (= mJ/mm^2): elements of these blocks soften after their
        failure criterion is met and dissipate G_f / h_e per unit volume before they are
        deleted (crack band, :mod:`corneasim.solver._softening`); needs a von Mises failure
        criterion. Blocks not given (or 0) fail brittle.
    free_translation : sequence of int
        Components (0, 1, 2 = x, y, z or r, z) in which the model may translate as a whole
        (held by elastic supports, not fixed): the mass-proportional damping spares the
        translation there (``Model.free_translation``); empty: none.
    node_copies : ndarray (n_pairs, 2) int64, optional
        (original, copy) node pairs of a mesh split along a surface
        (:func:`corneasim.fracture.split_nodes`): the copies of two nodes paired by cyclic
        symmetry are paired too (they sit where their originals do).
    hourglass_coefficient, bulk_viscosity_linear, bulk_viscosity_quadratic : float
        Passed to the element kernels (dimensionless); the hourglass coefficient may be one
        per element (``physical_hourglass_coefficients``).
    """
    mesh.validate()
    missing = [name for name in mesh.block_names if name not in materials]
    if missing:
        raise InputError(f"no material for block '{missing[0]}' (blocks: {', '.join(mesh.block_names)})")
    unknown = [name for name in materials if name not in mesh.block_names]
    if unknown:
        raise InputError(f"material given for block '{unknown[0]}', which is not in the mesh "
                         f"(blocks: {', '.join(mesh.block_names)})")
    if not 0.0 < safety_factor <= 1.0:
        raise InputError(f"safety_factor: expected 0 < value <= 1, got {safety_factor}")
    if not 0.0 <= distortion_limit < 1.0:
        raise InputError(f"distortion_limit: expected 0 <= value < 1, got {distortion_limit}")
    fracture_energy = dict(fracture_energy or {})
    for name, value in fracture_energy.items():
        if name not in mesh.block_names:
            raise InputError(f"fracture_energy: no block '{name}' (blocks: {', '.join(mesh.block_names)})")
        if not value >= 0.0:
            raise InputError(f"fracture_energy of block '{name}': expected an energy >= 0 N/mm, got {value}")
        material = materials.get(name)
        if value > 0.0 and material is not None and not (
                material.failure_criterion == FAILURE_VON_MISES and material.failure_limit > 0.0):
            raise InputError(f"fracture_energy of block '{name}': softening needs a von Mises failure "
                             "criterion with a limit > 0 (the damage scales the isochoric stress only)")
    if int(time_step_every) < 1:
        raise InputError(f"time_step_every: expected an integer >= 1, got {time_step_every}")
    table = kernel_table([materials[name] for name in mesh.block_names])
    element_material = np.ascontiguousarray(mesh.element_block, dtype=np.int64)
    elements = element_kernels.prepare(
        mesh.points, mesh.cells, mesh.cell_type, element_material, table,
        hourglass_coefficient=hourglass_coefficient, bulk_viscosity_linear=bulk_viscosity_linear,
        bulk_viscosity_quadratic=bulk_viscosity_quadratic)
    element_dt = element_kernels.stable_time_steps(elements, np.zeros_like(mesh.points))
    density_scale = density_scale_for_target(element_dt, target_time_step, safety_factor)
    physical_mass = element_kernels.lumped_masses(elements, np.ones(mesh.n_elements))
    mass = element_kernels.lumped_masses(elements, density_scale)
    inverse_mass = np.divide(1.0, mass, out=np.zeros_like(mass), where=mass > 0)
    constraints = pack_constraints(mesh, boundary_conditions)
    pressure = pack_pressures(mesh, pressures)
    dof_constrained = np.zeros(mesh.n_nodes * mesh.dim, np.uint8)
    dof_constrained[constraints["dof"]] = 1
    model = Model(
        mesh=mesh, elements=elements, material_table=table, element_material=element_material,
        density_scale=density_scale, mass=mass, dof_mass=np.repeat(mass, mesh.dim),
        dof_inverse_mass=np.repeat(inverse_mass, mesh.dim),
        added_mass_fraction=float((mass.sum() - physical_mass.sum()) / physical_mass.sum()),
        element_time_step=element_dt, safety_factor=float(safety_factor),
        time_step=None if time_step is None else float(time_step),
        time_step_every=int(time_step_every),
        constraint_dof=constraints["dof"], constraint_kind=constraints["kind"],
        constraint_value=constraints["value"], constraint_amplitude=constraints["amplitude"],
        constraint_set=constraints["set_index"], constraint_set_names=constraints["set_names"],
        amplitude_table=constraints["amplitude_table"],
        dof_constrained=dof_constrained.reshape(mesh.n_nodes, mesh.dim),
        pressure_face_nodes=pressure["face_nodes"], pressure_face_element=pressure["face_element"],
        pressure_value=pressure["value"], pressure_amplitude=pressure["amplitude"],
        pressure_amplitude_table=pressure["amplitude_table"],
        target_time_step=None if target_time_step is None else float(target_time_step),
        variable_mass_scaling=bool(variable_mass_scaling) and target_time_step is not None,
        physical_mass_total=float(physical_mass.sum()), distortion_limit=float(distortion_limit),
        corner_inverse=(reference_corner_inverse(mesh.points, mesh.cells) if distortion_limit > 0.0
                        else np.zeros((0, mesh.cells.shape[1]))),
        cyclic_master=constraints["cyclic_master"], cyclic_slave=constraints["cyclic_slave"],
        cyclic_held=constraints["cyclic_held"])
    block_energy = np.array([float(fracture_energy.get(name, 0.0)) for name in mesh.block_names])
    if np.any(block_energy > 0.0):
        model.softening = Softening(elements, block_energy[mesh.element_block],
                                    element_sizes(mesh.points, mesh.cells))
    if len(free_translation):
        model.free_translation = np.zeros(mesh.dim, np.uint8)
        model.free_translation[list(free_translation)] = 1
    if node_copies is not None:
        pair_copies(model, np.asarray(node_copies, dtype=np.int64))
    if time_step is not None:
        if not time_step > 0:
            raise InputError(f"time_step: expected a step > 0 s, got {time_step}")
        stable, element = model.stable_time_step()
        check_fixed_time_step(time_step, stable, element, model.block_of(element), 0.0)
    return model

