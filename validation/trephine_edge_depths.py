"""How deep the trephine's edge points sit under the faces that hold them, resumed from a checkpoint.

A diagnostic for the umbrella run's failure at 62 s (docs/trephination.md, "Known
limitations"). It resumes a trephine results folder from its ``checkpoint.npz`` up to
``--end`` (procedure time, s), and every ``--every`` steps recomputes, for every edge point,
the face that holds it (``EdgeContact.holding_faces``, the contact's own search) and
prints: the points held, the largest depth (mm), and for the points deeper than ``--deep``
(mm) the size and normal of their faces, the blocks of the faces' elements and the smallest
scaled corner Jacobian of those elements (negative: folded). Also prints, at the start, how
many live elements are folded. Nothing is written.

Usage::

    corneasim run trephine --set solver.end_time=60.5 --set solver.field_count=0 --out DIR
    python validation/trephine_edge_depths.py DIR --end 61.0 [--every 25] [--deep 0.02]
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from corneasim.mesh._quality import corner_jacobians
from corneasim.scenarios import build
from corneasim.scenarios import load_scenario
from corneasim.solver import load_checkpoint, run
from corneasim.contact._edge_law import HOLD_DEPTH, HOLD_NORMAL, HOLD_SIZE


def smallest_scaled_jacobian(mesh, x: np.ndarray) -> np.ndarray:
    """Smallest scaled corner Jacobian of each element of ``mesh`` at positions ``x`` (mm), (n,)."""
    return corner_jacobians(dataclasses.replace(mesh, points=x)).min(axis=1)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="trephine results folder with checkpoint.npz")
    parser.add_argument("--end", type=float, required=True, help="procedure time to run to, s")
    parser.add_argument("--every", type=int, default=25, help="steps between reports")
    parser.add_argument("--deep", type=float, default=0.02, help="depth reported in detail, mm")
    args = parser.parse_args(argv)
    scenario, _, base = load_scenario(str(args.folder / "scenario.toml"), [f"solver.end_time={args.end}"])
    setup = build(scenario, base)
    model = setup.model
    state = load_checkpoint(args.folder / "checkpoint.npz", model, setup.hooks)
    contact, points = setup.instrument, model.mesh.points
    edge = contact.edge
    folded = (state.alive != 0) & (smallest_scaled_jacobian(model.mesh, points + state.u) < 0.0)
    blocks = [model.block_of(int(e)) for e in np.flatnonzero(folded)]
    print(f"t = {setup.procedure_time(state.time):.4f} s: {folded.sum()} live elements folded "
          f"({', '.join(f'{b} {blocks.count(b)}' for b in sorted(set(blocks)))})")
    frames = run(model, state, setup.preload_duration + args.end, history_every=args.every,
                 damping=scenario.solver.damping, deletion_every=scenario.solver.deletion_every,
                 hooks=setup.hooks)
    for frame in frames:
        if frame.history is None:
            continue
        x = points + state.u
        held, hold = edge.holding_faces(x, contact.pose)
        depth = np.where(held >= 0, hold[:, HOLD_DEPTH], 0.0)
        deep = np.flatnonzero(depth > args.deep)
        line = (f"t = {setup.procedure_time(state.time):.4f} s: {np.count_nonzero(held >= 0)} points held, "
                f"largest depth {depth.max():.4f} mm, {deep.size} deeper than {args.deep} mm")
        if deep.size:
            owners = np.unique(edge.face_owner[held[deep]])
            line += (f"; their faces {hold[deep, HOLD_SIZE].min():.3f}-{hold[deep, HOLD_SIZE].max():.3f} mm, "
                     f"normal z {hold[deep, HOLD_NORMAL + 2].min():.2f}-{hold[deep, HOLD_NORMAL + 2].max():.2f}, "
                     f"blocks {sorted({model.block_of(int(e)) for e in owners})}, smallest scaled Jacobian "
                     f"{smallest_scaled_jacobian(model.mesh, x)[owners].min():.3f}")
        print(line, flush=True)


if __name__ == "__main__":
    main()
