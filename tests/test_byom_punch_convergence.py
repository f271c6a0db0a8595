"""The layered-disc punch force converges monotonically on three meshes, without folding elements.

Truth: the converged mesh sequence itself. The punch (a = 0.5 mm, the prescribed displacement
of its contact nodes, 50 um = a/10 deep, quasi-static recipe) on 2, 4, 8 elements under the
punch must give stiffnesses that rise monotonically with shrinking steps (first-order
convergence from the edge singularity: measured 1.332, 1.648, 1.739 N/mm, difference ratio
3.5), no element below the distortion check's threshold and an hourglass energy below 5% of
the internal energy (3.1%, 0.72%, 0.30%). A folding hourglass mode at the punch edge breaks
all three (the error of a folding sequence was -0.3%, -2.8%, -1.3%, not monotone).
"""

import sys
from pathlib import Path

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "flat_punch"
sys.path.insert(0, str(EXAMPLE))
import convergence  # noqa: E402


def test_punch_force_converges_monotonically(tmp_path):
    rows = convergence.run_sequence("small", tmp_path)
    k = [row["stiffness_N_per_mm"] for row in rows]
    assert k[0] < k[1] < k[2]
    assert (k[1] - k[0]) > 1.5 * (k[2] - k[1]) > 0
    for row in rows:
        assert row["distortion"]["first"] is None and row["min_corner_jacobian_ratio"] > 0.5
        assert row["hourglass_to_internal"] < 0.05
