"""The scenario file: one TOML format for the built-in scenarios and for any imported mesh.

A scenario names a mesh (a built-in eye generator or a mesh file), maps its blocks to
materials, its node sets to constraints and its surface sets to pressures, optionally
adds a rigid instrument with its motion and contact, and says how to integrate and what
to record. The built-in ``needle`` and ``trephine`` scenarios are files of this format
(``corneasim show needle``); their ``kind`` adds the paper-specific post-processing.
Every key and its unit: ``docs/scenario-format.md``. Units: mm, s, N, MPa, tonne/mm^3.
"""

from __future__ import annotations

from typing import Literal

import pydantic
from pydantic import Field

from corneasim.fracture import CohesiveCut, RadialCut
from corneasim.mesh import EyeGeometry
from corneasim.scenarios._history_requests import HistoryRequest
from corneasim.schema import StrictModel
from corneasim.solver import AmplitudeConfig, ConstantAmplitude
from corneasim.contact import ContactSettings
from corneasim.instruments import MotionConfig
from corneasim.instruments import Needle, Trephine

PositiveFloat = pydantic.PositiveFloat
PositiveInt = pydantic.PositiveInt


class MeshSource(StrictModel):
    """Where the mesh comes from: exactly one of ``generator`` or ``file``."""

    generator: Literal["eye-axisymmetric", "eye-3d"] | None = Field(
        None, description="Built-in parametric eye: 2D axisymmetric (needle) or 3D half model (trephine).")
    strategy: Literal["umbrella", "vertical", "horizontal"] = Field(
        "umbrella", description="3D meshing strategy of the trephination paper (eye-3d only).")
    preset: Literal["coarse", "default", "fine", "needle-path", "needle-path-2x", "needle-path-4x"] = Field(
        "default", description="Mesh density preset (needle-path and its 2x, 4x coarser family: eye-axisymmetric "
        "only).")
    geometry: EyeGeometry = Field(default_factory=EyeGeometry, description="Eye dimensions, mm.")
    file: str | None = Field(None, description="Mesh file (.inp, .msh, .vtu), relative to the scenario file.")
    axisymmetric: bool | None = Field(
        None, description="Whether an imported mesh is axisymmetric (r, z); default: a 2D mesh is.")

    @pydantic.model_validator(mode="after")
    def _one_source(self):
        if (self.generator is None) == (self.file is None):
            raise ValueError("give exactly one of mesh.generator or mesh.file")
        return self


def unit_amplitude() -> ConstantAmplitude:
    """a(t) = 1: the default time function of loads and prescribed motions (full value at all times)."""
    return ConstantAmplitude(value=1.0)


class MaterialAssignment(StrictModel):
    """The material of one block (element set)."""

    material: str = Field(description="Material preset name (corneasim material list) or a TOML file path.")
    failure_limit: float | None = Field(
        None, gt=0.0, description="Override of the material's failure limit: MPa (stress criteria) "
        "or dimensionless (strain criterion).")
    fracture_energy: float = Field(
        0.0, ge=0.0, description="Fracture energy G_f, N/mm (= mJ/mm^2): an element whose failure criterion "
        "is met softens linearly and dissipates G_f / h_e per unit volume (h_e its size) before it is "
        "deleted (crack band, docs/solver.md; von Mises criterion only); 0: deleted at once (brittle).")
    failure: bool = Field(
        True, description="false: the block's elements do not fail by the material's criterion (a cutting "
        "rule or a cut still separates them), so that a scenario has one way for the tissue to separate.")

    @pydantic.model_validator(mode="after")
    def _failure_settings_need_failure(self):
        if not self.failure and (self.failure_limit is not None or self.fracture_energy > 0.0):
            raise ValueError("failure = false leaves no criterion for failure_limit or fracture_energy to act on")
        return self


class Constraint(StrictModel):
    """A boundary condition on a node set: fixed components, mirror or cyclic symmetry, or a prescribed motion."""

    node_set: str = Field(description="Node set name of the mesh.")
    fixed: str = Field("", description="Components held at zero displacement, e.g. 'rz' or 'xyz'.")
    symmetry: Literal["x", "y", "z", "r"] | None = Field(
        None, description="Normal axis of a symmetry plane through these nodes.")
    cyclic: Literal["z"] | None = Field(
        None, description="Axis of cyclic symmetry of order 2 (rotation by 180 degrees): these nodes are the "
        "cut plane y = 0 of a half model, each (x, 0, z) moving as the image of (-x, 0, z).")
    prescribed: Literal["displacement", "velocity"] | None = Field(
        None, description="Prescribe a displacement (mm) or a velocity (mm/s) of `component`.")
    component: str | None = Field(None, description="Component of the prescribed motion: r, z, x, y.")
    value: float = Field(0.0, description="Magnitude of the prescribed motion: mm or mm/s, times the amplitude.")
    amplitude: AmplitudeConfig = Field(default_factory=unit_amplitude,
                                       description="Time function (dimensionless); default constant 1.")

    @pydantic.model_validator(mode="after")
    def _one_kind(self):
        kinds = [bool(self.fixed), self.symmetry is not None, self.cyclic is not None, self.prescribed is not None]
        if sum(kinds) != 1:
            raise ValueError(f"constraint on '{self.node_set}': give exactly one of fixed, symmetry, cyclic, "
                             "prescribed")
        if self.prescribed is not None and not self.component:
            raise ValueError(f"constraint on '{self.node_set}': a prescribed motion needs a component")
        return self


class PressureLoad(StrictModel):
    """A follower pressure on a surface set, positive pushing into the surface."""

    surface: str = Field(description="Surface set name of the mesh.")
    pressure: float = Field(description="Pressure, MPa (17.5 mmHg = 2.333e-3 MPa), times the amplitude.")
    amplitude: AmplitudeConfig = Field(default_factory=unit_amplitude,
                                       description="Time function (dimensionless); default constant 1.")
    release_on_puncture: bool = Field(False, description="Fall to 0 once the instrument has cut through the "
                                      "cornea (the `cornea` puncture event): the opened chamber loses its fluid.")
    release_duration: PositiveFloat = Field(1.0, description="Time over which a released pressure falls to 0 "
                                            "(smooth step), s.")


class Preload(StrictModel):
    """Quasi-static preload before the instrument moves: loads ramped and settled with damping."""

    duration: PositiveFloat = Field(description="Length of the preload stage, s (not part of the procedure time).")
    damping: float = Field(ge=0.0, description="Mass-proportional damping during the preload, 1/s.")
    relaxed: bool = Field(False, description="Let the viscoelastic (Prony) terms relax fully during the "
                          "preload, so the procedure starts from the long-term equilibrium under the "
                          "preload's loads (held long before, as an eye at its IOP) and nothing creeps "
                          "under them afterwards; false: the instantaneous response, which then creeps.")
    stress_free_reference: bool = Field(False, description="Build the model on the stress-free geometry whose "
                                        "preload gives the mesh's geometry (the mesh is the eye measured under its "
                                        "IOP), found by backward displacement and cached in the results folder "
                                        "(`reference.npz`); false: the mesh is taken as stress-free.")
    reference_tolerance: PositiveFloat = Field(1e-3, description="Largest nodal distance between the preloaded "
                                               "stress-free reference and the mesh's geometry, mm "
                                               "(`stress_free_reference` only).")
    reference_iterations: PositiveInt = Field(20, description="Most preload solves of the backward-displacement "
                                              "iteration; a run that has not converged by then fails "
                                              "(`stress_free_reference` only).")


class InstrumentSetup(StrictModel):
    """A rigid instrument, its motion and its contact with the tissue."""

    shape: Needle | Trephine = Field(discriminator="kind", description="Instrument geometry, mm and degrees.")
    motion: MotionConfig = Field(default_factory=MotionConfig, description="Insertion (mm) and rotation (rad) amplitudes.")
    contact: ContactSettings = Field(default_factory=ContactSettings, description="Penalty contact and friction.")
    symmetry_factor: float = Field(1.0, ge=1.0, description="Multiplier of the reported instrument forces "
                                   "and torque: 2 for a half model (mirror or cyclic symmetry) cut through the axis.")
    start_gap: float = Field(0.0, ge=0.0, description="Clearance between the instrument and the anterior "
                             "surface when the procedure starts, mm: the instrument is lowered along the optical "
                             "axis onto the surface as deformed by the preload (1 mm clear of the apex during it); "
                             "a needle's nodes-to-instrument distance, a trephine edge's height above the surface "
                             "under it (its first contact after a descent of start_gap).")


class ReactionOutput(StrictModel):
    """A history column: the reaction force on a constrained node set."""

    name: str = Field(description="Column name (the unit _N is appended).")
    node_set: str = Field(description="Constrained node set whose reaction is summed.")
    component: str = Field(description="Force component: r, z, x, y.")


class SolverSettings(StrictModel):
    """Explicit integration, output and checkpoint settings."""

    end_time: PositiveFloat = Field(description="Procedure time after the preload, s.")
    target_time_step: PositiveFloat | None = Field(
        None, description="Mass scaling target, s: elements with a smaller stable step get denser.")
    mass_scaling: Literal["initial", "variable"] = Field(
        "variable", description="With a target: scale once in the reference geometry (initial), or also "
        "whenever crushed elements fall below the target (variable, as Abaqus 'throughout the step').")
    time_step: PositiveFloat | None = Field(None, description="Fixed time step, s (must be stable).")
    time_scaling: PositiveFloat = Field(
        1.0, description="Run the procedure this many times faster (rates x, durations and Prony times /); "
        "results in physical time; target_time_step and time_step are solver-time steps (docs/trephination.md).")
    safety_factor: float = Field(0.9, gt=0.0, le=1.0, description="Fraction of the stable step used.")
    damping: float = Field(
        0.0, ge=0.0, description="Mass-proportional damping during the procedure (after the preload), 1/s; "
        "0: none. Reported as damping_energy_mJ in the history.")
    quasi_static: bool = Field(False, description="Apply the quasi-static recipe (docs/quasi-static.md): "
                               "constant-amplitude loads ramped by a smooth step, mass scaling and damping "
                               "chosen from the model's lowest period, KE/IE reported.")
    ramp_time: PositiveFloat | None = Field(None, description="Quasi-static ramp time, s (default: 0.8 end_time, "
                                            "or the shortest rise of the loads' own amplitudes).")
    ramp_periods: PositiveFloat = Field(20.0, description="Quasi-static ramp length in lowest periods of the "
                                        "(mass-scaled) model, dimensionless.")
    history_every: PositiveInt = Field(20, description="Steps between history rows.")
    field_count: int = Field(8, ge=0, description="Number of field frames, equally spaced in time.")
    checkpoint_every: PositiveInt = Field(2000, description="Steps between checkpoints.")
    deletion_every: PositiveInt = Field(1, description="Steps between failure checks.")
    distortion_limit: float = Field(
        0.0, ge=0.0, lt=1.0, description="Element erosion: delete a live element whose smallest corner "
        "Jacobian ratio (local area/volume change at a corner) falls below this, dimensionless; 0: off.")
    distortion_warning: float = Field(
        0.1, ge=0.0, lt=1.0, description="Distortion check: warn (and record in summary.json) when a live "
        "element's smallest corner Jacobian ratio falls below this, naming the element and the time, "
        "dimensionless; 0: off. The history gets min_corner_jacobian_ratio.")
    hourglass_coefficient: float = Field(0.1, ge=0.0, description="Hourglass stiffness coefficient, dimensionless.")
    hourglass_control: Literal["stiffness", "physical"] = Field(
        "stiffness", description="stiffness: k_e = hourglass_coefficient mu_0 V (b:b); physical: the coefficient "
        "4 / (3 (1 - nu)) per block that makes a square element exact in bending (docs/quasi-static.md).")
    bulk_viscosity_linear: float = Field(0.06, ge=0.0, description="Linear bulk viscosity, dimensionless.")
    bulk_viscosity_quadratic: float = Field(1.2, ge=0.0, description="Quadratic bulk viscosity, dimensionless.")
    threads: PositiveInt | None = Field(
        None, description="Numba threads (default: all cores from 5000 elements, else one).")


class Validation(StrictModel):
    """Experimental data the run is compared with."""

    dataset: str = Field(description="Dataset name (corneasim data list).")
    x_column: str = Field(description="Abscissa column of the dataset.")
    y_column: str = Field(description="Force column of the dataset, N.")


class Support(StrictModel):
    """An elastic support: the nodes of a set held by springs to ground in one component."""

    node_set: str = Field(description="Node set name of the mesh.")
    component: str = Field(description="Supported component: r or z (axisymmetric), x, y or z (3D).")
    stiffness: PositiveFloat = Field(description="Total stiffness of the set in this model, N/mm, shared "
                                     "equally by its nodes (a half model holds half the whole body's).")
    damping_ratio: float = Field(0.0, ge=0.0, le=2.0, description="Damping ratio of the model's translation on "
                                 "the support, dimensionless: a dashpot c = 2 zeta sqrt(K M) beside the springs, M the "
                                 "model's (mass-scaled) mass, N s/mm.")
    held_in_preload: bool = Field(True, description="Hold the set (springs as stiff as the time step allows) "
                                  "while the preload settles, then release it onto `stiffness` keeping the force "
                                  "it carries (a specimen mounted at its pressure); false: on `stiffness` throughout.")


class Scenario(StrictModel):
    """A complete simulation input (see the module notes)."""

    kind: Literal["general", "needle", "trephine"] = Field(
        "general", description="Post-processing: general, or the needle / trephination paper's.")
    name: str = Field(description="Short name, used for the default results folder.")
    description: str = ""
    mesh: MeshSource
    materials: dict[str, MaterialAssignment] = Field(description="Block name -> material.")
    constraints: list[Constraint] = []
    pressures: list[PressureLoad] = []
    supports: list[Support] = []
    preload: Preload | None = None
    instrument: InstrumentSetup | None = None
    cohesive_cut: CohesiveCut | None = Field(None, description="The cornea split along the trephine's "
                                             "cylinder and tied by a cohesive law, cut by the instrument's work "
                                             "(none by default: the ring rule and element deletion cut).")
    cut: RadialCut | None = Field(None, description="The needle's path separated by smeared radial cracks of a "
                                  "strength and a toughness (axisymmetric; none by default: element deletion).")
    reactions: list[ReactionOutput] = []
    history: list[HistoryRequest] = Field([], description="Extra history.csv columns of node and element sets "
                                          "(docs/scenario-format.md, History requests).")
    solver: SolverSettings
    validation: Validation | None = None
    variant: str | None = Field(
        None, description="Model variant: the name of a presets table that is not a mesh preset (e.g. "
        "'paper', the paper's own model); its settings apply before the mesh preset's and the --set "
        "overrides. --preset NAME sets it.")
    presets: dict[str, dict[str, bool | int | float | str | list]] = Field(
        {}, description="Settings that come with a mesh preset or a model variant: when mesh.preset or "
        "variant is NAME, the table presets.NAME ({dotted key: value}, as --set, units of the key) applies "
        "before the --set overrides (the variant's first, then the mesh preset's); its key unset = [KEY, ...] "
        "removes those keys (each takes its default).")
