"""A scenario's cohesive cut: the cornea split along the trephine's cylinder and tied back.

With ``[cohesive_cut]`` the mesh gets a node surface on the cylinder r = R (a through-thickness
node line at R parallel to the axis, revolved: ``mesh_3d(cut_radius=R)``, every strategy),
the cornea's nodes on it
are duplicated for the elements outside (``fracture._split.split_nodes``) and each pair is held
by the cohesive law of ``fracture._ties``: the trephine separates the tissue along its path
at the cost of the fracture energy per unit area, instead of deleting elements. The copies
on a cyclic-symmetry cut plane are paired with each other as their originals are.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pydantic
from pydantic import Field

from corneasim.errors import InputError
from corneasim.mesh import Mesh
from corneasim.schema import StrictModel
from corneasim.fracture._split import split_nodes
from corneasim.fracture._ties import CohesiveTies, tie_areas


class CohesiveCut(StrictModel):
    """The cornea split along the trephine's cylinder, its two sides tied by a cohesive law
    (``fracture._split``, ``fracture._ties``; needs a 3D mesh with a node surface on the cylinder,
    which the built-in eye meshes have with a cut)."""

    radius: pydantic.PositiveFloat | None = Field(None, description="Radius of the cut cylinder r = sqrt(x^2 + y^2), mm "
                                         "(default: the trephine's cutting radius).")
    blocks: list[str] = Field(["epithelium", "stroma"], description="Blocks split along the cylinder.")
    element_width: pydantic.PositiveFloat | None = Field(None, description="Width of the elements on either side of the "
                                                "cut along the anterior surface, mm (doubling away from it up to "
                                                "the mesh's width; default: the mesh's own).")
    strength: pydantic.PositiveFloat | dict[str, pydantic.PositiveFloat] = Field(
        description="Cohesive strength sigma_c, MPa: one value, or one per split block "
        "({ epithelium = 10.0, stroma = 5.0 }).")
    fracture_energy: pydantic.PositiveFloat | dict[str, pydantic.PositiveFloat] = Field(
        description="Toughness G_c, energy per unit area of the cut, N/mm: one value, or one per split block.")
    penalty_fraction: float = Field(0.3, gt=0.0, lt=0.76, description="Tie stiffness k = beta m* / dt^2: beta, "
                                    "dimensionless (stable below 4 (1 - s^2), 0.76 for the safety factor 0.9).")


RADIUS_TOLERANCE = 1e-9
"""Relative tolerance (of R) of a node on the cut cylinder."""


def cut_radius(scenario) -> float:
    """R of the cut, mm: ``cohesive_cut.radius`` or the trephine's cutting radius."""
    cut = scenario.cohesive_cut
    if cut.radius is not None:
        return float(cut.radius)
    shape = scenario.instrument.shape if scenario.instrument is not None else None
    if shape is None or not hasattr(shape, "cutting_radius"):
        raise InputError("cohesive_cut.radius: needed without a trephine (its cutting radius is the default)")
    return float(shape.cutting_radius)


def split_cornea(scenario, mesh: Mesh) -> tuple[Mesh, np.ndarray]:
    """The mesh split along the cut cylinder and the (original, copy) node pairs.

    Copies are left out of the node sets that carry cyclic symmetry (``solver._cyclic.pair_copies``
    pairs them afterwards); every other node set holds the copies of its split nodes.
    """
    cut = scenario.cohesive_cut
    radius = cut_radius(scenario)
    if mesh.axisymmetric:
        raise InputError("cohesive_cut: needs a 3D mesh (the axisymmetric cut would lie on the axis)")
    unknown = [block for block in cut.blocks if block not in mesh.block_names]
    if unknown:
        raise InputError(f"cohesive_cut.blocks: no block '{unknown[0]}' in the mesh "
                         f"(blocks: {', '.join(mesh.block_names)})")
    in_blocks = np.isin(mesh.element_block, [mesh.block_names.index(block) for block in cut.blocks])
    nodes = np.unique(mesh.cells[in_blocks])
    on_cylinder = nodes[np.abs(np.hypot(mesh.points[nodes, 0], mesh.points[nodes, 1]) - radius)
                        <= RADIUS_TOLERANCE * radius]
    # the side of an element: the mean radius of its nodes (its centroid lies inside the arc it
    # spans by a chord's sagitta, 0.2 % of r for 24 sectors: more than a fine column is wide)
    node_radius = np.hypot(mesh.points[:, 0], mesh.points[:, 1])
    outside = in_blocks & (node_radius[mesh.cells].mean(axis=1) > radius)
    split, pairs = split_nodes(mesh, on_cylinder, outside)
    reaches = [np.isin(on_cylinder, mesh.node_sets.get(name, [])).any()
               for name in ("anterior_surface", "inner_surface")]
    if pairs.size == 0 or not all(reaches):
        raise InputError(f"cohesive_cut: the mesh has no node surface on the cylinder r = {radius:g} mm "
                         f"from the anterior to the inner surface of the {'/'.join(cut.blocks)} blocks "
                         f"({on_cylinder.size} nodes on it): a mesh file needs a node line at r = R parallel to the axis")
    for name in {c.node_set for c in scenario.constraints if c.cyclic is not None} & set(split.node_sets):
        members = split.node_sets[name]
        split.node_sets[name] = members[~np.isin(members, pairs[:, 1])]
    return split, pairs


def block_values(mesh: Mesh, pairs: np.ndarray, area: np.ndarray, values, key: str, blocks: list[str]):
    """One value per tie: ``values`` itself, or, for a table by block, the mean of the blocks'
    values weighted by each block's share of the tie's area (a tie on the epithelium-stroma
    interface takes half of each)."""
    if not isinstance(values, dict):
        return float(values)
    missing = [block for block in blocks if block not in values]
    unknown = [block for block in values if block not in blocks]
    if missing or unknown:
        raise InputError(f"cohesive_cut.{key}: expected one value for each split block ({', '.join(blocks)}); "
                         f"{'missing ' + missing[0] if missing else 'not split: ' + unknown[0]}")
    total = np.zeros(len(pairs))
    for block in blocks:
        own = dataclasses.replace(mesh, cells=mesh.cells[mesh.element_block == mesh.block_names.index(block)])
        total += values[block] * tie_areas(own, pairs)
    return total / area


def make_ties(scenario, mesh: Mesh, model, pairs: np.ndarray) -> CohesiveTies:
    """The cohesive hook of the split mesh (history columns ``cohesive_*``)."""
    cut = scenario.cohesive_cut
    area = tie_areas(mesh, pairs)
    strength = block_values(mesh, pairs, area, cut.strength, "strength", cut.blocks)
    toughness = block_values(mesh, pairs, area, cut.fracture_energy, "fracture_energy", cut.blocks)
    return CohesiveTies(model, pairs, area, strength, toughness, cut.penalty_fraction, name="cohesive")
