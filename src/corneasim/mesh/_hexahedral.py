"""3D half model of the eye (y >= 0) in 8-node hexahedra, with the trephination paper's strategies.

The section strip (see :mod:`corneasim.mesh._strip`) is revolved over 180 degrees about
the optical axis. Around the apex and the posterior pole, where revolving would collapse
hexahedra onto the axis, an O-grid half disc (:mod:`corneasim.mesh._core`) is mapped onto
the shell and extruded through its layers. Sector counts change along the meridian
through bands of 3:1 sector transitions, layer counts through 3:1 layer transitions.

Strategies (the paper's Fig. 3 is not available; our reading, see ``docs/geometry.md``):

``umbrella``
    Through-thickness edges along the anterior-surface normals (ribs converging to the
    centre of curvature), the trephine annulus refined in both directions: fine radial
    columns, many sectors and three times the layers.
``vertical``
    Through-thickness edges parallel to the optical axis (the cornea partitioned by
    vertical cylinders), refined only by dense vertical partitions: fine radial
    columns in a wider band, the coarse layer count kept.
``horizontal``
    Through-thickness edges along the normals, refined only by dense horizontal
    partitions: many thin layers over the whole central cornea, with coarse columns.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from corneasim.errors import InputError
from corneasim.mesh._core import half_disc
from corneasim.mesh._mesh import Mesh
from corneasim.mesh._order import grouped_by_block
from corneasim.mesh._section import Section
from corneasim.mesh._sets import eye_sets
from corneasim.mesh._strip import Zone, build_strip, level_weights
from corneasim.mesh._axisymmetric import BLOCKS
from corneasim.mesh._geometry import EyeGeometry

TREPHINE_RADIUS = 3.75
"""Radius of the trephine of the paper (7.5 mm diameter), mm."""

STRATEGIES = ("umbrella", "vertical", "horizontal")

CUT_TURN = 1.0
"""Anterior-radius span (mm) over which an umbrella or horizontal mesh with a cut cylinder
turns its through-thickness lines from the normal (inside) to the axis (at the cut radius and
beyond, back to the normal at the limbus as the vertical strategy's): the node surface on
r = R that the split needs, the ribs' spacing at the posterior surface stretched by at most
the ratio of the normal's tilt over the span (about 1.4 at R = 3.75 mm)."""


@dataclass(frozen=True)
class SolidPreset:
    """Layers (finest level), zones from the apex core to the pole core, and the cores."""

    n_epithelium: int
    n_stroma: int
    zones: tuple[Zone, ...]
    core_radius: float  # plan radius of the apex O-grid, mm
    pole_arc: float  # arc length of the pole O-grid along the outer sclera, mm
    direction: str = "normal"
    epithelium_levels: int = 1


def _umbrella(fine: int, width: float, n_stroma: int = 9) -> SolidPreset:
    return SolidPreset(3, n_stroma, (
        Zone(3.0, 0.3, 0.15, 1, sectors=fine // 3),
        Zone(3.2, 0.1, 0.1, 1, sectors=fine),
        Zone(4.2, width, width, 0, True, sectors=fine),
        Zone(4.4, 0.1, 0.1, 1, sectors=fine),
        Zone("limbus", 0.25, 0.35, 1, sectors=fine // 3),
        Zone("pole", 0.8, 1.5, 2, sectors=fine // 3),
    ), core_radius=1.8, pole_arc=4.0)


def _vertical(fine: int, width: float, n_stroma: int = 4) -> SolidPreset:
    return SolidPreset(1, n_stroma, (
        Zone(2.6, 0.3, 0.12, 0, sectors=fine // 3),
        Zone(3.0, 0.1, 0.06, 0, sectors=fine),
        Zone(4.5, width, width, 0, True, sectors=fine),
        Zone(5.0, 0.06, 0.12, 0, sectors=fine),
        Zone("limbus", 0.2, 0.3, 0, sectors=fine // 3),
        Zone("pole", 0.6, 1.5, 1, sectors=fine // 3),
    ), core_radius=1.8, pole_arc=4.0, direction="vertical", epithelium_levels=0)


def _horizontal(fine: int, width: float, n_stroma: int = 18) -> SolidPreset:
    return SolidPreset(3, n_stroma, (
        Zone(2.8, 0.3, 0.2, 1, sectors=fine // 3),
        Zone(2.9, 0.15, 0.15, 1, sectors=fine),
        Zone(4.6, width, width, 0, True, sectors=fine),
        Zone(4.8, 0.15, 0.15, 1, sectors=fine),
        Zone("limbus", 0.3, 0.4, 1, sectors=fine // 3),
        Zone("pole", 0.8, 1.5, 2, sectors=fine // 3),
    ), core_radius=1.8, pole_arc=4.0)


SOLID_PRESETS = {
    "umbrella": {"coarse": _umbrella(24, 0.15, 6), "default": _umbrella(72, 0.072), "fine": _umbrella(96, 0.04)},
    "vertical": {"coarse": _vertical(24, 0.15, 3), "default": _vertical(72, 0.05), "fine": _vertical(108, 0.033)},
    "horizontal": {"coarse": _horizontal(24, 0.3, 9), "default": _horizontal(48, 0.108, 15), "fine": _horizontal(72, 0.08)},
}
"""Presets per strategy: ``coarse`` (~1-3k elements, tests), ``default`` (near the paper's Table 1), ``fine``."""


def _angles(n: int) -> np.ndarray:
    """Azimuths j pi / n, j = 0..n, as exact-rational multiples of pi (shared angles coincide)."""
    return np.array([math.pi * float(Fraction(j, n)) for j in range(n + 1)])


def _revolve(rz: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """(r, z) points at azimuths alpha to (x, y, z); y = 0 exactly at 0 and pi."""
    c, s = np.cos(alpha), np.sin(alpha)
    c[alpha == 0.0], s[alpha == 0.0] = 1.0, 0.0
    c[alpha == math.pi], s[alpha == math.pi] = -1.0, 0.0
    return np.stack([rz[:, 0] * c, rz[:, 0] * s, rz[:, 1]], axis=1)


class _Builder:
    """Collects hexahedra with their node coordinates and flags; merges coincident nodes."""

    def __init__(self):
        self.points, self.flags, self.hexes, self.blocks, self.refined = [], [], [], [], []
        self.count = 0

    def add_points(self, xyz: np.ndarray, s: np.ndarray, f: np.ndarray) -> np.ndarray:
        ids = np.arange(self.count, self.count + len(xyz))
        self.points.append(xyz)
        self.flags.append(np.stack([s, f], axis=1))
        self.count += len(xyz)
        return ids

    def add_hexes(self, hexes: np.ndarray, blocks: np.ndarray, refined: np.ndarray) -> None:
        self.hexes.append(hexes)
        self.blocks.append(blocks)
        self.refined.append(refined)

    def finish(self):
        points = np.concatenate(self.points)
        flags = np.concatenate(self.flags)
        key = np.round(points / 1e-8).astype(np.int64)
        _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
        hexes = inverse.ravel()[np.concatenate(self.hexes)]
        used = np.zeros(len(first), dtype=bool)
        used[hexes] = True
        renumber = np.cumsum(used) - 1
        first = first[used]
        hexes = _positive(points[first], renumber[hexes])
        return (points[first], flags[first], hexes, np.concatenate(self.blocks).astype(np.int64),
                np.concatenate(self.refined).astype(bool))


def _positive(points: np.ndarray, hexes: np.ndarray) -> np.ndarray:
    """Swap the bottom and top faces of hexahedra whose centre Jacobian is negative."""
    x = points[hexes]  # (n, 8, 3)
    d_xi = (x[:, 1] - x[:, 0] + x[:, 2] - x[:, 3] + x[:, 5] - x[:, 4] + x[:, 6] - x[:, 7])
    d_eta = (x[:, 3] - x[:, 0] + x[:, 2] - x[:, 1] + x[:, 7] - x[:, 4] + x[:, 6] - x[:, 5])
    d_zeta = (x[:, 4:] - x[:, :4]).sum(axis=1)
    negative = np.einsum("ni,ni->n", np.cross(d_xi, d_eta), d_zeta) < 0
    hexes = hexes.copy()
    hexes[negative] = np.concatenate([hexes[negative, 4:], hexes[negative, :4]], axis=1)
    return hexes


def mesh_3d(geometry: EyeGeometry | None = None, strategy: str = "umbrella",
                  preset: str = "default", cut_radius: float | None = None,
                  cut_element_width: float | None = None) -> Mesh:
    """Hexahedral half model of the eye for trephination.

    Parameters
    ----------
    geometry : EyeGeometry, optional
        Eye dimensions (mm); default: the porcine eye.
    strategy : {"umbrella", "vertical", "horizontal"}
        Meshing strategy of the trephination paper (Fig. 3, Table 1).
    preset : {"coarse", "default", "fine"}
    cut_radius : float, optional
        Anterior radius (mm) of a through-thickness node line in the refined zone (the
        nearest one is moved there), parallel to the axis (the umbrella and horizontal
        strategies turn their lines to the axis over :data:`CUT_TURN` inside it): the
        revolved line is the cylinder r = cut_radius through the cornea, a surface to split
        (``fracture.split_cornea``).
    cut_element_width : float, optional
        Width (mm, along the anterior surface) of the elements on either side of the cut
        line; they double away from it up to the zone's width.

    Returns
    -------
    Mesh
        Blocks ``epithelium``, ``stroma``, ``sclera``; surface sets ``inner_surface``,
        ``anterior_surface``; node sets ``inner_surface``, ``anterior_surface``,
        ``lower_hemisphere``, ``symmetry_plane``; element set ``refined`` (the trephine area).
    """
    if strategy not in SOLID_PRESETS:
        raise InputError(f"unknown meshing strategy '{strategy}' (expected {', '.join(STRATEGIES)})")
    if preset not in SOLID_PRESETS[strategy]:
        raise InputError(f"unknown mesh preset '{preset}' (expected coarse, default, fine)")
    geometry = geometry or EyeGeometry()
    shape = geometry.shape()
    spec = SOLID_PRESETS[strategy][preset]
    if cut_radius is not None and spec.direction == "normal":
        section = Section(shape, "vertical", normal_within=(cut_radius - CUT_TURN, cut_radius))
    else:
        section = Section(shape, spec.direction)
    s_core = section.s_of_radius(spec.core_radius)
    s_pole_core = section.s_pole - spec.pole_arc
    strip = build_strip(section, list(spec.zones), spec.n_epithelium, spec.n_stroma,
                        s_start=s_core, s_stop=s_pole_core, epithelium_levels=spec.epithelium_levels,
                        snap=None if cut_radius is None else section.s_of_radius(cut_radius),
                        snap_width=cut_element_width)
    builder = _Builder()
    first, last = spec.zones[0], spec.zones[-1]
    _core(builder, section, s_core, first.sectors,
          level_weights(spec.n_epithelium, spec.n_stroma, first.level, spec.epithelium_levels), apex=True)
    _core(builder, section, spec.pole_arc, last.sectors,
          level_weights(spec.n_epithelium, spec.n_stroma, last.level, spec.epithelium_levels), apex=False)
    _revolved(builder, section, strip)
    points, flags, hexes, blocks, refined = builder.finish()
    s, f = flags[:, 0], flags[:, 1]
    surface_sets, node_sets = eye_sets(
        points, hexes, "hexahedron", outer=f == 0.0, inner=f == 1.0,
        cornea=s <= section.s_limbus, globe_centre=shape.globe_centre,
    )
    node_sets["symmetry_plane"] = np.flatnonzero(np.abs(points[:, 1]) < 1e-9).astype(np.int64)
    mesh = Mesh(points=points, cells=hexes, cell_type="hexahedron", element_block=blocks,
                block_names=list(BLOCKS), axisymmetric=False, node_sets=node_sets,
                element_sets={"refined": np.flatnonzero(refined).astype(np.int64)},
                surface_sets=surface_sets)
    mesh = grouped_by_block(mesh)
    mesh.validate()
    return mesh


def _core(builder: _Builder, section: Section, radius: float, sectors: int, weights, apex: bool) -> None:
    """O-grid half disc of plan radius ``radius`` (arc length) mapped onto the shell at a pole."""
    weights_e, weights_s = weights
    n_e = len(weights_e)
    sigma, alpha, quads = half_disc(radius, sectors)
    rim = sigma == radius
    alpha[rim] = _angles(sectors)[np.round(alpha[rim] / (math.pi / sectors)).astype(int)]
    s = sigma if apex else section.s_pole - sigma
    n_layers = n_e + len(weights_s)
    fractions = np.stack([section.station_fractions(value, weights_e, weights_s) for value in s])  # (n, L + 1)
    s_all = np.repeat(s, n_layers + 1)
    rz = section.points(s_all, fractions.ravel())
    xyz = _revolve(rz, np.repeat(alpha, n_layers + 1))
    ids = builder.add_points(xyz, s_all, fractions.ravel()).reshape(-1, n_layers + 1)
    layers = np.arange(n_layers)
    hexes = np.concatenate([ids[quads][:, :, layers + 1], ids[quads][:, :, layers]], axis=1)  # (q, 8, L)
    hexes = hexes.transpose(0, 2, 1).reshape(-1, 8)
    part = np.where(layers < n_e, 0, 1) if apex else np.full(n_layers, 2)
    builder.add_hexes(hexes, np.tile(part, len(quads)), np.zeros(len(hexes), dtype=bool))


def _revolved(builder: _Builder, section: Section, strip) -> None:
    """Revolve the strip's bands; bands whose sector count changes get 3:1 sector transitions."""
    cache: dict[int, np.ndarray] = {}

    def ring_ids(sectors: int) -> np.ndarray:
        if sectors not in cache:
            alpha = _angles(sectors)
            n = len(strip.points)
            xyz = _revolve(np.repeat(strip.points, sectors + 1, axis=0), np.tile(alpha, n))
            ids = builder.add_points(xyz, np.repeat(strip.s, sectors + 1), np.repeat(strip.f, sectors + 1))
            cache[sectors] = ids.reshape(n, sectors + 1)
        return cache[sectors]

    left_sectors, right_sectors = strip.band_sectors[strip.band, 0], strip.band_sectors[strip.band, 1]
    same = left_sectors == right_sectors
    for sectors in np.unique(left_sectors[same]):
        select = np.flatnonzero(same & (left_sectors == sectors))
        ids = ring_ids(int(sectors))
        j = np.arange(sectors)
        quads = strip.quads[select]  # (q, 4)
        hexes = np.concatenate([ids[quads][:, :, j + 1], ids[quads][:, :, j]], axis=1)  # (q, 8, n)
        builder.add_hexes(hexes.transpose(0, 2, 1).reshape(-1, 8), np.repeat(strip.part[select], sectors),
                          np.repeat(strip.refined[select], sectors))
    for index in np.flatnonzero(~same):
        _sector_transition(builder, section, strip, index, int(left_sectors[index]), int(right_sectors[index]),
                           ring_ids)


def _sector_transition(builder, section, strip, quad, n_left, n_right, ring_ids) -> None:
    """Hexahedra of one strip quad in a band that triples (or thirds) the sectors."""
    left_k, right_k, right_k1, left_k1 = strip.raw_quads[quad]
    if n_right > n_left:
        coarse_nodes, fine_nodes, n_coarse, n_fine = (left_k, left_k1), (right_k, right_k1), n_left, n_right
    else:
        coarse_nodes, fine_nodes, n_coarse, n_fine = (right_k, right_k1), (left_k, left_k1), n_right, n_left
    coarse_ids, fine_ids = ring_ids(n_coarse), ring_ids(n_fine)
    alpha = _angles(n_fine)
    mid_alpha = np.stack([alpha[1:-1:3], alpha[2::3]], 1).ravel()  # (2 n_coarse,)
    levels = []
    for c_node, f_node in zip(coarse_nodes, fine_nodes):
        s_mid = 0.5 * (strip.s[c_node] + strip.s[f_node])
        f_mid = 0.5 * (strip.f[c_node] + strip.f[f_node])
        rz = section.points(np.array([s_mid]), np.array([f_mid]))[0]
        xyz = _revolve(np.repeat(rz[None], mid_alpha.size, 0), mid_alpha)
        mids = builder.add_points(xyz, np.full(mid_alpha.size, s_mid), np.full(mid_alpha.size, f_mid))
        mids = mids.reshape(-1, 2)
        c, fi = coarse_ids[c_node], fine_ids[f_node]
        levels.append(np.concatenate([
            np.stack([fi[0:-1:3], fi[1::3], mids[:, 0], c[:-1]], 1),
            np.stack([fi[1::3], fi[2::3], mids[:, 1], mids[:, 0]], 1),
            np.stack([fi[2::3], fi[3::3], c[1:], mids[:, 1]], 1),
            np.stack([c[:-1], mids[:, 0], mids[:, 1], c[1:]], 1),
        ]))
    hexes = np.concatenate([levels[1], levels[0]], axis=1)
    builder.add_hexes(hexes, np.full(len(hexes), strip.part[quad]), np.full(len(hexes), strip.refined[quad]))
