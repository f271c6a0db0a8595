"""Adding a material law: the worked example of docs/elements.md, registered and checked.

The example registers the neo-Hookean law under its own name with the shear modulus as its
constant, W = mu/2 (I1bar - 3) + (J - 1)^2 / D1, and checks the registered law against the
closed-form uniaxial stress sigma_11 = mu (lambda^2 - 1/lambda) of an incompressible bar,
through the curve code, the pointwise Cauchy stress, the fit and the fast element kernel.
"""

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.materials import (
    LAWS, KernelMaterial, Law, cauchy_stress, check_stability, fit_hyperelastic,
    homogeneous_cauchy_stress, homogeneous_nominal_stress, kernel_table, register_law)
from corneasim.materials._laws import family_constants
from corneasim.solver import elements as el

from elements_helpers import RHO, grid_hex

SHEAR_NEO_HOOKE = Law(
    name="neo-hooke-mu",
    keys=("mu",),
    family=lambda p: (0.5 * p[0], 0.0, 0.0, 0.0),  # C10 = mu / 2
    fit_start=(2.0,),
)
MU = 0.6  # MPa
STRETCHES = np.array([0.7, 0.9, 1.0, 1.3, 2.0])


def uniaxial_closed_form(stretch):
    return MU * (stretch**2 - 1.0 / stretch)


@pytest.fixture
def law():
    register_law(SHEAR_NEO_HOOKE)
    yield SHEAR_NEO_HOOKE
    LAWS.pop(SHEAR_NEO_HOOKE.name)


def test_registered_law_gives_the_closed_form_uniaxial_stress(law):
    got = homogeneous_cauchy_stress(law.name, [MU, 1.0], "uniaxial", STRETCHES)
    np.testing.assert_allclose(got, uniaxial_closed_form(STRETCHES), rtol=1e-13, atol=1e-15)
    for stretch in STRETCHES:  # the compressible 3D law at J = 1: no pressure
        F = np.diag([stretch, stretch**-0.5, stretch**-0.5])
        sigma = cauchy_stress(law.name, [MU, 0.05], F)
        assert sigma[0, 0] - sigma[1, 1] == pytest.approx(uniaxial_closed_form(stretch), rel=1e-12)
        assert sigma[1, 1] == pytest.approx(sigma[2, 2], abs=1e-14)


def test_registered_law_is_fitted_and_checked_like_a_built_in_one(law):
    data = (STRETCHES, homogeneous_nominal_stress(law.name, [MU, 1.0], "uniaxial", STRETCHES))
    result = fit_hyperelastic(law.name, data)
    assert result.constants() == {"mu": pytest.approx(MU, rel=1e-6)}
    assert check_stability(law.name, [MU, 1.0]).stable


def test_registered_law_runs_in_the_fast_element_kernel(law):
    """One hexahedron under the isochoric uniaxial F: the kernel's failure ratio with a
    von Mises limit of 1 MPa is |sigma_11 - sigma_22|, the closed form."""
    points, cells = grid_hex(1, size=1.0)
    record = KernelMaterial(RHO, *family_constants(law.name, [MU, 0.05]), d1=0.05,
                            failure_criterion=1, failure_limit=1.0)
    elements = el.prepare(points, cells, "hexahedron", [0], kernel_table([record]), kernel="fast")
    for stretch in (0.9, 1.3):
        F = np.diag([stretch, stretch**-0.5, stretch**-0.5])
        u = points @ (F - np.eye(3)).T
        ratio = np.zeros(1)
        el.eval_internal_forces(elements, u, 0.0, np.ones(1, np.uint8), el.new_history(elements),
                                np.zeros_like(points), ratio, np.zeros(3))
        assert ratio[0] == pytest.approx(abs(uniaxial_closed_form(stretch)), rel=1e-12)


def test_unknown_law_is_an_input_error():
    with pytest.raises(InputError, match="unknown hyperelastic law 'rubber'"):
        homogeneous_cauchy_stress("rubber", [1.0, 1.0], "uniaxial", STRETCHES)
