"""The cap inflation example (examples/cap_inflation/) against Lame's thick-sphere solution.

At the tiny mesh (2 x 12 quads) the equator's radial displacement is within 0.5% of Lame's
(measured -0.31%) and the poles' within 5% (measured +4.0%, +3.7%; second order in the
angular element size, +0.28% at the default 4 x 48).
"""

import sys
from pathlib import Path

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "cap_inflation"
sys.path.insert(0, str(EXAMPLE))
import cap_inflation  # noqa: E402


def test_cap_inflation_matches_lame(tmp_path):
    outcome = cap_inflation.main("tiny", tmp_path)
    errors = outcome["errors"]
    assert abs(errors["outer_equator_r_mm"]) < 0.005
    assert abs(errors["outer_pole_z_mm"]) < 0.05 and abs(errors["inner_pole_z_mm"]) < 0.05
    summary = outcome["result"].summary
    assert summary["quasi_static"]["met"] and summary["status"] == "completed"


def test_lame_solution_meets_its_boundary_conditions():
    a, b, p, E, nu = 5.0, 6.0, 1e-4, 1.0, 0.3
    u = cap_inflation.lame_displacement

    def radial_stress(rho, h=1e-5):
        du = (u(rho + h) - u(rho - h)) / (2 * h)
        return E / ((1 + nu) * (1 - 2 * nu)) * ((1 - nu) * du + 2 * nu * u(rho) / rho)

    assert abs(radial_stress(a) + p) < 1e-6 * p and abs(radial_stress(b)) < 1e-6 * p
