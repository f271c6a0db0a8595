"""From a validated :class:`~corneasim.scenarios._format.Scenario` to a runnable model.

:func:`build` makes the mesh (a built-in eye or an imported file), checks it, loads the
materials of its blocks, turns constraints and pressures into solver loads, builds the
model (with mass scaling), and places the instrument with its contact hook. Every
mismatch between the scenario and the mesh (a block without a material, a set that does
not exist) is an :class:`~corneasim.errors.InputError` naming it.
"""

from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from corneasim.errors import InputError
from corneasim.materials import KernelMaterial, load_material
from corneasim.materials.kernel import FAILURE_NONE
from corneasim.mesh import Mesh, check_elements, lamellar_frames, mesh_3d, mesh_axisymmetric, read_mesh
from corneasim.fracture import CutAxis, cut_radius, make_radial_cut, make_ties, split_cornea
from corneasim.scenarios._cut_punctures import CutPunctures
from corneasim.scenarios._history_requests import HistoryProbe
from corneasim.scenarios._kinds import scenario_kind
from corneasim.scenarios._pressure_release import PressureRelease
from corneasim.scenarios._punctures import PunctureEvents, TieEvents
from corneasim.scenarios._format import Scenario
from corneasim.scenarios._time_scaling import scaled_material, scaled_scenario
from corneasim.solver import (
    CyclicSymmetry, DistortionCheck, physical_hourglass_coefficients, ElasticSupport, Fixed, Model, Prescribed, Pressure, SymmetryPlane, build_model,
    check_support_stability, critical_dashpot)
from corneasim.solver import component_index
from corneasim.solver import shifted
from corneasim.fracture import CohesiveTies, EdgeWork
from corneasim.contact import InstrumentContact
from corneasim.instruments import edge_surface_height, tip_height_for_gap
from corneasim.instruments import Motion


@dataclass
class Setup:
    """Everything a run needs, built from a scenario.

    Attributes
    ----------
    scenario : Scenario
        In solver time (``solver.time_scaling`` applied, see :func:`procedure_time`).
    mesh : Mesh
    model : Model
    instrument : InstrumentContact or None
        The contact hook of the instrument (None without instrument).
    preload_duration : float
        Length of the preload stage, s (0 without preload); the procedure starts then.
    warnings : list of str
        Warnings met while building (unstable material, friction law validity ...) and running.
    preload_end : dict or None
        How settled the model was when the preload ended (``postprocess.preload_report``).
    steps_before : int
        Steps taken before this process started (a resumed checkpoint, a reused preload):
        the throughput counts only the steps this process took.
    cohesive : CohesiveTies or None
        The ties of a cohesive cut (``fracture._cohesive_cut``; None without one).
    edge_work : EdgeWork or None
        The instrument's work on the ties (``fracture._edge_work``; None without ties or
        instrument).
    tie_events : TieEvents or None
        The puncture events of a cohesive cut, read from its ties (then ``punctures`` is None).
    supports : list of ElasticSupport
        The elastic supports (``supports``), hooks of the time loop.
    punctures : PunctureEvents or None
        The puncture events of the procedure (``scenarios._punctures``; None without an
        instrument or with a cut).
    cut : CutAxis or None
        The axis hook of a cut band (``[cut]``, ``fracture._cut_band``; None without one).
    cut_punctures : CutPunctures or None
        The puncture events of a cut band with an instrument (``scenarios._cut_punctures``).
    pressure_release : PressureRelease or None
        Releases the pressures with ``release_on_puncture`` when the cornea is cut through
        (``scenarios._pressure_release``, in the state; None when no pressure has it).
    """

    scenario: Scenario
    mesh: Mesh
    model: Model
    instrument: InstrumentContact | None
    preload_duration: float
    warnings: list[str] = field(default_factory=list)
    preload_end: dict | None = None
    steps_before: int = 0
    cohesive: CohesiveTies | None = None
    edge_work: EdgeWork | None = None
    tie_events: TieEvents | None = None
    supports: list[ElasticSupport] = field(default_factory=list)
    pressure_release: PressureRelease | None = None
    punctures: PunctureEvents | None = None
    probe: HistoryProbe | None = None
    distortion: DistortionCheck | None = None
    cut: CutAxis | None = None
    cut_punctures: CutPunctures | None = None

    def procedure_time(self, solver_time: float) -> float:
        """Physical procedure time (s, 0 when the instrument starts) of a solver time (s):
        t = lambda (t_solver - preload duration), lambda = ``solver.time_scaling``."""
        return (solver_time - self.preload_duration) * self.scenario.solver.time_scaling

    def solver_time(self, procedure_time: float) -> float:
        """Solver time (s) of a physical procedure time (s): the inverse of
        :meth:`procedure_time`."""
        return procedure_time / self.scenario.solver.time_scaling + self.preload_duration

    @property
    def kind(self):
        """The scenario kind's object (:mod:`corneasim.scenarios._kinds`)."""
        return scenario_kind(self.scenario.kind)

    @property
    def events(self) -> tuple:
        """Event terms of the procedure's time loop: the puncture events (with an instrument),
        then the pressure release (with ``release_on_puncture``)."""
        if self.instrument is None:
            return ()
        return tuple(term for term in (self.punctures, self.pressure_release) if term is not None)

    @property
    def hooks(self) -> tuple:
        """External-force hooks for the solver loop."""
        work = self.edge_work
        return tuple(hook for hook in (work and work.before, self.instrument, work, self.cut, self.cut_punctures,
                                       self.cohesive, self.tie_events, *self.supports, self.probe, self.distortion)
                     if hook is not None)


def make_mesh(scenario: Scenario, base_dir: Path) -> Mesh:
    """The scenario's mesh: generated or read, then checked (positive Jacobians)."""
    source = scenario.mesh
    if source.generator == "eye-axisymmetric":
        mesh = mesh_axisymmetric(source.geometry, source.preset)
    elif source.generator == "eye-3d":
        cut = scenario.cohesive_cut
        mesh = mesh_3d(source.geometry, source.strategy, source.preset,
                       cut_radius=cut_radius(scenario) if cut is not None else None,
                       cut_element_width=cut.element_width if cut is not None else None)
    else:
        path = Path(source.file)
        mesh = read_mesh(path if path.is_absolute() else base_dir / path, axisymmetric=source.axisymmetric)
    mesh.validate()
    check_elements(mesh)
    return mesh


def with_reference(mesh: Mesh, points: np.ndarray) -> Mesh:
    """``mesh`` on other reference coordinates (n_nodes, dim), mm, checked for positive Jacobians."""
    points = np.asarray(points, dtype=float)
    if points.shape != mesh.points.shape:
        raise InputError(f"stress-free reference: {points.shape[0]} nodes of dimension {points.shape[-1]} for a "
                         f"mesh of {mesh.n_nodes} nodes of dimension {mesh.dim}")
    moved = dataclasses.replace(mesh, points=points)
    check_elements(moved)
    return moved


def material_source(material: str, base_dir: Path) -> str:
    """A preset name as is; a relative material file path (``.toml`` or with a ``/``) from ``base_dir``."""
    path = Path(material)
    if (material.endswith(".toml") or "/" in material or "\\" in material) and not path.is_absolute():
        return str(base_dir / path)
    return material


def load_materials(scenario: Scenario, mesh: Mesh, messages: list[str],
                   base_dir: Path = Path(".")) -> dict[str, KernelMaterial]:
    """Kernel materials per block; every block needs one, every assignment needs a block.

    Material files are read relative to ``base_dir`` (the scenario file's folder), like mesh files.
    """
    for block in scenario.materials:
        if block not in mesh.block_names:
            raise InputError(f"materials.{block}: the mesh has no block '{block}' "
                             f"(blocks: {', '.join(mesh.block_names)})")
    materials = {}
    for block in mesh.block_names:
        if block not in scenario.materials:
            raise InputError(f"materials: block '{block}' of the mesh has no material")
        assignment = scenario.materials[block]
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            spec = load_material(material_source(assignment.material, base_dir))
        messages.extend(f"materials.{block}: {warning.message}" for warning in caught)
        kernel = spec.kernel_form()
        if assignment.failure_limit is not None:
            kernel = dataclasses.replace(kernel, failure_limit=assignment.failure_limit)
        if not assignment.failure:
            kernel = dataclasses.replace(kernel, failure_criterion=FAILURE_NONE)
        materials[block] = scaled_material(kernel, scenario.solver.time_scaling)
    return materials


def make_loads(scenario: Scenario) -> tuple[list, list]:
    """Solver boundary conditions and pressures from the scenario tables."""
    conditions = []
    for constraint in scenario.constraints:
        if constraint.fixed:
            conditions.append(Fixed(constraint.node_set, constraint.fixed))
        elif constraint.symmetry is not None:
            conditions.append(SymmetryPlane(constraint.node_set, constraint.symmetry))
        elif constraint.cyclic is not None:
            conditions.append(CyclicSymmetry(constraint.node_set, constraint.cyclic))
        else:
            conditions.append(Prescribed(constraint.node_set, constraint.component, constraint.prescribed,
                                         constraint.value, constraint.amplitude.build()))
    pressures = [Pressure(load.surface, load.pressure, load.amplitude.build()) for load in scenario.pressures]
    return conditions, pressures


def check_reactions(scenario: Scenario, model: Model) -> None:
    """Every requested reaction output names a constrained node set and one of its constrained components."""
    names = "rz" if model.mesh.axisymmetric else "xyz"
    for k, output in enumerate(scenario.reactions):
        where = f"reactions[{k}] ('{output.name}')"
        if output.node_set not in model.constraint_set_names:
            raise InputError(f"{where}: node set '{output.node_set}' carries no constraint "
                             f"(constrained sets: {', '.join(model.constraint_set_names)})")
        if output.component not in names:
            raise InputError(f"{where}: component '{output.component}' is not one of {', '.join(names)}")
        rows = ((model.constraint_set == model.constraint_set_names.index(output.node_set))
                & (model.constraint_dof % model.dim == names.index(output.component)))
        if not np.any(rows):
            raise InputError(f"{where}: component '{output.component}' of node set '{output.node_set}' "
                             "is not constrained")


def make_supports(scenario: Scenario, model: Model) -> list[ElasticSupport]:
    """The elastic supports of the scenario, checked against the mesh, the constraints and the step."""
    supports = []
    time_step = model.stable_time_step()[0] if scenario.supports else 0.0
    for k, item in enumerate(scenario.supports):
        where = f"supports[{k}]"
        nodes = model.mesh.node_sets.get(item.node_set)
        if nodes is None:
            raise InputError(f"{where}: the mesh has no node set '{item.node_set}' "
                             f"(node sets: {', '.join(model.mesh.node_sets)})")
        component = component_index(item.component, model.mesh.axisymmetric, f"{where}.component")
        if np.any(model.dof_constrained[nodes, component]):
            raise InputError(f"{where}: component '{item.component}' of node set '{item.node_set}' is also "
                             "held by a constraint; support it or constrain it, not both")
        dashpot = critical_dashpot(item.damping_ratio, item.stiffness, float(model.mass.sum()))
        support = ElasticSupport(item.node_set, nodes, component, item.component, item.stiffness, dashpot)
        check_support_stability(support, model.mass, time_step, where)
        if item.held_in_preload and scenario.preload is not None:
            support.hold(scenario.preload.duration, model.mass, time_step)
        supports.append(support)
    return supports


def make_pressure_release(scenario: Scenario, instrument) -> PressureRelease | None:
    """The release of the pressures with ``release_on_puncture`` (None when there is none)."""
    released = [k for k, load in enumerate(scenario.pressures) if load.release_on_puncture]
    if not released:
        return None
    if instrument is None:
        raise InputError(f"pressures[{released[0]}].release_on_puncture: needs an [instrument] to cut through")
    durations = {scenario.pressures[k].release_duration for k in released}
    if len(durations) > 1:
        raise InputError(f"pressures[{released[-1]}].release_duration: released pressures need one duration")
    return PressureRelease(released, durations.pop())


def apex_height(mesh: Mesh) -> float:
    """Height (z, mm) of the highest node on the optical axis, where the instrument aims."""
    on_axis = _on_axis(mesh)
    if not np.any(on_axis):
        raise InputError("instrument: the mesh has no node on the optical axis to aim at")
    return float(mesh.points[on_axis, -1].max())


PRELOAD_CLEARANCE = 1.0
"""Extra height (mm) of the instrument above the apex during a preload, clear of the tissue
inflating under the pressure; :func:`place_on_tissue` sets it on the deformed tissue when the
procedure starts (or at once without a preload)."""


def _on_axis(mesh: Mesh) -> np.ndarray:
    radius = mesh.points[:, 0] if mesh.axisymmetric else np.hypot(mesh.points[:, 0], mesh.points[:, 1])
    return radius <= 1e-9


def _tip(mesh: Mesh, height: float) -> tuple:
    return (0.0, height) if mesh.axisymmetric else (0.0, 0.0, height)


def place_on_tissue(mesh: Mesh, instrument: InstrumentContact, gap: float, displacement: np.ndarray) -> None:
    """Lower the instrument along the optical axis until it clears the deformed anterior surface by ``gap`` (mm).

    ``displacement`` (n_nodes, dim), mm; the surface is the node set ``anterior_surface`` (all
    nodes if the mesh has none). A needle's clearance to the surface nodes is ``gap`` (its tip
    ends above the apex, ``corneasim.instruments._placement``); a trephine's edge ends ``gap`` above
    the surface the nodes span under it (``placement.edge_surface_height``), the instrument
    clear of every node, so that the edge touches first, after a descent of ``gap``.
    """
    nodes = mesh.node_sets.get("anterior_surface", np.arange(mesh.n_nodes))
    current = mesh.points[nodes] + displacement[nodes]
    edge_radius = getattr(instrument.instrument, "edge_radius", None)
    if edge_radius is not None and not mesh.axisymmetric:
        surface = edge_surface_height(mesh.points + displacement, mesh.cells, nodes, edge_radius,
                                      0.25 * instrument.smallest_element_size)
        height = max(surface + gap, tip_height_for_gap(instrument.shape, current, 0.0, False))
    else:
        height = tip_height_for_gap(instrument.shape, current, gap, mesh.axisymmetric)
    instrument.place(_tip(mesh, height))


def make_instrument(scenario: Scenario, mesh: Mesh, model: Model, start_time: float) -> InstrumentContact | None:
    """The instrument's contact hook, moving from ``start_time`` (s).

    With a preload it waits :data:`PRELOAD_CLEARANCE` above the apex and the runner places it
    (:func:`place_on_tissue`) when the procedure starts; without one it is placed here.
    """
    setup = scenario.instrument
    if setup is None:
        return None
    motion_config = setup.motion
    tip = _tip(mesh, apex_height(mesh) + setup.start_gap + PRELOAD_CLEARANCE)
    insertion = shifted(motion_config.insertion.build(), start_time)
    rotation = shifted(motion_config.rotation.build(), start_time)
    motion = Motion(insertion, rotation, tip)
    settings = setup.contact
    if scenario.cohesive_cut is not None:  # the ties cut the cornea: no ring rule beside them
        settings = settings.model_copy(update={"cutting_toughness": None})
    contact = InstrumentContact(setup.shape, motion, model, settings, name="instrument",
                             symmetry_factor=setup.symmetry_factor)
    if start_time == 0.0:
        place_on_tissue(mesh, contact, setup.start_gap, np.zeros_like(mesh.points))
    return contact


def build(scenario: Scenario, base_dir: str | Path = ".", reference_points: np.ndarray | None = None) -> Setup:
    """Mesh, materials, loads, model and instrument of ``scenario``.

    Parameters
    ----------
    scenario : Scenario
        The validated scenario (physical time); the setup holds it in solver time
        (:func:`corneasim.scenarios._time_scaling.scaled_scenario`).
    base_dir : path-like
        Folder that relative paths in the scenario (mesh files) refer to.
    reference_points : ndarray (n_nodes, dim), optional
        Reference coordinates (mm) that replace the mesh's (after a cohesive cut's split): the
        stress-free geometry of a prestressed reference (:mod:`corneasim.scenarios._prestress`).
        The fibre frames stay those of the mesh's own geometry.
    """
    scenario = scaled_scenario(scenario)
    messages: list[str] = []
    with warnings.catch_warnings(record=True) as caught:  # a quadratic mesh split on import says so
        warnings.simplefilter("always")
        mesh = make_mesh(scenario, Path(base_dir))
    messages.extend(f"mesh: {warning.message}" for warning in caught)
    pairs = None
    if scenario.cohesive_cut is not None:
        mesh, pairs = split_cornea(scenario, mesh)
    # the damping leaves the model's translation on its supports free
    free = sorted({component_index(item.component, mesh.axisymmetric, f"supports[{k}].component")
                   for k, item in enumerate(scenario.supports)})
    materials = load_materials(scenario, mesh, messages, Path(base_dir))
    fibrous = np.array([materials[name].has_fibres for name in mesh.block_names], dtype=bool)
    fibre_frame = (lamellar_frames(mesh, scenario.mesh.geometry, fibrous[mesh.element_block])
                   if fibrous.any() else None)
    measured_points = mesh.points
    if reference_points is not None:
        mesh = with_reference(mesh, reference_points)
    conditions, pressures = make_loads(scenario)
    solver = scenario.solver
    model = build_model(
        mesh, materials, conditions, pressures, safety_factor=solver.safety_factor,
        target_time_step=solver.target_time_step, time_step=solver.time_step,
        variable_mass_scaling=solver.mass_scaling == "variable", distortion_limit=solver.distortion_limit,
        fracture_energy={block: item.fracture_energy for block, item in scenario.materials.items()},
        free_translation=free, node_copies=pairs,
        hourglass_coefficient=(physical_hourglass_coefficients(mesh, materials) if solver.hourglass_control == "physical"
                               else solver.hourglass_coefficient),
        bulk_viscosity_linear=solver.bulk_viscosity_linear,
        bulk_viscosity_quadratic=solver.bulk_viscosity_quadratic, fibre_frame=fibre_frame)
    cut = make_radial_cut(scenario.cut, mesh, model) if scenario.cut is not None else None
    check_reactions(scenario, model)
    preload_duration = scenario.preload.duration if scenario.preload else 0.0
    ties = None
    if pairs is not None:
        ties = make_ties(scenario, mesh, model, pairs)
    instrument = make_instrument(scenario, mesh, model, preload_duration)
    setup = Setup(scenario, mesh, model, instrument, preload_duration, messages, cohesive=ties,
                  supports=make_supports(scenario, model),
                  pressure_release=make_pressure_release(scenario, instrument),
                  probe=HistoryProbe(scenario.history, mesh, model,
                                     [(c.node_set, c.component) for c in scenario.constraints if c.prescribed]),
                  distortion=DistortionCheck(mesh, solver.distortion_warning) if solver.distortion_warning > 0 else None)
    setup.cut = cut
    if cut is not None:
        if instrument is not None:  # the point splits the band; the axis penalty is damped like the contact's
            cut.follow(instrument, model)
            cut.damping_ratio = float(instrument.settings.damping_ratio)
    if ties is not None and instrument is not None:
        setup.edge_work = EdgeWork(ties, instrument, line_points=measured_points)
        if instrument.edge is not None:  # the edge rests on the cut's fronts, not on the faces beside it
            instrument.edge.hold_by_fronts(ties.pairs, setup.edge_work.line_start, setup.edge_work.line_pairs,
                                           ties.cut)
        setup.tie_events = TieEvents(setup)
    elif instrument is not None and cut is not None:
        setup.cut_punctures = CutPunctures(setup)
    elif instrument is not None:
        setup.punctures = PunctureEvents(setup)
    return setup
