"""Wall time of corneasim against CalculiX's explicit solver on the same hexahedral flat punch.

The model: a block of 20 x 17 x 14 = 4,760 C3D8R hexahedra of 0.1 mm (2.0 x 1.7 x 1.4 mm),
its base fixed, the top nodes within ``PUNCH_RADIUS`` of the top face's centre pushed down
``DEPTH`` in z (a bonded rigid punch as a prescribed displacement, free to slide sideways),
a compressible neo-Hooke solid (C10, D1: ``*HYPERELASTIC, NEO HOOKE`` in CalculiX, the
``neo-hooke`` law in corneasim, the same strain energy). The punch moves by a linear ramp over
the first ``RAMP_FRACTION`` of the run and then holds. Both codes take ``--increments``
central-difference steps of the same fixed size (``*DYNAMIC, DIRECT, EXPLICIT`` in CalculiX,
``solver.time_step`` in corneasim; CalculiX takes the smaller of its stable step and the
largest increment given, which is set to the step, and scales no mass as long as its stable
step stays above the smallest increment given, a thousandth of it) and report the punch's reaction at the end (CalculiX:
``*NODE PRINT, TOTALS=ONLY`` of RF in the ``.dat`` file; corneasim: the ``[[reactions]]``
history column).

Each code runs as a user runs it, in a fresh process (start-up included), alternating
CalculiX, corneasim, CalculiX, corneasim, ..., on 1 and on 2 threads each (``OMP_NUM_THREADS``
for ``ccx``, ``NUMBA_NUM_THREADS`` and ``solver.threads`` for corneasim), so that both see the
shared machine in the same state. Prints one table row per thread count: the best wall time of
each over ``--repeats`` pairs, their ratio, both punch forces and their relative difference,
and the load average; writes ``benchmarks/out/peer_calculix.json``. Without ``ccx`` on the
path it prints one line and exits (``apt-get install calculix-ccx``). Not part of the test
suite.

The two codes differ in what they add to the element forces: corneasim's hourglass stiffness
(``solver.hourglass_coefficient``) and bulk viscosity, CalculiX's own hourglass control of
C3D8R; the forces agree to a few percent, not to round-off.

Usage::

    python benchmarks/peer_calculix.py [--increments 10000] [--threads 1,2] [--repeats 2]
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
SHAPE = (20, 17, 14)
"""Elements along x, y, z."""
SIZE = 0.1
"""Element edge, mm."""
PUNCH_RADIUS = 0.4
"""Radius of the punched patch of top nodes, mm."""
DEPTH = 0.02
"""Final punch displacement, mm (downward)."""
RAMP_FRACTION = 0.8
"""Part of the run over which the punch moves; it holds for the rest."""
C10, D1 = 0.1724, 0.6
"""Neo-Hooke constants, MPa and 1/MPa (E = 1 MPa, nu = 0.45 at small strain)."""
DENSITY = 1.0e-9
"""tonne/mm^3."""
TIME_STEP = 5.0e-7
"""Fixed increment, s (about 0.3 of the stable step of the 0.1 mm elements in this solid)."""


def block_mesh():
    """The block's corneasim mesh: nodes, hexahedra, the ``bottom`` and ``punch`` node sets."""
    from corneasim.mesh import Mesh

    nx, ny, nz = SHAPE
    x, y, z = (SIZE * np.arange(n + 1) for n in SHAPE)
    grid = np.stack(np.meshgrid(x, y, z, indexing="ij"), axis=-1).reshape(-1, 3)
    node = np.arange(grid.shape[0]).reshape(nx + 1, ny + 1, nz + 1)
    i, j, k = (a.ravel() for a in np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij"))
    cells = np.stack([node[i, j, k], node[i + 1, j, k], node[i + 1, j + 1, k], node[i, j + 1, k],
                      node[i, j, k + 1], node[i + 1, j, k + 1], node[i + 1, j + 1, k + 1], node[i, j + 1, k + 1]],
                     axis=1)
    top = node[:, :, -1].ravel()
    centre = 0.5 * SIZE * np.array([nx, ny])
    punch = top[np.hypot(*(grid[top, :2] - centre).T) <= PUNCH_RADIUS]
    return Mesh(grid, cells.astype(np.int64), "hexahedron", np.zeros(len(cells), np.int64), ["solid"],
                node_sets={"bottom": node[:, :, 0].ravel(), "punch": punch})


def write_models(folder: Path, increments: int) -> tuple[Path, Path]:
    """The mesh file, corneasim's scenario and material, CalculiX's deck; returns (scenario, deck)."""
    from corneasim.mesh import write_mesh

    end_time = float(f"{increments * TIME_STEP:.6g}")
    mesh_path = write_mesh(block_mesh(), folder / "block.inp")
    (folder / "solid.toml").write_text(
        f'name = "peer-solid"\ndescription = "neo-Hooke, E = 1 MPa, nu = 0.45"\nsource = "benchmark value"\n'
        f'density = {DENSITY}\n\n[hyperelastic]\nmodel = "neo-hooke"\nc10 = {C10}\nd1 = {D1}\n')
    scenario = folder / "punch.toml"
    scenario.write_text(f"""name = "peer_punch"
[mesh]
file = "block.inp"
[materials]
solid = {{ material = "solid.toml" }}
[[constraints]]
node_set = "bottom"
fixed = "xyz"
[[constraints]]
node_set = "punch"
prescribed = "displacement"
component = "z"
value = {-DEPTH}
amplitude = {{ type = "tabular", times = [0.0, {RAMP_FRACTION * end_time}, {end_time}], values = [0.0, 1.0, 1.0] }}
[[reactions]]
name = "punch_force"
node_set = "punch"
component = "z"
[solver]
end_time = {end_time}
time_step = {TIME_STEP}
history_every = {increments}
field_count = 0
checkpoint_every = {10 * increments}
""")
    deck = folder / "punch_ccx.inp"
    deck.write_text(mesh_path.read_text() + f"""*MATERIAL, NAME=SOLID
*HYPERELASTIC, NEO HOOKE
{C10}, {D1}
*DENSITY
{DENSITY}
*SOLID SECTION, ELSET=solid, MATERIAL=SOLID
*AMPLITUDE, NAME=RAMP
0.0, 0.0, {RAMP_FRACTION * end_time}, 1.0, {end_time}, 1.0
*BOUNDARY
bottom, 1, 3
*STEP, NLGEOM, INC={10 * increments}
*DYNAMIC, DIRECT, EXPLICIT
{TIME_STEP:.6g}, {end_time:.6g}, {1e-3 * TIME_STEP:.6g}, {TIME_STEP:.6g}
*BOUNDARY, AMPLITUDE=RAMP
punch, 3, 3, {-DEPTH}
*NODE PRINT, NSET=punch, TOTALS=ONLY, FREQUENCY={increments}
RF
*END STEP
""")
    return scenario, deck


def run_ccx(deck: Path, threads: int) -> tuple[float, float]:
    """Run CalculiX on ``deck``; its wall time (s) and the punch's z reaction at the end (N)."""
    environment = dict(os.environ, OMP_NUM_THREADS=str(threads))
    started = time.perf_counter()
    done = subprocess.run(["ccx", "-i", deck.stem], cwd=deck.parent, env=environment, capture_output=True,
                          text=True)
    wall = time.perf_counter() - started
    if done.returncode != 0 or "ERROR" in done.stdout:
        raise SystemExit(f"ccx failed: {done.stdout[-2000:]}{done.stderr[-2000:]}")
    return wall, ccx_force(deck.with_suffix(".dat"))


def ccx_force(dat: Path) -> float:
    """The z component of the last ``total force`` block of a CalculiX ``.dat`` file, N."""
    blocks = re.findall(r"total force \(fx,fy,fz\)[^\n]*\n\s*\n?\s*(\S+)\s+(\S+)\s+(\S+)", dat.read_text())
    if not blocks:
        raise SystemExit(f"{dat}: no total force of the punch")
    return float(blocks[-1][2])


def run_corneasim(scenario: Path, out: Path, threads: int) -> tuple[float, float, float | None]:
    """Run ``corneasim run`` on ``scenario``; its wall time (s), the punch's z reaction at the end
    (N) and the run's ``startup_s``."""
    environment = dict(os.environ, NUMBA_NUM_THREADS=str(threads))
    command = [sys.executable, "-m", "corneasim.cli.main", "run", str(scenario), "--out", str(out), "--overwrite",
               "--no-progress", "--set", f"solver.threads={threads}"]
    started = time.perf_counter()
    done = subprocess.run(command, env=environment, capture_output=True, text=True)
    wall = time.perf_counter() - started
    if done.returncode != 0:
        raise SystemExit(f"corneasim failed: {done.stderr.strip()}")
    from corneasim.data import read_table

    history = read_table(out / "history.csv")
    startup = json.loads((out / "summary.json").read_text())["run"].get("startup_s")
    return wall, float(history["punch_force_N"][-1]), startup


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--increments", type=int, default=10000)
    parser.add_argument("--threads", default="1,2")
    parser.add_argument("--repeats", type=int, default=2, help="CalculiX-corneasim pairs per thread count")
    parser.add_argument("--out", type=Path, default=HERE / "out" / "peer_calculix.json")
    arguments = parser.parse_args()
    if shutil.which("ccx") is None:
        print("peer_calculix: ccx (CalculiX) is not installed (apt-get install calculix-ccx); skipped")
        return
    rows = []
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        scenario, deck = write_models(folder, arguments.increments)
        run_corneasim(scenario, folder / "warm", 1)  # the Numba cache warm, as a user's second run
        for threads in (int(t) for t in arguments.threads.split(",")):
            ccx_walls, own_walls, startups = [], [], []
            for _ in range(arguments.repeats):
                load = os.getloadavg()[0]
                wall, ccx_fz = run_ccx(deck, threads)
                ccx_walls.append(wall)
                wall, own_fz, startup = run_corneasim(scenario, folder / "run", threads)
                own_walls.append(wall)
                startups.append(startup)
            rows.append({"threads": threads, "increments": arguments.increments, "elements": int(np.prod(SHAPE)),
                         "ccx_wall_s": min(ccx_walls), "corneasim_wall_s": min(own_walls),
                         "ccx_walls_s": ccx_walls, "corneasim_walls_s": own_walls,
                         "corneasim_startup_s": startups, "ratio": min(ccx_walls) / min(own_walls),
                         "ccx_force_N": ccx_fz, "corneasim_force_N": own_fz,
                         "force_difference": (own_fz - ccx_fz) / abs(ccx_fz), "load_average": load})
    arguments.out.parent.mkdir(parents=True, exist_ok=True)
    arguments.out.write_text(json.dumps(rows, indent=2) + "\n")
    print("| threads | elements | increments | CalculiX s | corneasim s (start-up s) | ratio | F CalculiX N "
          "| F corneasim N | difference | load |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for row in rows:
        startup = min(s for s in row["corneasim_startup_s"] if s is not None) if any(row["corneasim_startup_s"]) \
            else float("nan")
        print(f"| {row['threads']} | {row['elements']} | {row['increments']} | {row['ccx_wall_s']:.2f} "
              f"| {row['corneasim_wall_s']:.2f} ({startup:.2f}) | {row['ratio']:.1f} | {row['ccx_force_N']:.5g} "
              f"| {row['corneasim_force_N']:.5g} | {100 * row['force_difference']:+.1f}% "
              f"| {row['load_average']:.1f} |")


if __name__ == "__main__":
    main()
