"""Crack-band softening: a failed element dissipates G_f / h_e per unit volume before it dies.

One element in uniaxial strain (every node's lateral motion held, one face pulled), so its
strain is imposed exactly and the internal work is the energy that goes into it. In uniaxial
strain eps (small) the von Mises stress is 2 mu eps, the isochoric energy density
w = 2 mu eps^2 / 3 and the volumetric one K eps^2 / 2. Linear softening of the isochoric
stress from the failure strain to kappa_u times it, kappa_u = G_f / (h w_0), dissipates
w_0 kappa_u = G_f / h per unit volume (the triangle under the deviatoric stress-strain
curve); the volumetric energy K (J - 1)^2 / 2 stays stored until the element is deleted. A
brittle element takes only the energy of its onset strain.
"""

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.materials import KernelMaterial
from corneasim.materials._kernel_form import FAILURE_VON_MISES
from corneasim.solver import (Fixed, Prescribed, SymmetryPlane, build_model, field_output, load_checkpoint, new_state,
                              run)
from corneasim.solver import elements as element_kernels
from corneasim.solver import save_checkpoint
from corneasim.solver._amplitudes import SmoothStep
from test_solver_meshes import box_hex, box_quad

SHEAR, BULK, DENSITY = 0.4, 2.0, 1.0e-9
M = BULK + 4.0 / 3.0 * SHEAR  # uniaxial-strain modulus, MPa
ONSET = 0.004  # strain at which the criterion is met
LIMIT = 2.0 * SHEAR * ONSET  # von Mises failure stress, MPa
W0 = 0.5 * M * ONSET ** 2  # energy density at the onset, mJ/mm^3
W0_ISO = 2.0 / 3.0 * SHEAR * ONSET ** 2  # its isochoric part
RAMP, STRAIN = 1.0e-2, 0.03
SIZE = {"hexahedron": 1.0, "quad": 0.5}  # h_e, mm


def material():
    return KernelMaterial(density=DENSITY, c10=SHEAR / 2, d1=2 / BULK, failure_criterion=FAILURE_VON_MISES,
                          failure_limit=LIMIT)


def one_element(kind, fracture_energy):
    """A unit hexahedron (h = 1 mm) or an axisymmetric quad 0.5 x 0.5 mm at r = 2 mm, pulled in x / z."""
    pull = SmoothStep(0.0, RAMP)
    if kind == "hexahedron":
        mesh = box_hex(1, 1, 1, 1.0, 1.0, 1.0)
        conditions = [Fixed("x0", "x"), Prescribed("x1", "x", "displacement", STRAIN, pull)]
        conditions += [SymmetryPlane(name, name[0]) for name in ("y0", "y1", "z0", "z1")]
        size, volume = 1.0, 1.0
    else:
        mesh = box_quad(1, 1, 2.0, 2.5, 0.0, 0.5)
        conditions = [Fixed("r0", "r"), Fixed("r1", "r"), Fixed("z0", "z"),
                      Prescribed("z1", "z", "displacement", STRAIN * 0.5, pull)]
        size, volume = 0.5, 2.0 * np.pi * 2.25 * 0.25
    model = build_model(mesh, {mesh.block_names[0]: material()}, conditions,
                        fracture_energy={mesh.block_names[0]: fracture_energy})
    return model, size, volume


def dissipated(model):
    """Pull until the element dies; return (internal minus bulk-viscous work then, mJ; strain then; state)."""
    state = new_state(model)
    for frame in run(model, state, RAMP, history_every=1):
        if state.alive[0] == 0:
            break
    strain = state.u[:, -1].max() / model.mesh.points[:, -1].max() if model.mesh.axisymmetric else \
        state.u[:, 0].max()
    return frame.history["internal_energy_mJ"] - frame.history["viscous_energy_mJ"], strain, state


@pytest.mark.parametrize("kind", ["hexahedron", "quad"])
def test_softening_element_dissipates_the_fracture_energy_per_band_area(kind):
    ultimate = 4.0  # the stress reaches zero at 4 x the onset strain (0.016 < STRAIN)
    model, size, volume = one_element(kind, ultimate * SIZE[kind] * W0_ISO)
    energy, strain, state = dissipated(model)
    assert state.alive.tolist() == [0]
    assert state.damage[0, 2] == pytest.approx(ultimate, rel=0.03)
    assert strain == pytest.approx(ultimate * ONSET, rel=0.03)
    # G_f / h x V dissipated, plus the volumetric energy still stored at deletion
    assert energy == pytest.approx((ultimate * W0_ISO + 0.5 * BULK * strain ** 2) * volume, rel=0.03)


def test_without_fracture_energy_the_element_fails_brittle():
    model, size, volume = one_element("hexahedron", 0.0)
    assert model.softening is None
    energy, strain, state = dissipated(model)
    assert state.alive.tolist() == [0]
    assert energy == pytest.approx(W0 * volume, rel=0.05)


def test_an_element_too_large_for_its_fracture_energy_fails_brittle():
    model, size, volume = one_element("hexahedron", 0.5 * SIZE["hexahedron"] * W0_ISO)  # kappa_u = 0.5
    energy, strain, state = dissipated(model)
    assert state.alive.tolist() == [0] and state.damage[0, 0] == 0.0
    assert energy == pytest.approx(W0 * volume, rel=0.05)


def test_softened_deviatoric_stress_is_the_intact_one_times_one_minus_damage():
    model, size, volume = one_element("quad", 4.0 * 0.5 * W0_ISO)
    state = new_state(model)
    for frame in run(model, state, 0.4 * RAMP, history_every=10):
        pass
    damage = state.damage[0, 0]
    kappa = state.damage[0, 1]
    assert 0.0 < damage < 1.0 and state.alive[0] == 1
    # linear softening: (1 - D) kappa = (kappa_u - kappa) / (kappa_u - 1)
    ultimate = state.damage[0, 2]
    assert (1.0 - damage) * kappa == pytest.approx((ultimate - kappa) / (ultimate - 1.0), rel=1e-12)
    intact, _, _ = one_element("quad", 0.0)  # same element, undamaged
    mesh = intact.mesh
    volumetric = build_model(mesh, {"solid": KernelMaterial(density=DENSITY, c10=0.0, d1=2 / BULK)})
    forces, intact_forces, volumetric_forces = (np.zeros_like(state.u) for _ in range(3))
    history = state.history.copy()
    history[:, -1, :] = 0.0  # no volumetric rate: bulk viscosity is not softened
    element_kernels.eval_internal_forces(state.elements, state.u, 0.0, state.alive, history,
                                         forces, np.zeros(1), np.zeros(3))
    element_kernels.eval_internal_forces(intact.elements, state.u, 0.0, state.alive,
                                         element_kernels.new_history(intact.elements), intact_forces,
                                         np.zeros(1), np.zeros(3))
    element_kernels.eval_internal_forces(volumetric.elements, state.u, 0.0, state.alive,
                                         element_kernels.new_history(volumetric.elements), volumetric_forces,
                                         np.zeros(1), np.zeros(3))
    expected = volumetric_forces + (1.0 - damage) * (intact_forces - volumetric_forces)
    np.testing.assert_allclose(forces, expected, rtol=1e-9, atol=1e-15)
    assert not np.allclose(forces, intact_forces, rtol=1e-3)
    assert field_output(model, state)["damage"].tolist() == [damage]
    assert "damage" not in field_output(intact, new_state(intact))


def test_checkpoint_restores_the_softened_rows(tmp_path):
    model, size, volume = one_element("quad", 4.0 * 0.5 * W0_ISO)
    state = new_state(model)
    for frame in run(model, state, 0.4 * RAMP, history_every=10):
        pass
    save_checkpoint(tmp_path / "c.npz", model, state)
    fresh, _, _ = one_element("quad", 4.0 * 0.5 * W0_ISO)
    restored = load_checkpoint(tmp_path / "c.npz", fresh)
    np.testing.assert_array_equal(restored.damage, state.damage)
    np.testing.assert_allclose(restored.elements.material_table[restored.elements.element_material[0]],
                               state.elements.material_table[state.elements.element_material[0]])


def test_negative_fracture_energy_or_unknown_block_is_an_input_error():
    with pytest.raises(InputError, match="fracture_energy of block 'solid'"):
        one_element("quad", -1.0)
    mesh = box_quad(1, 1, 2.0, 2.5, 0.0, 0.5)
    with pytest.raises(InputError, match="fracture_energy: no block 'stroma'"):
        build_model(mesh, {"solid": material()}, fracture_energy={"stroma": 1.0})
    without_criterion = KernelMaterial(density=DENSITY, c10=SHEAR / 2, d1=2 / BULK)
    with pytest.raises(InputError, match="von Mises"):
        build_model(mesh, {"solid": without_criterion}, fracture_energy={"solid": 1.0})
