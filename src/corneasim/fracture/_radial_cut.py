"""A scenario's ``[cut]`` table: the needle's path separated by smeared radial cracks.

``[cut]`` with ``kind = "radial-cracks"`` puts the cornea's elements within ``band_radius``
of the axis of an axisymmetric model into a cut band (:mod:`corneasim.fracture._cut_band`)
whose hoop direction cracks by the law of :mod:`corneasim.fracture._radial_cracks`: ``cracks``
radial cracks of strength sigma_c and toughness G_c, given per block in ``[cut.blocks.NAME]``.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
import pydantic
from pydantic import Field

from corneasim.errors import InputError
from corneasim.schema import StrictModel
from corneasim.fracture._cut_band import CutAxis, RadialCracks, attach_radial_cracks, band_elements


class CutBlock(StrictModel):
    """Strength and toughness of the radial cracks in one block."""

    strength: pydantic.PositiveFloat = Field(description="Strength sigma_c: the nominal hoop stress at which a "
                                             "crack starts, MPa.")
    fracture_energy: pydantic.PositiveFloat = Field(description="Toughness G_c: energy per unit area of each "
                                                    "crack face, N/mm (= kJ/m^2).")


class RadialCut(StrictModel):
    """The needle's path separated by smeared radial cracks (axisymmetric models; docs/cutting.md)."""

    kind: Literal["radial-cracks"] = Field("radial-cracks", description="The separation model: radial-cracks "
                                           "(n radial cracks smeared over the band, docs/cutting.md).")
    cracks: int = Field(2, ge=1, description="n, radial cracks through the axis, dimensionless: 2 for a slit "
                        "(a sharp or bevelled point), 3 for a tri-facet point.")
    band_radius: pydantic.PositiveFloat = Field(description="Radius of the cut band: elements of the blocks "
                                                "below whose centroid lies within it may crack, mm (results must "
                                                "not depend on it once it holds the cracks: a few needle radii).")
    blocks: dict[str, CutBlock] = Field(description="Block name -> [cut.blocks.NAME] strength and toughness; "
                                        "the band is made of these blocks.")


def make_radial_cut(cut: RadialCut, mesh, model) -> CutAxis:
    """Give ``model`` the cut band of ``cut`` (``Model.radial_cracks``) and return its axis hook."""
    if not mesh.axisymmetric:
        raise InputError("cut: radial cracks need an axisymmetric mesh (the needle's path is its axis)")
    if not cut.blocks:
        raise InputError("cut.blocks: expected at least one block with strength and fracture_energy")
    for block in cut.blocks:
        if block not in mesh.block_names:
            raise InputError(f"cut.blocks.{block}: the mesh has no block '{block}' "
                             f"(blocks: {', '.join(mesh.block_names)})")
    band = band_elements(mesh, list(cut.blocks), cut.band_radius)
    names = np.array(mesh.block_names)[mesh.element_block[band]]
    strength = np.array([cut.blocks[name].strength for name in names])
    toughness = np.array([cut.blocks[name].fracture_energy for name in names])
    cracks = RadialCracks(model.elements, band, strength, toughness, cut.cracks)
    return CutAxis(model, attach_radial_cracks(model, cracks), name="cut")
