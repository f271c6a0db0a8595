"""The parametric eye: derived surfaces satisfy the dimensions they were built from."""

import math

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.mesh._geometry import EyeGeometry


def test_porcine_defaults_are_table_1():
    g = EyeGeometry()
    assert (g.anterior_radius, g.posterior_radius, g.central_thickness, g.peripheral_thickness) == (7.8, 6.8, 0.55, 1.0)
    assert (g.horizontal_diameter, g.vertical_diameter, g.axial_length) == (11.2, 11.0, 26.5)
    assert g.epithelium_thickness == 0.067
    assert g.limbus_radius == pytest.approx(5.55)


def test_posterior_surface_meets_thickness_and_apical_radius():
    g = EyeGeometry()
    shape = g.shape()
    A, P = np.array(shape.anterior_limbus), np.array(shape.posterior_limbus)
    # A on the anterior sphere at the limbus radius
    assert A[0] == pytest.approx(g.limbus_radius)
    assert math.hypot(A[0], A[1] + g.anterior_radius) == pytest.approx(g.anterior_radius)
    # P is the peripheral thickness away along the anterior normal, and on the posterior surface
    normal = (A - np.array([0.0, -g.anterior_radius])) / g.anterior_radius
    assert np.allclose(A - g.peripheral_thickness * normal, P)
    assert shape.posterior_z(np.array([P[0]]))[0] == pytest.approx(P[1])
    # apex at -t_c, apical curvature 1 / R_p (finite differences of z(r) at r = 0)
    h = 1e-3
    z0, z1 = shape.posterior_z(np.array([0.0, h]))
    assert z0 == pytest.approx(-g.central_thickness)
    assert -2 * (z1 - z0) / h**2 == pytest.approx(1 / g.posterior_radius, rel=1e-5)


def test_sclera_spheres_pass_through_limbus_and_poles():
    g = EyeGeometry()
    s = g.shape()
    A, P = s.anterior_limbus, s.posterior_limbus
    assert math.hypot(A[0], A[1] - s.globe_centre) == pytest.approx(s.globe_radius)
    assert s.globe_centre - s.globe_radius == pytest.approx(-g.axial_length)
    assert math.hypot(P[0], P[1] - s.inner_centre) == pytest.approx(s.inner_radius)
    assert s.inner_centre - s.inner_radius == pytest.approx(-g.axial_length + g.sclera_thickness)


@pytest.mark.parametrize(
    "changes, fragment",
    [
        (dict(epithelium_thickness=0.6), "epithelium_thickness"),
        (dict(horizontal_diameter=16.0, vertical_diameter=16.0), "limbus radius"),
        (dict(peripheral_thickness=3.0), "peripheral_thickness"),
        (dict(axial_length=5.0), "axial_length"),
    ],
)
def test_impossible_dimensions_are_one_line_errors(changes, fragment):
    with pytest.raises(InputError, match=fragment):
        EyeGeometry(**changes).shape()
