"""Stress maps of a section, drawn as the papers draw them (needle paper Fig. 10, trephination Fig. 5).

A von Mises field in a punctured cornea spans three orders of magnitude: a few elements
under the instrument's tip carry tens of MPa while the rest of the cornea carries well
under 1 MPa. A linear scale from 0 to the peak paints the whole section in the colour of
zero. The maps therefore scale the colours linearly from 0 to a high percentile of the
values they show, :data:`CLIP_PERCENTILE` of the elements drawn in the window; the few
elements above it take the top colour, the colour bar's arrow says so, and its label
states the rule, the clipping value and the peak.

The colour map is perceptually uniform (viridis: equal steps in value are equal steps in
lightness, and it reads in grey and for colour-blind eyes). The elements are filled
without edges and without antialiasing, so no mesh lines and no moiré of seams appear;
each element has its own (constant) colour, as the element computes it. The window is
centred on the region that matters, the instrument's lowest point (:func:`tip_window`),
and the title says what happened at that instant (:func:`map_title`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure

from corneasim.output._plots import draw_instrument, save

CLIP_PERCENTILE = 99.0
"""Percentile of the drawn elements' values at which the colour scale ends, %."""

COLOUR_MAP = "viridis"

EVENTS = {
    "epithelium": "epithelium punctured",
    "stroma": "stroma punctured",
    "cornea": "cornea punctured",
    "end": "end of the run",
}
"""What a snapshot's name means, for the titles (other names are times of the papers' figures)."""


def colour_limits(values: np.ndarray, percentile: float = CLIP_PERCENTILE) -> tuple[float, float]:
    """Colour scale (lower, upper) of a map: 0 to the ``percentile`` of ``values``.

    The upper limit is at least 1e-12 of the values' unit (a field that is zero everywhere
    still gets a valid scale).
    """
    values = np.asarray(values, dtype=float)
    upper = float(np.percentile(values, percentile)) if values.size else 0.0
    return 0.0, max(upper, 1e-12)


def colour_label(quantity: str, unit: str, upper: float, peak: float,
                 percentile: float = CLIP_PERCENTILE) -> str:
    """The colour bar's label: the quantity, its unit and the clipping rule with its values."""
    return f"{quantity}, {unit}\nlinear, clipped at the {percentile:g}th percentile ({upper:.3g}); peak {peak:.3g}"


def map_title(quantity: str, name: str, time: float, position: str | None = None, events=None) -> str:
    """The title of a map: the quantity, then the event (or instant) with its time and position.

    ``events`` maps snapshot names to what happened (default :data:`EVENTS`); other names
    are instants, titled by their time alone.

    >>> map_title("von Mises stress", "stroma", 0.437, "depth 0.437 mm")
    'von Mises stress\\nstroma punctured, t = 0.437 s, depth 0.437 mm'
    """
    event = (EVENTS if events is None else events).get(name)
    text = f"{event}, t = {time:.3g} s" if event else f"t = {time:.3g} s"
    return f"{quantity}\n{text}, {position}" if position else f"{quantity}\n{text}"


def lowest_point(section) -> tuple[float, float] | None:
    """(x, z) of the lowest grid point inside an instrument's section (X, Z, D), mm (D < 0 inside);
    None without a section or when the section misses the grid."""
    if section is None:
        return None
    X, Z, D = section
    inside = D < 0.0
    if not inside.any():
        return None
    index = np.argmin(np.where(inside, Z, np.inf))
    return float(X.flat[index]), float(Z.flat[index])


def tip_window(tip_z: float, x_centre: float, half_width: float, below: float, above: float):
    """The window ((x0, x1), (z0, z1)) in mm around an instrument tip at height ``tip_z``."""
    return (x_centre - half_width, x_centre + half_width), (tip_z - below, tip_z + above)


def in_window(polygons: np.ndarray, x_limits, z_limits) -> np.ndarray:
    """Which polygons (n, corners, 2) overlap the window (their bounding boxes do), bool (n,)."""
    low, high = polygons.min(axis=1), polygons.max(axis=1)
    return ((high[:, 0] >= x_limits[0]) & (low[:, 0] <= x_limits[1])
            & (high[:, 1] >= z_limits[0]) & (low[:, 1] <= z_limits[1]))


def stress_map(polygons: np.ndarray, values: np.ndarray, *, title: str, path: Path, x_limits, z_limits,
               instrument=None, x_label: str = "x, mm", quantity: str = "von Mises stress",
               unit: str = "MPa", figure_size=(6.4, 4.4)) -> tuple[float, float]:
    """Draw cell values on polygons of the deformed section in a window and save the PNG.

    Parameters
    ----------
    polygons : ndarray (n, corners, 2)
        The live elements' sections, deformed, mm (horizontal, vertical).
    values : ndarray (n,)
        One value per polygon (e.g. von Mises stress, MPa).
    title, path
        Title and PNG file.
    x_limits, z_limits : (float, float)
        The window, mm.
    instrument : (X, Z, D), optional
        The instrument's section to draw over the tissue (``plots.draw_instrument``).

    Returns
    -------
    (float, float)
        The colour limits used (:func:`colour_limits` of the values drawn in the window).
    """
    polygons = np.asarray(polygons, dtype=float)
    values = np.asarray(values, dtype=float)
    shown = in_window(polygons, x_limits, z_limits) if len(polygons) else np.zeros(0, dtype=bool)
    limits = colour_limits(values[shown])
    peak = float(values[shown].max(initial=0.0))
    figure = Figure(figsize=figure_size)
    axes = figure.subplots()
    collection = PolyCollection(polygons[shown], array=values[shown], cmap=COLOUR_MAP, edgecolors="face",
                                linewidths=0.0, antialiased=False)
    collection.set_clim(*limits)
    axes.add_collection(collection)
    draw_instrument(axes, instrument)
    axes.set_xlim(*x_limits)
    axes.set_ylim(*z_limits)
    axes.set_aspect("equal")
    axes.set_facecolor("white")
    axes.set_xlabel(x_label)
    axes.set_ylabel("z, mm")
    axes.set_title(title, fontsize=9)
    bar = figure.colorbar(collection, ax=axes, extend="max" if peak > limits[1] else "neither")
    bar.set_label(colour_label(quantity, unit, limits[1], peak), fontsize=8)
    save(figure, path)
    return limits


def axisymmetric_section(points, cells, displacement, values, alive) -> tuple[np.ndarray, np.ndarray]:
    """The live quads of an axisymmetric (r, z) model, deformed and mirrored about the axis to a full section.

    Parameters
    ----------
    points : ndarray (n_nodes, 2)
        Reference (r, z), mm.
    cells : ndarray (n_elements, 4)
    displacement : ndarray (n_nodes, 2)
        mm.
    values : ndarray (n_elements,)
    alive : ndarray (n_elements,)
        Dead elements (0) are left out.

    Returns
    -------
    polygons : ndarray (2 n_live, 4, 2)
        mm; the mirrored copies (-r, z) follow the originals.
    values : ndarray (2 n_live,)
    """
    keep = np.flatnonzero(np.asarray(alive) != 0)
    quads = (np.asarray(points) + np.asarray(displacement))[np.asarray(cells)[keep]]  # (n_live, 4, 2)
    return np.concatenate([quads, quads * np.array([-1.0, 1.0])]), np.tile(np.asarray(values)[keep], 2)
