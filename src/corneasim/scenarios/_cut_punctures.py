"""Puncture events of a needle whose path is cut by radial cracks (``[cut]``, no deletions).

The needle's path is the column of cornea elements on the axis (``_punctures.path_column``).
A layer of it is *punctured* when

* the crack of every element of the layer in that column has started and opened
  (delta_max > 0: the crack on the axis has run through the layer down to its posterior
  surface), and
* the needle's tip has passed the layer's posterior surface on the axis: the tip is below the
  current height of the layer's lowest node on the axis (that node has moved aside: a node
  cannot be passed through).

``epithelium``: the epithelium's elements of the column are punctured; ``stroma``: the
epithelium is, and the crack has opened in the column's first stroma element (the cut has
entered the stroma); ``cornea``: every element of the column is. Each is recorded once, at
the solver time of the step that meets it, in ``State.event_time``; it is checked every
:data:`CHECK_EVERY` steps.
"""

from __future__ import annotations

import math

import numpy as np

from corneasim.fracture._radial_cracks import OPENING_MAX
from corneasim.instruments import POSE_Z
from corneasim.scenarios._punctures import EVENT_INDEX, path_column

CHECK_EVERY = 10
"""Steps between two checks of the events (10 steps of 2e-5 s: 0.2 um of travel at 1 mm/s)."""


class CutPunctures:
    """Hook recording the puncture events of a cut needle path (module notes); no forces.

    Parameters
    ----------
    setup : Setup
        With an instrument and a cut band (``model.radial_cracks``).
    """

    name = "cut_punctures"

    def __init__(self, setup):
        self.instrument = setup.instrument
        cracks = setup.model.radial_cracks
        mesh = setup.mesh
        elements, blocks, _ = path_column(setup)
        position = np.full(mesh.n_elements, -1, np.int64)
        position[cracks.band] = np.arange(cracks.n_band)
        self.layers = {}
        epithelium = elements[blocks == "epithelium"]
        stroma = elements[blocks != "epithelium"]
        if epithelium.size:
            self.layers["epithelium"] = (position[epithelium], self._lowest_axis_node(mesh, epithelium))
            if stroma.size:
                self.layers["stroma"] = (position[np.concatenate([epithelium, stroma[:1]])],
                                         self._lowest_axis_node(mesh, epithelium))
        self.layers["cornea"] = (position[elements], self._lowest_axis_node(mesh, elements))
        self.steps = 0

    @staticmethod
    def _lowest_axis_node(mesh, elements) -> int:
        nodes = np.unique(mesh.cells[elements])
        nodes = nodes[mesh.points[nodes, 0] <= 1e-9]
        return int(nodes[np.argmin(mesh.points[nodes, 1])])

    def add_forces(self, model, state, time: float, time_step: float, f_ext: np.ndarray) -> None:
        """Check the events every ``CHECK_EVERY`` steps (the instrument's pose is this step's)."""
        self.steps += 1
        if self.steps % CHECK_EVERY:
            return
        tip = float(self.instrument.pose[POSE_Z])
        for name, (positions, node) in self.layers.items():
            index = EVENT_INDEX[name]
            if not math.isnan(state.event_time[index]):
                continue
            cracked = positions.size and np.all(positions >= 0) and np.all(state.crack[positions, OPENING_MAX] > 0.0)
            if cracked and tip < model.mesh.points[node, 1] + state.u[node, 1]:
                state.event_time[index] = time

    def outputs(self) -> dict[str, float]:
        return {}

    def events(self, setup, state) -> dict[str, float]:
        """Procedure times (s) of the events recorded so far."""
        return {name: setup.procedure_time(float(state.event_time[EVENT_INDEX[name]]))
                for name in self.layers if not math.isnan(state.event_time[EVENT_INDEX[name]])}
