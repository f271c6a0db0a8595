"""Axisymmetric mesh of the eye for needle insertion: 4-node quads in the (r, z) half-plane.

The insertion area (the central cornea around the axis, where the needle enters) is
meshed with near-square elements of the epithelium's layer height; columns then grow
and the layer count drops through 3:1 transitions towards the limbus and the sclera.
The ``refined`` element set is the insertion area (about 70% of the elements in the
``default`` preset, as the needle paper's 11,683 of 16,923).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from corneasim.errors import InputError
from corneasim.mesh._mesh import Mesh
from corneasim.mesh._order import grouped_by_block
from corneasim.mesh._section import Section
from corneasim.mesh._sets import eye_sets
from corneasim.mesh._strip import Zone, build_strip
from corneasim.mesh._geometry import EyeGeometry

BLOCKS = ["epithelium", "stroma", "sclera"]


@dataclass(frozen=True)
class StripPreset:
    """Layer counts at the finest level and the zones from the apex to the pole."""

    n_epithelium: int
    n_stroma: int
    zones: tuple[Zone, ...]
    epithelium_levels: int = 1


AXISYMMETRIC_PRESETS = {
    "coarse": StripPreset(3, 12, (
        Zone(0.4, 0.03, 0.03, 0, True),
        Zone(1.5, 0.03, 0.07, 0, True),
        Zone("limbus", 0.1, 0.25, 1),
        Zone("pole", 0.3, 0.8, 1),
    )),
    "default": StripPreset(9, 63, (
        Zone(0.5, 0.0077, 0.0077, 0, True),
        Zone(2.0, 0.0077, 0.023, 0, True),
        Zone(4.2, 0.025, 0.07, 1),
        Zone("limbus", 0.075, 0.1, 2),
        Zone("pole", 0.1, 0.1, 2),
    )),
    "fine": StripPreset(12, 87, (
        Zone(0.5, 0.0056, 0.0056, 0, True),
        Zone(2.2, 0.0056, 0.017, 0, True),
        Zone(4.2, 0.02, 0.05, 1),
        Zone("limbus", 0.05, 0.07, 2),
        Zone("pole", 0.07, 0.1, 2),
    )),
    "needle-path": StripPreset(9, 63, (
        Zone(0.25, 0.0077, 0.0077, 0, True),
        Zone(0.7, 0.023, 0.035, 1),
        Zone("limbus", 0.07, 0.12, 2),
        Zone("pole", 0.25, 0.3, 3),
    ), epithelium_levels=2),
    # the needle-path family, elements 2x and 4x the needle-path's along the path (convergence studies)
    "needle-path-2x": StripPreset(4, 32, (
        Zone(0.25, 0.0154, 0.0154, 0, True),
        Zone(0.7, 0.023, 0.035, 1),
        Zone("limbus", 0.07, 0.12, 2),
        Zone("pole", 0.25, 0.3, 3),
    ), epithelium_levels=2),
    "needle-path-4x": StripPreset(2, 16, (
        Zone(0.25, 0.0308, 0.0308, 0, True),
        Zone(0.7, 0.031, 0.035, 1),
        Zone("limbus", 0.07, 0.12, 2),
        Zone("pole", 0.25, 0.3, 3),
    ), epithelium_levels=1),
}
"""Mesh presets: ``coarse`` (fast tests, ~1,000 elements), ``default`` (~17,000), ``fine``, and
``needle-path`` (~3,750): the default's 7.7 um elements only within 0.25 mm of the axis (2.5
needle radii), then near-square elements of 23 um to 0.7 mm, 67 um to the limbus (one
epithelium layer) and 0.25 mm in the sclera; ``needle-path-2x`` and ``needle-path-4x`` have
elements 2 and 4 times as large along the path (15 and 31 um; 4 and 2 epithelium layers),
for convergence studies (``validation/needle_cut_convergence.py``). Mass scaling to a target step gives an element the
scaled density rho (dt* c / (s L_min))^2, so this mesh carries about 1/7 of the default's
artificial mass within 1 mm of the axis and 1/7 in total (docs/calibration.md, "Mass scaling")."""


def mesh_axisymmetric(geometry: EyeGeometry | None = None, preset: str = "default") -> Mesh:
    """Axisymmetric quad mesh of the eye with the insertion area refined around the apex.

    Parameters
    ----------
    geometry : EyeGeometry, optional
        Eye dimensions (mm); default: the porcine eye.
    preset : {"coarse", "default", "fine", "needle-path", "needle-path-2x", "needle-path-4x"}
        Mesh density.

    Returns
    -------
    Mesh
        Blocks ``epithelium``, ``stroma``, ``sclera``; surface sets ``inner_surface``,
        ``anterior_surface``; node sets ``inner_surface``, ``anterior_surface``,
        ``lower_hemisphere``, ``axis``; element set ``refined``.
    """
    if preset not in AXISYMMETRIC_PRESETS:
        raise InputError(f"unknown mesh preset '{preset}' (expected {', '.join(AXISYMMETRIC_PRESETS)})")
    geometry = geometry or EyeGeometry()
    shape = geometry.shape()
    spec = AXISYMMETRIC_PRESETS[preset]
    section = Section(shape, "normal")
    strip = build_strip(section, list(spec.zones), spec.n_epithelium, spec.n_stroma,
                        epithelium_levels=spec.epithelium_levels)
    points = strip.points
    points[:, 0] = np.maximum(points[:, 0], 0.0)
    on_axis = (strip.s == 0.0) | (strip.s >= section.s_pole)
    points[on_axis, 0] = 0.0
    surface_sets, node_sets = eye_sets(
        points, strip.quads, "quad", outer=strip.f == 0.0, inner=strip.f == 1.0,
        cornea=strip.s <= section.s_limbus, globe_centre=shape.globe_centre,
    )
    node_sets["axis"] = np.flatnonzero(on_axis).astype(np.int64)
    mesh = Mesh(
        points=points,
        cells=strip.quads,
        cell_type="quad",
        element_block=strip.part,
        block_names=list(BLOCKS),
        axisymmetric=True,
        node_sets=node_sets,
        element_sets={"refined": np.flatnonzero(strip.refined).astype(np.int64)},
        surface_sets=surface_sets,
    )
    mesh = grouped_by_block(mesh)
    mesh.validate()
    return mesh
