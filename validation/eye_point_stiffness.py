"""Point stiffness of the model's eye: the needle scenario's eye pressed by a needle that does not cut.

Runs ``validation/needle_cut.toml`` without its ``[cut]`` (nothing separates, nothing is
deleted: ``solver.distortion_limit = 0``), with a rounded or conical tip, at 1 mm/s to
``--depth`` mm, and prints the force at 0.1, 0.2 and 0.35 mm of travel and the secant
stiffness over 0.1-0.25 and 0.1-0.35 mm against the experiment's (the 1 mm/s curve of
``needle-insertion-force``, before its first puncture). The force is then the eye's
structural response to a point load; docs/cutting.md, "The eye's point stiffness", compares
it with shallow-shell theory (validation/shell_point_stiffness.py).

Usage::

    python validation/eye_point_stiffness.py [--out results/eye-point-stiffness] [--tip rounded]
                                             [--preset needle-path-4x] [--depth 0.4] [--set KEY=VALUE ...]
"""

from __future__ import annotations

import argparse
import tomllib
from pathlib import Path

import numpy as np
import tomli_w

import corneasim
from corneasim.data import load_dataset

SCENARIO = Path(__file__).resolve().parent / "needle_cut.toml"
DEPTHS = (0.1, 0.2, 0.35)
"""Travel (mm) at which the force is read."""


def uncut_scenario(tip: str, depth: float) -> dict:
    """``needle_cut.toml`` without ``[cut]``, its material files by absolute path, ``depth`` mm of travel."""
    table = tomllib.loads(SCENARIO.read_text())
    table.pop("cut")
    for block in table["materials"].values():
        if block["material"].endswith(".toml"):
            block["material"] = str((SCENARIO.parent / block["material"]).resolve())
    table["name"] = "eye-point"
    table["description"] = "The needle scenario's eye pressed by a needle that does not cut"
    table["instrument"]["shape"]["tip"] = tip
    table["solver"]["end_time"] = depth / table["instrument"]["motion"]["insertion"]["rate"]
    table["solver"]["distortion_limit"] = 0.0
    return table


def secant(depth: np.ndarray, force: np.ndarray, lo: float = DEPTHS[0], hi: float = DEPTHS[-1]) -> float:
    """(F(hi) - F(lo)) / (hi - lo), N/mm."""
    return float((np.interp(hi, depth, force) - np.interp(lo, depth, force)) / (hi - lo))


def experiment() -> tuple[np.ndarray, np.ndarray]:
    """Depth (mm) and force (N) of the 1 mm/s experiment."""
    data = load_dataset("needle-insertion-force")
    return (np.asarray(data.columns["depth_mm"], dtype=float),
            np.asarray(data.columns["experiment_1mm_s_N"], dtype=float))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/eye-point-stiffness"))
    parser.add_argument("--tip", default="rounded", choices=("rounded", "conical", "flat"))
    parser.add_argument("--preset", default="needle-path-4x")
    parser.add_argument("--depth", type=float, default=0.4, help="travel, mm")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / f"eye-point-{args.tip}.toml"
    path.write_text(tomli_w.dumps(uncut_scenario(args.tip, args.depth)))
    result = corneasim.run_scenario(str(path), [f"mesh.preset={args.preset}", *args.overrides],
                                    out_dir=args.out / f"{args.preset}-{args.tip}", overwrite=True)
    depth, force = result.history["depth_mm"], result.history["force_N"]
    x, y = experiment()
    for d in DEPTHS:
        print(f"travel {d:g} mm: model {np.interp(d, depth, force):.4g} N, experiment {np.interp(d, x, y):.4g} N")
    for hi in (0.25, DEPTHS[-1]):
        print(f"secant stiffness {DEPTHS[0]:g}-{hi:g} mm: model {secant(depth, force, hi=hi):.4g} N/mm, "
              f"experiment {secant(x, y, hi=hi):.4g} N/mm")
    folded = result.history["min_corner_jacobian_ratio"] < 0.1
    print(f"largest KE/IE {result.summary['run']['max_kinetic_to_internal']:.2g}; first element below a corner "
          f"Jacobian ratio 0.1 at {depth[folded][0] if folded.any() else float('nan'):.3g} mm of travel")


if __name__ == "__main__":
    main()
