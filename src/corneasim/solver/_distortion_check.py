"""Distortion check: the smallest corner Jacobian ratio of the live elements, watched at every history row.

The corner Jacobian ratio of element e is eta_e = min_a j_a(x) / j_a(X), j_a the cross
(quad) or triple (hexahedron) product of the edges leaving corner a in the current (x) and
reference (X) geometry (``_deletion``, which erodes elements below ``distortion_limit``).
It is 1 for a rigid motion, falls as a corner is crushed and is negative once the element
has folded: a one-point element whose hourglass mode runs away (a zig-zag pattern at a
punch edge) folds with a small hourglass energy, so the energies do not show it. The check
reports the first element to fall below the threshold (where and when) and the worst value
reached, and adds the column ``min_corner_jacobian_ratio`` to the history; the run goes on.
It is called like an external-force hook of the time loop and adds no force.
"""

from __future__ import annotations

import numpy as np

from corneasim.solver._deletion import corner_jacobian_ratios, reference_corner_inverse


class DistortionCheck:
    """Watch the corner Jacobian ratios of a mesh (module notes).

    Parameters
    ----------
    mesh : Mesh
    threshold : float
        Ratio below which an element is reported, dimensionless (0 < threshold < 1).
    """

    name = "distortion"

    def __init__(self, mesh, threshold: float):
        self.mesh, self.threshold = mesh, float(threshold)
        self.inverse = reference_corner_inverse(mesh.points, mesh.cells)
        self.state = None
        self.first = None  # (solver time s, element, ratio)
        self.worst = None  # (solver time s, element, ratio)
        self.below = 0  # elements below the threshold at the worst row

    def add_forces(self, model, state, time, time_step, f_ext) -> None:
        """No force: keep the state that :meth:`outputs` inspects."""
        self.state = state

    def ratios(self, u: np.ndarray, alive: np.ndarray) -> np.ndarray:
        """eta_e of every element at displacement ``u`` (mm); dead elements 1."""
        eta = np.empty(self.mesh.cells.shape[0])
        corner_jacobian_ratios(self.mesh.points, u, self.mesh.cells, self.inverse, alive, eta)
        return eta

    def outputs(self) -> dict[str, float]:
        """The history column; records the first and the worst element below the threshold."""
        if self.state is None:
            return {"min_corner_jacobian_ratio": 1.0}
        eta = self.ratios(self.state.u, self.state.alive)
        element = int(np.argmin(eta))
        smallest = float(eta[element])
        if smallest < self.threshold:
            time = float(self.state.time)
            if self.first is None:
                self.first = (time, element, smallest)
            if self.worst is None or smallest < self.worst[2]:
                self.worst = (time, element, smallest)
                self.below = int(np.count_nonzero(eta < self.threshold))
        return {"min_corner_jacobian_ratio": smallest}

    def checkpoint(self) -> dict:
        """The records so far (a resumed run keeps them): rows (time s, element, ratio), NaN when none."""
        rows = [record if record is not None else (np.nan, -1, np.nan) for record in (self.first, self.worst)]
        return {"records": np.array(rows, dtype=float), "below": np.array(self.below)}

    def restore(self, arrays: dict) -> None:
        """Take the records of :meth:`checkpoint` back."""
        if "records" not in arrays:
            return
        first, worst = ((float(t), int(e), float(r)) if e >= 0 else None for t, e, r in arrays["records"])
        self.first, self.worst, self.below = first, worst, int(arrays["below"])

    def report(self, procedure_time, warnings: list) -> dict:
        """The summary entry; one warning line when an element fell below the threshold.

        ``procedure_time`` maps a solver time to the procedure's (s).
        """
        entry = {"threshold": self.threshold, "first": None, "worst": None}
        if self.first is None:
            return entry
        for key, (time, element, ratio) in (("first", self.first), ("worst", self.worst)):
            entry[key] = {"element": element, "block": self.mesh.block_names[int(self.mesh.element_block[element])],
                          "time_s": procedure_time(time), "corner_jacobian_ratio": ratio}
        entry["worst"]["elements_below"] = self.below
        first, worst = entry["first"], entry["worst"]
        state = "folded" if worst["corner_jacobian_ratio"] < 0 else "distorted"
        warnings.append(
            f"elements {state}: element {first['element']} (block '{first['block']}') fell to a corner Jacobian "
            f"ratio {first['corner_jacobian_ratio']:.3g} (< {self.threshold:g}) at t = {first['time_s']:.6g} s; "
            f"worst {worst['corner_jacobian_ratio']:.3g} in element {worst['element']} at t = {worst['time_s']:.6g} s "
            f"({worst['elements_below']} elements below then)")
        return entry
