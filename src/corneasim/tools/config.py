"""Configuration tables for instrument motion and contact (validated, strict, with units).

TOML example (a trephine as in the trephination paper)::

    [instrument]
    kind = "trephine"
    diameter = 7.5

    [motion]
    tip_position = [0.0, 0.0, 0.62]
    insertion = { type = "linear", rate = 0.020 }
    rotation = { type = "fourier", sine = [1.25], cosine = [0.0], circular_frequency = 3.508 }

    [contact]
    penalty_fraction = 0.5
    friction = { law = "coulomb", coefficient = 0.1 }
"""

from __future__ import annotations

from typing import Annotated, Literal, Union

import pydantic

from corneasim.schema import StrictModel
from corneasim.tools.amplitudes import Amplitude, Constant, Fourier, Linear, SmoothStep, Tabular
from corneasim.tools.friction import Friction
from corneasim.tools.motion import Motion


class ConstantAmplitude(StrictModel):
    """a(t) = value (in the driven quantity's unit: mm for insertion, rad for rotation)."""

    type: Literal["constant"] = "constant"
    value: float = 0.0

    def build(self) -> Amplitude:
        return Constant(self.value)


class LinearAmplitude(StrictModel):
    """Constant velocity: a = rate (t - start_time); rate in mm/s or rad/s, start_time in s."""

    type: Literal["linear"] = "linear"
    rate: float
    start_time: float = 0.0

    def build(self) -> Amplitude:
        return Linear(self.rate, self.start_time)


class SmoothStepAmplitude(StrictModel):
    """Quintic step from a0 at t0 to a1 at t1 (times in s, values in mm or rad)."""

    type: Literal["smooth-step"] = "smooth-step"
    t0: float
    t1: float
    a0: float = 0.0
    a1: float = 1.0

    def build(self) -> Amplitude:
        return SmoothStep(self.t0, self.t1, self.a0, self.a1)


class TabularAmplitude(StrictModel):
    """Piecewise linear through (times in s, values in mm or rad)."""

    type: Literal["tabular"] = "tabular"
    times: list[float]
    values: list[float]

    def build(self) -> Amplitude:
        return Tabular(tuple(self.times), tuple(self.values))


class FourierAmplitude(StrictModel):
    """Trephination paper eq. 1: initial A0, cosine A_n, sine B_n, circular_frequency in rad/s, start_time in s."""

    type: Literal["fourier"] = "fourier"
    initial: float = 0.0
    cosine: list[float] = []
    sine: list[float] = []
    circular_frequency: float
    start_time: float = 0.0

    def build(self) -> Amplitude:
        return Fourier(self.initial, tuple(self.cosine), tuple(self.sine), self.circular_frequency, self.start_time)


AmplitudeConfig = Annotated[
    Union[ConstantAmplitude, LinearAmplitude, SmoothStepAmplitude, TabularAmplitude, FourierAmplitude],
    pydantic.Field(discriminator="type"),
]


class MotionConfig(StrictModel):
    """Prescribed instrument motion.

    Attributes
    ----------
    tip_position : list of float
        Tip position at zero insertion, mm: [x, y, z] (3D) or [r, z] with r = 0 (axisymmetric).
    insertion : amplitude table
        Insertion depth along the pointing direction (-z), mm.
    rotation : amplitude table
        Rotation angle about the axis, rad.
    """

    tip_position: list[float] = [0.0, 0.0, 0.0]
    insertion: AmplitudeConfig = ConstantAmplitude()
    rotation: AmplitudeConfig = ConstantAmplitude()

    def build(self) -> Motion:
        """The :class:`~corneasim.tools.motion.Motion` (raises InputError on inconsistent amplitudes)."""
        return Motion(self.insertion.build(), self.rotation.build(), tuple(self.tip_position))


class ContactSettings(StrictModel):
    """Penalty contact between an instrument and the tissue.

    Attributes
    ----------
    penalty_fraction : float
        alpha in the penalty stiffness k = alpha m / dt^2 per node, dimensionless; stable
        for alpha <= 4 (1 - s^2), s the time-step safety factor (see ``docs/contact.md``).
    damping_ratio : float
        Normal dashpot as a fraction of the critical damping of each node's penalty spring,
        dimensionless (<= 0.05 keeps the strict stability bound at alpha = 0.5, s = 0.9).
    friction : Friction
        Friction law and its parameters.
    node_set : str
        Name of the mesh node set that may touch the instrument (``all`` for every node).
    edge_contact : bool
        Also test points along a trephine's circular cutting edge against the tissue's boundary
        faces, so that the edge cannot pass between nodes (3D hexahedral meshes; the node and
        the edge penalty can act on one node: stable for 2 alpha <= 4 (1 - s^2); see
        ``docs/contact.md``).
    cutting_toughness : float, optional
        With ``edge_contact``: the line load, N per mm of edge (= J/m^2 x 1e-3), at which the
        edge cuts the element it presses; that element is deleted like one whose failure
        criterion is met (a sharp blade cuts when its force per unit length reaches the
        tissue's toughness; see ``docs/contact.md``). None: the edge only presses.
    """

    penalty_fraction: Annotated[float, pydantic.Field(gt=0.0, lt=4.0)] = 0.5
    damping_ratio: Annotated[float, pydantic.Field(ge=0.0, le=1.0)] = 0.05
    friction: Friction = Friction()
    node_set: str = "all"
    edge_contact: bool = False
    cutting_toughness: Annotated[float, pydantic.Field(gt=0.0)] | None = None

    @pydantic.model_validator(mode="after")
    def _cutting_needs_the_edge(self):
        if self.cutting_toughness is not None and not self.edge_contact:
            raise ValueError("cutting_toughness needs edge_contact = true")
        return self
