"""Can a resolved cohesive zone make a trephine cut? An axisymmetric plate study.

A flat stroma plate (``cornea`` preset, 0.55 mm thick, clamped at r = 5 mm) is split along
the cylinder r = 3.75 mm and tied by the cohesive law of ``corneasim.fracture._ties``; a
trephine (7.5 mm, 0.1 mm wall, 30 degree bevel; no rotation) descends on it at 20 um/s. The
mesh is ``--size`` mm (default 0.01) within 0.1 mm of the cut and through the whole
thickness, so the cohesive zone (E G_c / sigma_c^2) is resolved by several elements: this
isolates the question the 3D screening could not answer (docs/trephination.md,
"Alternatives considered"). Prints the trephine's force F_z and the ties' state every tenth of the run.

Usage::

    python validation/trephine_cut_plate.py --strength 0.2 --toughness 0.004 --end 16
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from corneasim.materials import load_material
from corneasim.mesh import Mesh
from corneasim.fracture import split_nodes
from corneasim.solver import Fixed, build_model, new_state, run
from corneasim.solver import Linear
from corneasim.fracture import CohesiveTies, tie_areas
from corneasim.contact import ContactSettings
from corneasim.contact import Friction
from corneasim.instruments import Trephine
from corneasim.contact import InstrumentContact
from corneasim.instruments import Motion

CUT_RADIUS, THICKNESS, OUTER_RADIUS = 3.75, 0.55, 5.0  # mm
SPEED = 0.02  # mm/s, the trephination paper's
START_GAP = 0.005  # mm between the edge and the plate at t = 0


def plate(size: float) -> tuple[Mesh, np.ndarray]:
    """The split plate (r, z), top at z = 0, and its tie pairs."""
    band = np.arange(CUT_RADIUS - 0.1, CUT_RADIUS + 0.1 + 1e-9, size)
    r = np.unique(np.round(np.concatenate([np.linspace(0.0, CUT_RADIUS - 0.1, 25), band,
                                           np.linspace(CUT_RADIUS + 0.1, OUTER_RADIUS, 14)]), 9))
    z = np.linspace(-THICKNESS, 0.0, int(round(THICKNESS / size)) + 1)
    R, Z = np.meshgrid(r, z, indexing="ij")
    index = np.arange(R.size).reshape(R.shape)
    i, k = (a.ravel() for a in np.meshgrid(np.arange(len(r) - 1), np.arange(len(z) - 1), indexing="ij"))
    cells = np.column_stack([index[i, k], index[i + 1, k], index[i + 1, k + 1], index[i, k + 1]])
    points = np.column_stack([R.ravel(), Z.ravel()])
    mesh = Mesh(points, cells.astype(np.int64), "quad", np.zeros(len(cells), np.int64), ["stroma"],
                axisymmetric=True, node_sets={"outer": index[-1], "top": index[:, -1]})
    on_cut = np.flatnonzero(np.isclose(points[:, 0], CUT_RADIUS, rtol=0.0, atol=1e-9))
    return split_nodes(mesh, on_cut, points[cells][:, :, 0].mean(axis=1) > CUT_RADIUS)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--strength", type=float, default=0.2, help="cohesive strength, MPa")
    parser.add_argument("--toughness", type=float, default=0.004, help="fracture energy, N/mm")
    parser.add_argument("--end", type=float, default=16.0, help="procedure time, s")
    parser.add_argument("--size", type=float, default=0.01, help="element size at the cut, mm")
    parser.add_argument("--target-time-step", type=float, default=3e-5, help="mass-scaling target, s")
    args = parser.parse_args()
    mesh, pairs = plate(args.size)
    material = load_material("cornea").kernel_form()
    model = build_model(mesh, {"stroma": material}, [Fixed("outer", "rz")], target_time_step=args.target_time_step)
    ties = CohesiveTies(model, pairs, tie_areas(mesh, pairs), args.strength, args.toughness)
    trephine = InstrumentContact(Trephine(diameter=2 * CUT_RADIUS, wall_thickness=0.1, bevel_angle=30.0),
                                 Motion(insertion=Linear(rate=SPEED), tip_position=(0.0, START_GAP)), model,
                                 ContactSettings(friction=Friction(coefficient=0.1), node_set="top"),
                                 name="trephine")
    print(f"{mesh.n_elements} elements, {len(pairs)} ties; cohesive length E G_c / sigma_c^2 = "
          f"{1.8 * args.toughness / args.strength ** 2:.3g} mm (E = 1.8 MPa)")
    started = time.perf_counter()
    rows = []
    for frame in run(model, new_state(model), args.end, history_every=200, hooks=[trephine, ties]):
        if frame.history:
            row = frame.history
            rows.append((frame.time, row["trephine_force_z_N"], row["cut_softening_ties"],
                         row["cut_broken_ties"], row["cut_dissipated_energy_mJ"]))
    rows = np.array(rows)
    print(f"{time.perf_counter() - started:.1f} s wall")
    print("| t (s) | descent (mm) | F_z (N) | ties softening | broken | dissipated (mJ) |")
    print("|---|---|---|---|---|---|")
    for t in np.linspace(0.0, args.end, 11):
        near = np.abs(rows[:, 0] - t) <= 0.25
        j = int(np.argmin(np.abs(rows[:, 0] - t)))
        print(f"| {t:.1f} | {max(SPEED * t - START_GAP, 0.0):.3f} | {rows[near, 1].mean():.4f} | "
              f"{rows[j, 2]:.0f} | {rows[j, 3]:.0f} | {rows[j, 4]:.5f} |")
    broken = ties.opening_max >= ties.separation
    depth = -mesh.points[pairs[broken, 0], 1].min() if broken.any() else 0.0
    print(f"cut from the top: {depth:.3f} of {THICKNESS} mm")


if __name__ == "__main__":
    main()
