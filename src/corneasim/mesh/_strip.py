"""Structured quadrilateral mesh of the eye section with graded columns and 3:1 layer transitions.

The strip is a sequence of *stations* (through-thickness node lines at parameters s)
joined by *bands* of quadrilaterals. A zone keeps its layers (epithelium, stroma)
and grades its column widths; between zones of different refinement level a
transition band joins 3 fine layers to 1 coarse layer with the conforming four-quad
template (three quads on the fine side, one on the coarse side, two mid nodes), so the
layer count changes from n to n - 2 floor(n / 3) in each part without hanging nodes.
Layers carry weights (the number of finest layers they span) that set their thickness
fractions, so coarse layers stay aligned with the fine ones they replace.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from corneasim.errors import InputError
from corneasim.mesh._section import Section

MID_FRACTION = 0.5
"""Position of a transition's mid nodes across the band, from the fine side (0.5 to 0.7 keeps
the fine-side quads from flattening, which would shorten the stable time step)."""


def coarsen(weights: tuple[int, ...]) -> tuple[int, ...]:
    """Layer weights after one 3:1 transition: full triples merge, the rest pass through.

    A weight counts the finest layers a layer spans, so coarse layers stay exactly aligned
    with the fine layers they replace (``(1,) * 7`` gives ``(3, 3, 1)``).
    """
    triples = len(weights) // 3
    return tuple(sum(weights[3 * i:3 * i + 3]) for i in range(triples)) + tuple(weights[3 * triples:])


def level_weights(n_epithelium: int, n_stroma: int, level: int,
                  epithelium_levels: int = 99) -> tuple[tuple[int, ...], tuple[int, ...]]:
    """(epithelium, stroma) layer weights after ``level`` transitions from the finest.

    The epithelium takes part in the first ``epithelium_levels`` transitions only (its
    layers are thinner than the stroma's; coarsening it further would flatten them).
    """
    epithelium, stroma = (1,) * n_epithelium, (1,) * n_stroma
    for step in range(level):
        if step < epithelium_levels:
            epithelium = coarsen(epithelium)
        stroma = coarsen(stroma)
    return epithelium, stroma


@dataclass(frozen=True)
class Zone:
    """A run of columns at one refinement level.

    end : float or str
        End of the zone: anterior plan radius in mm, ``"limbus"`` or ``"pole"``.
    width_start, width_end : float
        Column widths (mm of s) at the zone's ends; graded linearly in between.
    level : int
        Refinement level: 0 = finest layer counts, each level one 3:1 coarsening.
    refined : bool
        Whether the zone's elements belong to the ``refined`` element set.
    sectors : int
        Sectors over 180 degrees when the strip is revolved (3D); a change between zones
        inserts a band of 3:1 sector transitions (same layers on both sides), before the
        layer transition when the level changes too.
    """

    end: float | str
    width_start: float
    width_end: float
    level: int
    refined: bool = False
    sectors: int = 0


@dataclass
class Strip:
    """The strip mesh: nodes with their parameters and flags, quads with part and zone data."""

    points: np.ndarray  # (n_nodes, 2) r, z in mm
    s: np.ndarray  # (n_nodes,)
    f: np.ndarray  # (n_nodes,)
    quads: np.ndarray  # (n_quads, 4) counter-clockwise in (r, z)
    part: np.ndarray  # (n_quads,) 0 = epithelium layers, 1 = stroma layers, 2 = sclera
    refined: np.ndarray  # (n_quads,) bool
    raw_quads: np.ndarray  # (n_quads, 4) before orientation: left k, right k, right k+1, left k+1
    band: np.ndarray  # (n_quads,) index of the band (between stations band and band + 1)
    band_sectors: np.ndarray  # (n_bands, 2) sectors at the band's left and right station
    first_station: np.ndarray  # node indices of the first station, outer to inner
    last_station: np.ndarray  # node indices of the last station, outer to inner


def _column_widths(length: float, w0: float, w1: float) -> np.ndarray:
    n = max(1, int(round(2.0 * length / (w0 + w1))))
    w = w0 + (w1 - w0) * (np.arange(n) + 0.5) / n
    return w * (length / w.sum())


def _zone_end(section: Section, end: float | str) -> float:
    if end == "limbus":
        return section.s_limbus
    if end == "pole":
        return section.s_pole
    return section.s_of_radius(min(float(end), section.shape.geometry.limbus_radius))


def build_strip(section: Section, zones: list[Zone], n_epithelium: int, n_stroma: int,
                s_start: float = 0.0, s_stop: float | None = None,
                transition_width: float = 3.0, epithelium_levels: int = 99,
                snap: float | None = None, snap_width: float | None = None) -> Strip:
    """Mesh the section between s_start and s_stop (default: the pole).

    Parameters
    ----------
    section : Section
    zones : list of Zone
        Consecutive zones; a zone ending beyond ``s_stop`` is cut there.
    n_epithelium, n_stroma : int
        Finest layer counts (level 0).
    transition_width : float
        Width of a transition band in units of the thinnest fine layer being coarsened.
    epithelium_levels : int
        Number of transitions the epithelium takes part in (see :func:`level_weights`).
    snap : float, optional
        Arc length s (mm) that a station must have: the nearest station of a refined zone is
        moved there (at most half its column width), so that a node line sits exactly on it.
    snap_width : float, optional
        Width (mm of s) of the columns on either side of the snapped line; they double away
        from it until they reach the zone's own width (a band of fine columns at the line).
    """
    s_stop = section.s_pole if s_stop is None else s_stop
    stations: list[tuple] = []  # s, epithelium weights, stroma weights, sectors, refined
    s = s_start
    previous_level = previous_sectors = None
    for zone in zones:
        n_e, n_s = level_weights(n_epithelium, n_stroma, zone.level, epithelium_levels)
        end = min(_zone_end(section, zone.end), s_stop)
        if end <= s + 1e-12:
            continue
        if previous_sectors is not None and zone.sectors != previous_sectors:
            previous_e, previous_s = level_weights(n_epithelium, n_stroma, previous_level, epithelium_levels)
            fine = max(zone.sectors, previous_sectors)
            radius = float(section.points(np.array([s]), np.array([0.0]))[0, 0])
            s = min(s + np.pi * radius / fine * 1.5, end - 1e-9)
            stations.append((s, previous_e, previous_s, zone.sectors, False))
        if previous_level is not None and zone.level != previous_level:
            fine_level = min(zone.level, previous_level)
            f_e, f_s = level_weights(n_epithelium, n_stroma, fine_level, epithelium_levels)
            c_e, _ = level_weights(n_epithelium, n_stroma, fine_level + 1, epithelium_levels)
            thickness = _local_thickness(section, s)
            epithelium = section.shape.geometry.epithelium_thickness
            height = (thickness - epithelium) * min(f_s) / sum(f_s)
            if c_e != f_e:
                height = min(height, epithelium * min(f_e) / sum(f_e))
            s = min(s + transition_width * height, end - 1e-9)
            stations.append((s, n_e, n_s, zone.sectors, False))
        elif not stations:
            stations.append((s, n_e, n_s, zone.sectors, False))
        if end - s > 1e-6:
            for w in _column_widths(end - s, zone.width_start, zone.width_end):
                s += w
                stations.append((s, n_e, n_s, zone.sectors, zone.refined))
        stations[-1] = (end, n_e, n_s, zone.sectors, stations[-1][4])
        s = end
        previous_level, previous_sectors = zone.level, zone.sectors
    if snap is not None:
        refined = [k for k, station in enumerate(stations) if station[4] and 0 < k < len(stations) - 1]
        if not refined:
            raise InputError("mesh: no refined zone to place the cut surface in")
        k = min(refined, key=lambda k: abs(stations[k][0] - snap))
        if not stations[k - 1][0] + 0.5 * (stations[k][0] - stations[k - 1][0]) <= snap \
                <= stations[k][0] + 0.5 * (stations[k + 1][0] - stations[k][0]):
            raise InputError(f"mesh: the cut surface (s = {snap:.4g} mm) is outside the refined zone")
        stations[k] = (snap,) + tuple(stations[k][1:])
        if snap_width is not None:
            spacing = min(stations[k][0] - stations[k - 1][0], stations[k + 1][0] - stations[k][0])
            offsets, width = [], float(snap_width)
            while width < 0.75 * spacing:
                offsets.append(width)
                width *= 2.0
            band = [(snap + sign * offset,) + tuple(stations[k][1:]) for offset in offsets for sign in (-1.0, 1.0)]
            stations = sorted(stations + band, key=lambda station: station[0])
    return _assemble(section, stations, s_stop)


def _local_thickness(section: Section, s: float) -> float:
    points = section.points(np.array([s, s]), np.array([0.0, 1.0]))
    return float(np.linalg.norm(points[1] - points[0]))


def _assemble(section: Section, stations, s_stop: float) -> Strip:
    s_nodes, f_nodes, station_nodes = [], [], []
    count = 0
    for s, n_e, n_s, _, _ in stations:
        fractions = section.station_fractions(s, n_e, n_s)
        station_nodes.append(np.arange(count, count + fractions.size))
        s_nodes.append(np.full(fractions.size, s))
        f_nodes.append(fractions)
        count += fractions.size
    quads, parts, refined, bands = [], [], [], []
    for i in range(len(stations) - 1):
        s_a, e_a, t_a, _, _ = stations[i]
        s_b, e_b, t_b, _, flag = stations[i + 1]
        left, right = station_nodes[i], station_nodes[i + 1]
        cornea = 0.5 * (s_a + s_b) <= section.s_limbus
        if (e_a, t_a) == (e_b, t_b):
            k = np.arange(len(e_a) + len(t_a))
            quads.append(np.stack([left[k], right[k], right[k + 1], left[k + 1]], axis=1))
            part = np.where(k < len(e_a), 0, 1) if cornea else np.full(k.size, 2)
            parts.append(part)
            refined.append(np.full(k.size, flag))
            bands.append(np.full(k.size, i))
            continue
        fine_left = len(e_b) + len(t_b) < len(e_a) + len(t_a)
        fine, coarse = (left, right) if fine_left else (right, left)
        s_fine, s_coarse = (s_a, s_b) if fine_left else (s_b, s_a)
        a, b = (len(e_a), len(t_a)), (len(e_b), len(t_b))
        counts = (a, b) if fine_left else (b, a)
        new_quads, new_parts, mids = _transition(fine, coarse, counts, count, f_nodes, station_nodes,
                                                 i if fine_left else i + 1, i + 1 if fine_left else i)
        s_mid = s_fine + MID_FRACTION * (s_coarse - s_fine)
        s_nodes.append(np.full(mids.size, s_mid))
        f_nodes.append(mids)
        count += mids.size
        quads.append(new_quads)
        parts.append(new_parts if cornea else np.full(len(new_parts), 2))
        refined.append(np.zeros(len(new_quads), dtype=bool))
        bands.append(np.full(len(new_quads), i))
    s_all = np.concatenate(s_nodes)
    f_all = np.concatenate(f_nodes)
    points = section.points(s_all, f_all)
    raw = np.concatenate(quads).astype(np.int64)
    sectors = np.array([station[3] for station in stations])
    return Strip(points, s_all, f_all, _counter_clockwise(points, raw), np.concatenate(parts).astype(np.int64),
                 np.concatenate(refined).astype(bool), raw, np.concatenate(bands).astype(np.int64),
                 np.stack([sectors[:-1], sectors[1:]], 1), station_nodes[0], station_nodes[-1])


def _transition(fine, coarse, counts, first_new, f_nodes, station_nodes, fine_index, coarse_index):
    """Quads of a 3:1 transition band; returns quads, parts and the mid-node fractions."""
    (fine_e, fine_s), (coarse_e, coarse_s) = counts
    F = f_nodes[fine_index]
    G = f_nodes[coarse_index]
    quads, parts, mids = [], [], []
    a = b = 0
    for part, (n_fine, n_coarse) in enumerate(((fine_e, coarse_e), (fine_s, coarse_s))):
        triples = (n_fine - n_coarse) // 2
        assert n_coarse == n_fine - 2 * triples and 3 * triples <= n_fine
        for group in range(n_coarse):
            if group < triples:
                m1 = first_new + len(mids)
                m2 = m1 + 1
                mids.append(0.5 * (F[a + 1] + G[b] + (G[b + 1] - G[b]) / 3.0))
                mids.append(0.5 * (F[a + 2] + G[b] + 2.0 * (G[b + 1] - G[b]) / 3.0))
                quads += [
                    [fine[a], coarse[b], m1, fine[a + 1]],
                    [fine[a + 1], m1, m2, fine[a + 2]],
                    [fine[a + 2], m2, coarse[b + 1], fine[a + 3]],
                    [m1, coarse[b], coarse[b + 1], m2],
                ]
                parts += [part] * 4
                a += 3
            else:
                quads.append([fine[a], coarse[b], coarse[b + 1], fine[a + 1]])
                parts.append(part)
                a += 1
            b += 1
    return np.array(quads, dtype=np.int64), np.array(parts), np.array(mids)


def _counter_clockwise(points: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """Reorder quads with negative signed area in (r, z) to counter-clockwise."""
    x = points[quads]  # (n, 4, 2)
    area = 0.5 * np.sum(x[:, :, 0] * np.roll(x[:, :, 1], -1, 1) - np.roll(x[:, :, 0], -1, 1) * x[:, :, 1], 1)
    flipped = quads.copy()
    flipped[area < 0] = quads[area < 0][:, ::-1]
    return flipped
