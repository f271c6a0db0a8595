"""A needle cut through a tissue disc by radial cracks (``[cut]``), end to end through a scenario file.

Truths: the needle cannot pass a node (contact), so a tip below the disc's lowest axis node
means the axis nodes left the axis (cut faces); the cracks' dissipation is at most n G_c per
unit area of the band's (r, z) section and at least n G_c per unit area of the part of it
inside the shaft (which every fully opened crack has paid); the shaft's friction is the only
axial force on the needle once its tip is out of the disc, and it resists the insertion.
"""

import math

import numpy as np
import pytest

import corneasim
from corneasim.errors import InputError
from corneasim.mesh import QUAD_FACES, Mesh, write_mesh
from test_solver_meshes import _surface

EPITHELIUM, THICKNESS, RADIUS = 0.03, 0.12, 0.5  # mm
NEEDLE_RADIUS = 0.05  # mm
STRENGTH = {"epithelium": 0.5, "stroma": 1.0}  # MPa
TOUGHNESS = {"epithelium": 0.01, "stroma": 0.02}  # N/mm
BAND = 0.16  # mm


def disc(fine=0.01):
    """A tissue disc r <= RADIUS, -THICKNESS <= z <= 0: epithelium over stroma, elements of ``fine``
    (mm) within BAND of the axis, 0.05 mm beyond; sets rim (r = RADIUS), top (z = 0)."""
    outer = int(round((RADIUS - BAND) / 0.05))
    r = np.concatenate([np.linspace(0.0, BAND, int(round(BAND / fine)) + 1), np.linspace(BAND, RADIUS, outer + 1)[1:]])
    z = np.linspace(-THICKNESS, 0.0, int(round(THICKNESS / fine)) + 1)
    R, Z = np.meshgrid(r, z, indexing="ij")
    points = np.column_stack([R.ravel(), Z.ravel()])
    index = np.arange(points.shape[0]).reshape(r.size, z.size)
    i, k = np.meshgrid(np.arange(r.size - 1), np.arange(z.size - 1), indexing="ij")
    i, k = i.ravel(), k.ravel()
    cells = np.column_stack([index[i, k], index[i + 1, k], index[i + 1, k + 1], index[i, k + 1]]).astype(np.int64)
    centre_z = points[cells, 1].mean(axis=1)
    block = (centre_z < -EPITHELIUM).astype(np.int64)
    order = np.argsort(block, kind="stable")
    cells, block = cells[order], block[order]
    rim = np.isclose(points[:, 0], RADIUS)
    top = np.isclose(points[:, 1], 0.0)
    assert rim.any()
    node_sets = {"rim": np.flatnonzero(rim).astype(np.int64), "anterior_surface": np.flatnonzero(top).astype(np.int64)}
    return Mesh(points, cells, "quad", block, ["epithelium", "stroma"], True, node_sets, {},
                {"top": _surface(cells, QUAD_FACES, top)})


def scenario_text(mesh_file, end_time, extra=""):
    blocks = "\n".join(f"[cut.blocks.{name}]\nstrength = {STRENGTH[name]}\nfracture_energy = {TOUGHNESS[name]}\n"
                       for name in STRENGTH)
    return f"""
kind = "needle"
name = "cut-disc"
[mesh]
file = "{mesh_file}"
[materials]
epithelium = {{ material = "epithelium" }}
stroma = {{ material = "cornea" }}
[[constraints]]
node_set = "rim"
fixed = "rz"
[instrument]
start_gap = 0.002
[instrument.shape]
kind = "needle"
diameter = {2 * NEEDLE_RADIUS}
tip = "conical"
tip_angle = 30.0
[instrument.motion]
insertion = {{ type = "linear", rate = 20.0 }}
[instrument.contact]
friction = {{ law = "coulomb", coefficient = 0.2 }}
[solver]
end_time = {end_time}
target_time_step = 4.0e-6
history_every = 20
mass_scaling = "variable"
threads = 1
field_count = 0
{extra}
[cut]
kind = "radial-cracks"
cracks = 2
band_radius = {BAND}
{blocks}
"""


def run_disc(tmp_path, end_time=0.022, extra=""):
    mesh_file = write_mesh(disc(), tmp_path / "disc.inp")
    path = tmp_path / "cut.toml"
    path.write_text(scenario_text(mesh_file, end_time, extra))
    return corneasim.run_scenario(str(path))


def test_a_needle_cuts_through_the_disc_without_deleting_elements(tmp_path):
    result = run_disc(tmp_path)
    history, summary = result.history, result.summary
    assert summary["status"] == "completed"
    assert not result.deletions and history["deleted_elements"][-1] == 0
    depth, force = history["depth_mm"], history["force_N"]
    touching = force > 0.0
    assert np.all(force[touching.argmax():] > 0.0)  # force positive from the first touch on
    events = {p["event"]: p["depth_mm"] for p in summary["punctures"]}
    assert list(events) == ["epithelium", "stroma", "cornea"]
    assert events["epithelium"] <= events["stroma"] <= events["cornea"] < depth[-1]
    # through the disc: the shaft's friction alone holds the needle, resisting its insertion
    after = depth > events["cornea"] + 0.05
    assert after.any() and np.all(force[after] > 0.0)
    # the cracks' energy: bounded by n G_c over the band's section, at least the shaft's part of it
    dissipated = history["cut_dissipated_energy_mJ"][-1]
    n = 2
    upper = n * (TOUGHNESS["epithelium"] * BAND * EPITHELIUM + TOUGHNESS["stroma"] * BAND * (THICKNESS - EPITHELIUM))
    lower = n * (TOUGHNESS["epithelium"] * NEEDLE_RADIUS * EPITHELIUM * 0.5
                 + TOUGHNESS["stroma"] * NEEDLE_RADIUS * (THICKNESS - EPITHELIUM) * 0.5)
    assert lower < dissipated < upper


@pytest.mark.parametrize("table, message", [
    ("[cut]\nband_radius = 0.2\n[cut.blocks.stroma]\nstrength = 1.0\nfracture_energy = -0.1\n",
     "cut.blocks.stroma.fracture_energy"),
    ("[cut]\ncracks = 0\nband_radius = 0.2\n[cut.blocks.stroma]\nstrength = 1.0\nfracture_energy = 0.1\n",
     "cut.cracks"),
    ("[cut]\nband_radius = 0.001\n[cut.blocks.stroma]\nstrength = 1.0\nfracture_energy = 0.1\n",
     "cut.band_radius"),
    ("[cut]\nband_radius = 0.2\n[cut.blocks.lens]\nstrength = 1.0\nfracture_energy = 0.1\n",
     "cut.blocks.lens"),
])
def test_bad_cut_tables_name_their_key(tmp_path, table, message):
    mesh_file = write_mesh(disc(), tmp_path / "disc.inp")
    text = scenario_text(mesh_file, 0.001).split("[cut]")[0] + table
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(InputError, match=message.replace(".", r"\.")):
        corneasim.run_scenario(str(path))
