"""Where the kinetic energy is and which nodes carry F_z around a cohesive cut-through, resumed from a checkpoint.

A diagnostic for the cohesive trephine run (docs/trephination.md, "After the cut-through").
It resumes a results folder of ``corneasim run trephine --preset cohesive`` from its
``checkpoint.npz`` up to ``--end`` (procedure time, s) and every ``--every`` steps prints:

* the kinetic energy ½ Σ m |v|² (mJ, lumped scaled masses, v at the half step) of the whole
  half model, the part of it in the model's rigid translation along the axis, ½ M v̄_z² with
  v̄_z = Σ m v_z / M, and the kinetic energy of the disc (the cornea's elements inside the
  cut cylinder, by the mean radius of their nodes in the reference mesh), of the rim (the
  cornea's others) and of the sclera;
* the instrument's F_z (whole eye: times ``instrument.symmetry_factor``, N) on the disc's
  nodes and on the rest: the change of the nodes' external force over the instrument's hook;
* the edge height and v̄_z (mm, mm/s), the ties cut.

Nothing is written; the folder's own files are not touched.

Usage::

    corneasim run trephine --preset coarse --preset cohesive --set solver.end_time=73.3 --out DIR
    python validation/trephine_after_cut.py DIR --end 80 [--every 100]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from corneasim.fracture._cohesive_cut import cut_radius
from corneasim.instruments import POSE_Z
from corneasim.scenarios import build, load_scenario
from corneasim.solver import load_checkpoint, run


def parts(mesh, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """(disc, cornea) node masks (n_nodes,): the nodes of the cornea's elements inside the
    cylinder r = ``radius`` (mm, the mean radius of an element's reference nodes), and of all
    the cornea's elements (blocks epithelium and stroma)."""
    in_cornea = np.isin(mesh.element_block, [mesh.block_names.index(b) for b in ("epithelium", "stroma")])
    node_radius = np.hypot(mesh.points[:, 0], mesh.points[:, 1])
    inside = in_cornea & (node_radius[mesh.cells].mean(axis=1) < radius)
    disc = np.zeros(mesh.n_nodes, dtype=bool)
    disc[np.unique(mesh.cells[inside])] = True
    cornea = np.zeros(mesh.n_nodes, dtype=bool)
    cornea[np.unique(mesh.cells[in_cornea])] = True
    return disc, cornea


class InstrumentShare:
    """Two hooks around the instrument's: ``before`` keeps f_ext_z, ``after`` the change it made."""

    def __init__(self, n_nodes: int):
        self.z_before = np.zeros(n_nodes)
        self.change = np.zeros(n_nodes)
        self.before, self.after = _Side(self, True), _Side(self, False)


class _Side:
    """One of the hooks of :class:`InstrumentShare` (adds no force)."""

    def __init__(self, share: InstrumentShare, first: bool):
        self.name = f"instrument_share_{'before' if first else 'after'}"
        self.share, self.first = share, first

    def add_forces(self, model, state, time: float, time_step: float, f_ext: np.ndarray) -> None:
        """Record f_ext_z (N) before the instrument, or its change after it."""
        if self.first:
            self.share.z_before[:] = f_ext[:, 2]
        else:
            np.subtract(f_ext[:, 2], self.share.z_before, out=self.share.change)

    def outputs(self) -> dict[str, float]:
        """None."""
        return {}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="cohesive trephine results folder with checkpoint.npz")
    parser.add_argument("--end", type=float, required=True, help="procedure time to run to, s")
    parser.add_argument("--every", type=int, default=100, help="steps between reports")
    args = parser.parse_args(argv)
    scenario, _, base = load_scenario(str(args.folder / "scenario.toml"), [f"solver.end_time={args.end}"],
                                      resolved=True)
    setup = build(scenario, base)
    model = setup.model
    state = load_checkpoint(args.folder / "checkpoint.npz", model, setup.hooks)
    disc, cornea = parts(model.mesh, cut_radius(scenario))
    sclera, rim = ~cornea, cornea & ~disc
    share = InstrumentShare(model.mesh.n_nodes)
    hooks = []
    for hook in setup.hooks:
        hooks += [share.before, hook, share.after] if hook is setup.instrument else [hook]
    factor = setup.instrument.symmetry_factor
    print("t_s KE_mJ translation_mJ disc_mJ rim_mJ sclera_mJ fz_disc_N fz_rest_N edge_z_mm vz_mm_per_s ties_cut")
    frames = run(model, state, setup.solver_time(args.end), history_every=args.every,
                 damping=setup.scenario.solver.damping, hooks=tuple(hooks), events=setup.events)
    for frame in frames:
        if frame.history is None:
            continue
        m, v = state.mass, state.v
        ke = 0.5 * m * np.einsum("ij,ij->i", v, v)
        vz = float(m @ v[:, 2] / m.sum())
        fz = -factor * share.change
        print(f"{setup.procedure_time(state.time):.3f} {ke.sum():.4g} {0.5 * m.sum() * vz * vz:.4g} "
              f"{ke[disc].sum():.4g} {ke[rim].sum():.4g} {ke[sclera].sum():.4g} {fz[disc].sum():.4f} "
              f"{fz[~disc].sum():.4f} {setup.instrument.pose[POSE_Z]:.4f} {vz:.4f} "
              f"{int(setup.cohesive.cut.sum())}", flush=True)


if __name__ == "__main__":
    main()
