"""Mesh convergence of the flat-punch force: the layered disc pressed 50 um (a/10) on three meshes.

The punch is the prescribed displacement of its contact nodes (``flat_punch_quasi_static.toml``,
run by the quasi-static recipe), on meshes with ``n`` = 4, 8, 16 elements under the punch
(the fine zone's size h = a / (n + 1/2); a 15 mm disc graded by 1.3), or 2, 4, 8 on a 10 mm
disc graded by 1.4 (``small``, the size the test suite runs). For each mesh it prints the
punch force, the stiffness F / delta, the smallest corner Jacobian ratio the distortion check
saw and the hourglass share of the internal energy, then the differences between successive
meshes, whose ratio (about 2 for first-order convergence, the edge singularity's) and sign
show a monotone convergence, and the Richardson extrapolation K_inf = K_3 + (K_3 - K_2) / (r - 1).

Run: ``python examples/flat_punch/convergence.py [default|small] [KEY=VALUE ...]`` (overrides as
``--set``, e.g. ``solver.hourglass_control=physical``).
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import corneasim

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import flat_punch  # noqa: E402  (the sibling script)
from make_mesh import disc_mesh  # noqa: E402

SCENARIO = HERE / "flat_punch_quasi_static.toml"
DEPTH = 0.05
"""delta, mm (a / 10)."""
SEQUENCES = {
    "default": dict(counts=(4, 8, 16), radius=15.0, thickness=15.0, growth=1.3),
    "small": dict(counts=(2, 4, 8), radius=10.0, thickness=10.0, growth=1.4),
}


def run_sequence(size: str = "default", work_dir: str | Path | None = None, overrides=()) -> list[dict]:
    """Run the three meshes; one dict per mesh (elements, force_N, stiffness_N_per_mm, min ratio, hourglass)."""
    spec = SEQUENCES[size]
    work = Path(work_dir) if work_dir is not None else Path(tempfile.mkdtemp(prefix="punch-convergence-"))
    rows = []
    for count in spec["counts"]:
        mesh = disc_mesh(flat_punch.PUNCH_RADIUS, layer_thickness=flat_punch.LAYER_THICKNESS,
                         elements_under_punch=count, radius=spec["radius"], thickness=spec["thickness"],
                         growth=spec["growth"])
        path = corneasim.mesh.write_mesh(mesh, work / f"disc-{size}-{count}.inp")
        result = corneasim.run_scenario(SCENARIO, [f"mesh.file={path.resolve()}", f"constraints.punch.value={-DEPTH}",
                                                   *overrides])
        force = -float(result.history["punch_force_N"][-1])
        rows.append({"under_punch": count, "elements": mesh.n_elements, "force_N": force,
                     "stiffness_N_per_mm": force / DEPTH,
                     "min_corner_jacobian_ratio": float(result.history["min_corner_jacobian_ratio"].min()),
                     "hourglass_to_internal": result.summary["run"]["hourglass_to_internal"],
                     "distortion": result.summary["distortion"], "steps": result.summary["run"]["steps"]})
    return rows


def main(size: str = "default", *overrides: str) -> list[dict]:
    """Print the convergence table (``overrides``: --set KEY=VALUE, e.g. solver.hourglass_control=physical)."""
    rows = run_sequence(size, overrides=overrides)
    print("| elements under the punch | elements | F (N) | K (N/mm) | min corner ratio | hourglass / internal | steps |")
    print("|---|---|---|---|---|---|---|")
    for row in rows:
        print(f"| {row['under_punch']} | {row['elements']} | {row['force_N']:.5f} | {row['stiffness_N_per_mm']:.4f} | "
              f"{row['min_corner_jacobian_ratio']:.3f} | {row['hourglass_to_internal']:.2g} | {row['steps']} |")
    k = [row["stiffness_N_per_mm"] for row in rows]
    ratio = (k[1] - k[0]) / (k[2] - k[1])
    print(f"differences {k[1] - k[0]:+.4f}, {k[2] - k[1]:+.4f} N/mm (ratio {ratio:.2f}); "
          f"Richardson K_inf = {k[2] + (k[2] - k[1]) / (ratio - 1):.4f} N/mm")
    return rows


if __name__ == "__main__":
    main(*sys.argv[1:])
