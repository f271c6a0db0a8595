"""A coarse trephination with the cohesive cut, end to end: the cut on the blade's cylinder only,
F_c with the rotation, every tie through the thickness cut and the disc free.

Slow (about a minute on two cores): the cut has to go through the whole cornea, which takes
some 10^4 steps of the coarse eye even with a low toughness and a short preload.
"""

import math

import numpy as np
import pytest

from corneasim.scenarios import run_scenario
from corneasim.scenarios._build import build
from corneasim.scenarios._registry import load_scenario

pytestmark = pytest.mark.slow

AMPLITUDE, OMEGA = 1.25, 3.5081117965086  # rad, rad/s: the scenario's rotation theta = A sin(omega t)
CUT = ["mesh.preset=coarse", "cohesive_cut.strength=4.0", "cohesive_cut.fracture_energy=0.02",
       "supports=[]", "constraints.lower_hemisphere.fixed=xyz", "instrument.start_gap=0.01",
       "solver.target_time_step=1e-3", "preload.duration=2.0", "solver.end_time=10.0", "solver.field_count=0"]


@pytest.fixture(scope="module")
def cut_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("trephine-cut")
    return run_scenario("trephine", CUT, out_dir=out, progress=False), out


def test_the_run_writes_its_contract_files(cut_run):
    result, out = cut_run
    for name in ("scenario.toml", "history.csv", "summary.json"):
        assert (out / name).is_file()
    assert result.summary["status"] == "completed"


def test_only_the_ties_on_the_cylinder_separate_and_all_of_them_do(cut_run):
    result, _ = cut_run
    history = result.history
    assert np.all(history["deleted_elements"] == 0) and not result.deletions
    scenario, _, base_dir = load_scenario("trephine", CUT)
    setup = build(scenario, base_dir)
    pairs, points = setup.cohesive.pairs, setup.mesh.points
    np.testing.assert_allclose(np.hypot(points[pairs, 0], points[pairs, 1]), 3.75, atol=1e-9)
    assert history["cohesive_broken_ties"][-1] == len(pairs)
    # the disc is free: no element inside the cylinder shares a node with one outside
    mesh = setup.mesh
    radius = np.hypot(mesh.points[:, 0], mesh.points[:, 1])[mesh.cells].mean(axis=1)
    cornea = np.isin(mesh.element_block, [mesh.block_names.index(b) for b in ("epithelium", "stroma")])
    inside = set(mesh.cells[cornea & (radius < 3.75)].ravel())
    outside = set(mesh.cells[~(cornea & (radius < 3.75))].ravel())
    assert not inside & outside
    events = {p["event"]: p["time_s"] for p in result.summary["punctures"]}
    assert events["epithelium"] <= events["stroma"] <= events["cornea"] < 10.0


def test_fc_opposes_the_rotation(cut_run):
    """Friction and the cut's resistance oppose the edge's sliding: F_c (torque / R, the tissue on
    the trephine) has the sign of -theta' of the imposed rotation, period 2 pi / omega."""
    result, _ = cut_run
    history = result.history
    time, fc = history["time_s"], history["fc_N"]
    angular_velocity = AMPLITUDE * OMEGA * np.cos(OMEGA * time)
    touching = ((history["instrument_edge_contact_points"] + history["instrument_contact_nodes"] > 0)
                & (np.abs(angular_velocity) > 0.5 * AMPLITUDE * OMEGA))  # edge (on the fronts) or walls
    assert touching.sum() > 20 and np.ptp(time[touching]) > 2 * math.pi / OMEGA
    assert np.corrcoef(fc[touching], angular_velocity[touching])[0, 1] < -0.5
