"""Backward displacement on a thick neo-Hookean sphere against its closed-form inflation.

An incompressible neo-Hookean sphere (shear modulus mu) inflated from the stress-free radii
(A, B) to (a, b), with a^3 - A^3 = b^3 - B^3, takes the internal pressure

    p = int_{lambda_b}^{lambda_a} W'(lambda) / (lambda^3 - 1) dlambda,
    W(lambda) = mu/2 (2 lambda^2 + lambda^-4 - 3),  lambda_a = a/A, lambda_b = b/B

(Ogden, Non-linear Elastic Deformations, 1984, sec. 5.3.2), which for this W is
p = 2 mu [g(lambda_b) - g(lambda_a)], g(lambda) = 1/lambda + 1/(4 lambda^4). The mesh is the
loaded sphere (a, b) = (1, 2) mm; the iteration must find the stress-free (A, B) that this
relation gives for the applied p. The model is nearly incompressible (K = 200 mu).
"""

import dataclasses
import re

import numpy as np
import pytest

from corneasim.materials import KernelMaterial
from corneasim.solver import (
    Pressure, SimulationError, SmoothStep, SymmetryPlane, backward_displacement, build_model, new_state, preload)
from test_solver_meshes import sphere_octant_hex, sphere_quarter_quad

INNER, OUTER = 1.0, 2.0  # mm, loaded radii (the mesh)
SHEAR, BULK, DENSITY = 0.1, 20.0, 1.0e-9  # MPa, MPa, tonne/mm^3
MATERIAL = KernelMaterial(density=DENSITY, c10=SHEAR / 2, d1=2 / BULK)
STRETCH = 1.2  # inner hoop stretch a / A of the closed-form solution
TOLERANCE = 1e-4  # mm


def stress_free_outer(inner_free):
    """B from A by incompressibility (mm)."""
    return (OUTER ** 3 - INNER ** 3 + inner_free ** 3) ** (1 / 3)


def inflation_pressure(inner_free):
    """Pressure (MPa) that inflates the stress-free sphere (A, B(A)) to (a, b) (module notes)."""
    def g(stretch):
        return 1 / stretch + 1 / (4 * stretch ** 4)
    return 2 * SHEAR * (g(OUTER / stress_free_outer(inner_free)) - g(INNER / inner_free))


INNER_FREE = INNER / STRETCH
PRESSURE = inflation_pressure(INNER_FREE)


def solver_for(mesh, conditions):
    """The loaded geometry (mm) of the sphere built on reference points X: ramp 1 ms, settle to 4 ms."""
    def solve(points):
        model = build_model(dataclasses.replace(mesh, points=points), {"shell": MATERIAL}, conditions,
                            [Pressure("inner", PRESSURE, SmoothStep(0.0, 1e-3))])
        state = new_state(model)
        for _ in preload(model, state, 4e-3, damping=1e4, history_every=10 ** 9):
            pass
        return points + state.u
    return solve


def radii(points, nodes):
    return np.linalg.norm(points[nodes], axis=1)


def check_stress_free_radii(mesh, reference, tolerance=TOLERANCE):
    assert reference.converged and reference.errors[-1] <= tolerance
    assert reference.errors[0] > 0.1  # the mesh taken as stress-free inflates by far more
    for name, loaded, free in (("inner", INNER, INNER_FREE), ("outer", OUTER, stress_free_outer(INNER_FREE))):
        found = radii(reference.points, mesh.node_sets[name])
        # within 2% of the inflation displacement (discretisation and the finite bulk modulus)
        assert np.all(np.abs(found - free) < 0.02 * (loaded - free)), (name, found, free)


def test_the_closed_form_pressure_is_the_thin_shell_limit():
    """An independent check of the closed form: a thin shell of thickness h takes
    p = 2 mu h/R (lambda^-1 - lambda^-7)."""
    radius, thickness, stretch = 10.0, 1e-3, 1.3
    outer = (radius ** 3 + 3 * radius ** 2 * thickness) ** (1 / 3)
    loaded_inner = stretch * radius
    loaded_outer = (loaded_inner ** 3 + outer ** 3 - radius ** 3) ** (1 / 3)
    def g(value):
        return 1 / value + 1 / (4 * value ** 4)
    closed = 2 * SHEAR * (g(loaded_outer / outer) - g(stretch))
    membrane = 2 * SHEAR * thickness / radius * (stretch ** -1 - stretch ** -7)
    assert closed == pytest.approx(membrane, rel=1e-3)


@pytest.fixture(scope="module")
def axisymmetric():
    """The quarter-section sphere's iteration stopped after 2 solves, then continued to convergence."""
    mesh = sphere_quarter_quad(INNER, OUTER, 4, 20)
    solve = solver_for(mesh, [SymmetryPlane("equator", "z")])
    saved = []
    with pytest.raises(SimulationError) as failure:
        backward_displacement(mesh.points, solve, TOLERANCE, 2, on_iteration=saved.append)
    continued = backward_displacement(mesh.points, solve, TOLERANCE, 20, start=saved[-1])
    return mesh, solve, str(failure.value), saved, continued


def test_axisymmetric_sphere_recovers_its_stress_free_radii(axisymmetric):
    mesh, solve, _, _, reference = axisymmetric
    check_stress_free_radii(mesh, reference)
    errors = reference.errors
    assert all(later < 0.5 * earlier for earlier, later in zip(errors, errors[1:]))  # linear convergence
    loaded = solve(reference.points)  # the loaded geometry is the measured one
    assert np.abs(loaded - mesh.points).max() <= TOLERANCE


def test_hexahedral_sphere_recovers_its_stress_free_radii():
    mesh = sphere_octant_hex(INNER, OUTER, 4, 4)
    solve = solver_for(mesh, [SymmetryPlane(f"{axis}0", axis) for axis in "xyz"])
    check_stress_free_radii(mesh, backward_displacement(mesh.points, solve, 1e-3, 20), 1e-3)


def test_an_iteration_that_does_not_converge_fails_in_one_line_and_can_be_continued(axisymmetric):
    _, _, message, saved, continued = axisymmetric
    assert re.fullmatch(r"stress-free reference: not converged in 2 iterations \(largest nodal error 0\.2\d* mm at "
                        r"the first, 0\.0\d* mm at the last; tolerance 0\.0001 mm\)", message), message
    assert [len(item.errors) for item in saved] == [1, 2] and not saved[-1].converged
    assert continued.errors[:2] == saved[-1].errors
