"""The instruments: a needle and a trephine, every dimension a parameter.

Each configuration is a strict pydantic model (unknown keys are errors) whose
:meth:`pack` gives the shape array read by :mod:`corneasim.instruments._shapes`. Local frame:
axis along z, tip at z = 0, pointing down (-z).

Needle (needle paper: a No. 2 medical needle, 0.2 mm in diameter, inserted vertically).
Tips: ``flat`` (a flat punch), ``conical`` (included angle ``tip_angle``), ``rounded``
(hemispherical) and ``bevelled`` (a plane at ``bevel_angle`` to the axis; 3D only).

Trephine (trephination paper: a disposable trephine of 7.5 mm diameter). A hollow
cylinder whose wall of thickness ``wall_thickness`` ends in a sharp cutting edge of
diameter ``diameter``; the bevel ground at ``bevel_angle`` to the axis is on the outside
(edge on the inner wall, the usual corneal trephine), the inside, or both (symmetric).
"""

from __future__ import annotations

import math
from typing import Annotated, Literal, Union

import numpy as np
import pydantic

from corneasim.errors import InputError
from corneasim.schema import StrictModel, validate
from corneasim.instruments._shapes import BEVELLED, PROFILE, ROUNDED

Positive = Annotated[float, pydantic.Field(gt=0.0)]
Angle = Annotated[float, pydantic.Field(gt=0.0, lt=90.0)]


def pack_profile(r, z, closed: bool) -> np.ndarray:
    """Pack a meridian polygon (r_k, z_k) in mm as a PROFILE shape, made counter-clockwise."""
    r, z = np.asarray(r, dtype=np.float64), np.asarray(z, dtype=np.float64)
    twice_area = np.sum(r * np.roll(z, -1) - np.roll(r, -1) * z)
    if twice_area < 0:
        if closed:
            r, z = r[::-1], z[::-1]
        else:
            raise InputError("open instrument profile must run counter-clockwise, starting and ending on the axis")
    return np.concatenate([[PROFILE, len(r), 1.0 if closed else 0.0], r, z])


class Needle(StrictModel):
    """A solid needle.

    Attributes
    ----------
    diameter : float
        Shaft diameter, mm (needle paper: 0.2 mm).
    length : float
        Length of the modelled part from the tip, mm.
    tip : str
        ``flat``, ``conical``, ``rounded`` or ``bevelled``.
    tip_angle : float
        Included angle of the conical tip, degrees (0 < angle < 180).
    bevel_angle : float
        Angle between the bevel face and the axis, degrees (bevelled tip only).
    """

    kind: Literal["needle"] = "needle"
    diameter: Positive = 0.2
    length: Positive = 5.0
    tip: Literal["flat", "conical", "rounded", "bevelled"] = "conical"
    tip_angle: Annotated[float, pydantic.Field(gt=0.0, lt=180.0)] = 30.0
    bevel_angle: Angle = 15.0

    @pydantic.model_validator(mode="after")
    def _long_enough(self):
        if self.length <= self.tip_height:
            raise ValueError(f"length ({self.length} mm) must exceed the tip height ({self.tip_height:.4g} mm)")
        return self

    @property
    def radius(self) -> float:
        """Shaft radius, mm."""
        return 0.5 * self.diameter

    @property
    def tip_height(self) -> float:
        """Axial length of the tip (from z = 0 to the full shaft section), mm."""
        if self.tip == "conical":
            return self.radius / math.tan(math.radians(0.5 * self.tip_angle))
        if self.tip == "rounded":
            return self.radius
        if self.tip == "bevelled":
            return self.diameter / math.tan(math.radians(self.bevel_angle))
        return 0.0

    @property
    def axisymmetric(self) -> bool:
        """True when the shape is a body of revolution (usable in the axisymmetric model)."""
        return self.tip != "bevelled"

    @property
    def cutting_radius(self) -> float:
        """Radius used for a tangential force from a torque, mm (the shaft radius)."""
        return self.radius

    def pack(self) -> np.ndarray:
        """The packed shape array (see :mod:`corneasim.instruments._shapes`)."""
        radius, length, height = self.radius, self.length, self.tip_height
        if self.tip == "rounded":
            return np.array([ROUNDED, radius, length], dtype=np.float64)
        if self.tip == "bevelled":
            return np.array([BEVELLED, radius, length, math.radians(self.bevel_angle)], dtype=np.float64)
        return pack_profile([0.0, radius, radius, 0.0], [0.0, height, length, length], closed=False)


class Trephine(StrictModel):
    """A hollow cylindrical trephine with a sharp bevelled cutting edge.

    Attributes
    ----------
    diameter : float
        Diameter of the cutting edge, mm (trephination paper: 7.5 mm).
    wall_thickness : float
        Radial thickness of the wall, mm.
    bevel_angle : float
        Angle between each bevel face and the axis, degrees.
    bevel_side : str
        ``outer`` (edge on the inner wall), ``inner`` (edge on the outer wall) or ``symmetric``.
    length : float
        Length of the modelled part from the edge, mm.
    """

    kind: Literal["trephine"] = "trephine"
    diameter: Positive = 7.5
    wall_thickness: Positive = 0.1
    bevel_angle: Angle = 30.0
    bevel_side: Literal["outer", "inner", "symmetric"] = "outer"
    length: Positive = 3.0

    @pydantic.model_validator(mode="after")
    def _consistent(self):
        inner = self.edge_radius - self.wall_thickness * {"outer": 0.0, "inner": 1.0, "symmetric": 0.5}[self.bevel_side]
        if inner <= 0:
            raise ValueError(f"wall_thickness ({self.wall_thickness} mm) leaves no bore inside the edge diameter")
        if self.length <= self.bevel_height:
            raise ValueError(f"length ({self.length} mm) must exceed the bevel height ({self.bevel_height:.4g} mm)")
        return self

    @property
    def edge_radius(self) -> float:
        """Radius of the cutting edge, mm."""
        return 0.5 * self.diameter

    @property
    def cutting_radius(self) -> float:
        """R of the rotary cutting force F_c = M_z / R, mm: the edge radius."""
        return self.edge_radius

    @property
    def bevel_height(self) -> float:
        """Axial length of the bevel, mm."""
        run = self.wall_thickness * (0.5 if self.bevel_side == "symmetric" else 1.0)
        return run / math.tan(math.radians(self.bevel_angle))

    @property
    def axisymmetric(self) -> bool:
        """Always True: the trephine is a body of revolution."""
        return True

    def pack(self) -> np.ndarray:
        """The packed shape array: a closed meridian quadrilateral or pentagon."""
        edge, wall, h, length = self.edge_radius, self.wall_thickness, self.bevel_height, self.length
        if self.bevel_side == "outer":
            r, z = [edge, edge + wall, edge + wall, edge], [0.0, h, length, length]
        elif self.bevel_side == "inner":
            r, z = [edge, edge, edge - wall, edge - wall], [0.0, length, length, h]
        else:
            half = 0.5 * wall
            r = [edge, edge + half, edge + half, edge - half, edge - half]
            z = [0.0, h, length, length, h]
        return pack_profile(r, z, closed=True)


Instrument = Annotated[Union[Needle, Trephine], pydantic.Field(discriminator="kind")]


class _InstrumentDocument(StrictModel):
    instrument: Instrument


def instrument_from_dict(data: dict, source: str | None = None) -> Needle | Trephine:
    """Validate an instrument table (with ``kind = "needle"`` or ``"trephine"``)."""
    return validate(_InstrumentDocument, {"instrument": data}, source).instrument
