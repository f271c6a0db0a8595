"""Steady penetration of a sharp needle into a flat block cut by radial cracks: the force plateau
against its closed form (docs/cutting.md, "The tip's split").

Truth: once the cone is in, each advance dz of the point cuts the footprint (the shaft's
radius a) of n radial cracks, n a dz of crack area at G_c each, and wedges the uncut solid
beyond r = a open by a, a plane-strain cavity expansion from a to 2a of the incompressible
neo-Hooke solid, (3/2) pi ln(4) mu a^2 per unit depth. Without friction the work per unit
depth is the force,

    F = n G_c a + (3/2) pi ln(4) mu a^2,

and the cut's dissipation grows by n G_c a per unit depth.
"""

import math

import numpy as np
import pytest

import corneasim
from corneasim.mesh import QUAD_FACES, Mesh, write_mesh
from test_solver_meshes import _surface

RADIUS, THICKNESS, FINE, BAND = 0.8, 1.0, 0.0125, 0.1  # mm: block, its elements along the path, cut band
NEEDLE_RADIUS, TIP_ANGLE = 0.05, 15.0  # mm, degrees (a cone 0.38 mm long)
C10, BULK = 0.25, 50.0  # MPa: neo-Hooke, mu = 0.5 MPa, nu = 0.495
CRACKS, STRENGTH = 2, 2.0  # a slit; MPa (the band beyond the footprint stays below it)
RATE, DEPTH, PLATEAU = 40.0, 0.75, (0.5, 0.75)  # mm/s, mm, mm: the steady part, past the cone


def block():
    """An axisymmetric block r <= RADIUS, -THICKNESS <= z <= 0 fixed on its rim and base: FINE
    elements within BAND of the axis, graded outwards."""
    r = np.concatenate([np.linspace(0.0, BAND, int(round(BAND / FINE)) + 1), np.geomspace(BAND, RADIUS, 12)[1:]])
    z = np.linspace(-THICKNESS, 0.0, int(round(THICKNESS / FINE)) + 1)
    R, Z = np.meshgrid(r, z, indexing="ij")
    points = np.column_stack([R.ravel(), Z.ravel()])
    index = np.arange(points.shape[0]).reshape(r.size, z.size)
    i, k = np.meshgrid(np.arange(r.size - 1), np.arange(z.size - 1), indexing="ij")
    i, k = i.ravel(), k.ravel()
    cells = np.column_stack([index[i, k], index[i + 1, k], index[i + 1, k + 1], index[i, k + 1]]).astype(np.int64)
    fixed = np.isclose(points[:, 0], RADIUS) | np.isclose(points[:, 1], -THICKNESS)
    top = np.isclose(points[:, 1], 0.0)
    return Mesh(points, cells, "quad", np.zeros(cells.shape[0], np.int64), ["stroma"], True,
                {"fixed": np.flatnonzero(fixed).astype(np.int64)}, {}, {"top": _surface(cells, QUAD_FACES, top)})


def insert(tmp_path, toughness):
    """Push the needle DEPTH into the block at RATE without friction; returns the history."""
    mesh_file = write_mesh(block(), tmp_path / "block.inp")
    (tmp_path / "solid.toml").write_text(f'name = "solid"\ndensity = 1e-9\n[hyperelastic]\nmodel = "neo-hooke"\n'
                                         f"c10 = {C10}\nd1 = {2.0 / BULK}\n")
    path = tmp_path / "block.toml"
    path.write_text(f"""
kind = "needle"
name = "block"
[mesh]
file = "{mesh_file}"
[materials]
stroma = {{ material = "solid.toml" }}
[[constraints]]
node_set = "fixed"
fixed = "rz"
[instrument]
start_gap = 0.002
[instrument.shape]
kind = "needle"
diameter = {2 * NEEDLE_RADIUS}
tip = "conical"
tip_angle = {TIP_ANGLE}
[instrument.motion]
insertion = {{ type = "linear", rate = {RATE} }}
[instrument.contact]
friction = {{ law = "coulomb", coefficient = 0.0 }}
[solver]
end_time = {(DEPTH + 0.002) / RATE}
target_time_step = 4.0e-6
history_every = 20
mass_scaling = "variable"
threads = 1
field_count = 0
[cut]
kind = "radial-cracks"
cracks = {CRACKS}
band_radius = {BAND}
[cut.blocks.stroma]
strength = {STRENGTH}
fracture_energy = {toughness}
""")
    return corneasim.run_scenario(str(path)).history


@pytest.mark.parametrize("toughness", [0.1, 0.2])
def test_the_force_plateau_of_a_deep_insertion_is_the_cut_plus_the_wedge(tmp_path, toughness):
    history = insert(tmp_path, toughness)
    depth, force = history["depth_mm"], history["force_N"]
    steady = (depth >= PLATEAU[0]) & (depth <= PLATEAU[1])
    cut = CRACKS * toughness * NEEDLE_RADIUS
    wedge = 1.5 * math.pi * math.log(4.0) * 2.0 * C10 * NEEDLE_RADIUS ** 2
    assert np.mean(force[steady]) == pytest.approx(cut + wedge, rel=0.05)
    rate = np.polyfit(depth[steady], history["cut_dissipated_energy_mJ"][steady], 1)[0]
    assert rate == pytest.approx(cut, rel=0.05)
