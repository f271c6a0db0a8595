"""The flat punch by the quasi-static recipe (examples/flat_punch/flat_punch_quasi_static.toml).

Truth: Sneddon's K = 2 a E / (1 - nu^2) for a rigid frictionless flat punch on a half-space.
At the test's tiny mesh (h = a / 6.5) nodal resolution of the edge singularity makes the disc
softer, by about 5% (as for the dynamic runs of ``test_example_flat_punch.py``, measured
-4.6% here); the band -9% .. +2% fails for a lost ring of punch nodes, a wrong ring weight or
a run that is not quasi-static (inertia or damping force left in the reaction).
"""

import sys
from pathlib import Path

import pytest

import corneasim
from corneasim.mesh import write_mesh

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "flat_punch"
sys.path.insert(0, str(EXAMPLE))
import flat_punch  # noqa: E402
from make_mesh import disc_mesh  # noqa: E402


def test_quasi_static_punch_matches_sneddon(tmp_path):
    mesh = write_mesh(disc_mesh(flat_punch.PUNCH_RADIUS, layer_thickness=flat_punch.LAYER_THICKNESS,
                                **flat_punch.SIZES["tiny"]), tmp_path / "disc.inp")
    result = corneasim.run_scenario(EXAMPLE / "flat_punch_quasi_static.toml", [
        f"mesh.file={mesh}", "materials.top_layer.material=materials/substrate.toml"])
    stiffness = -result.history["punch_force_N"][-1] / 0.005
    reference = flat_punch.sneddon_stiffness(flat_punch.PUNCH_RADIUS, *flat_punch.SUBSTRATE)
    assert -0.09 < stiffness / reference - 1.0 < 0.02
    report = result.summary["quasi_static"]
    assert report["met"] and report["ramp_periods"] == pytest.approx(20.0, rel=0.03)
    assert result.summary["run"]["steps"] < 20000
