"""Quality measures against hand-computed shapes; check_elements names the bad element."""

import math

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.mesh import Mesh
from corneasim.mesh._quality import (
    check_elements,
    characteristic_lengths,
    corner_jacobians,
    dilatational_wave_speed,
    element_measures,
    quality_report,
)

CUBE = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)


def quad_mesh(points, cells=((0, 1, 2, 3),)):
    return Mesh(points=np.array(points, float), cells=np.array(cells), cell_type="quad",
                element_block=np.zeros(len(cells), dtype=np.int64), block_names=["stroma"], axisymmetric=True)


def hex_mesh(points):
    return Mesh(points=np.array(points, float), cells=np.arange(8)[None], cell_type="hexahedron",
                element_block=np.zeros(1, dtype=np.int64), block_names=["sclera"])


def test_square_and_parallelogram():
    square = quad_mesh([[0, 0], [2, 0], [2, 2], [0, 2]])
    assert np.allclose(corner_jacobians(square), 1.0)
    assert characteristic_lengths(square)[0] == pytest.approx(2.0)
    report = quality_report(square, wave_speed=4.0)
    assert report.max_aspect_ratio == pytest.approx(1.0)
    assert report.stable_time_step == pytest.approx(0.5)  # L / c
    angle = math.radians(60)
    rhombus = quad_mesh([[0, 0], [1, 0], [1 + math.cos(angle), math.sin(angle)], [math.cos(angle), math.sin(angle)]])
    assert np.allclose(corner_jacobians(rhombus), math.sin(angle))  # sin of the corner angle
    assert element_measures(rhombus)[0] == pytest.approx(math.sin(angle))


def test_cube_and_sheared_brick():
    cube = hex_mesh(2 * CUBE)
    assert np.allclose(corner_jacobians(cube), 1.0)
    assert element_measures(cube)[0] == pytest.approx(8.0)
    assert characteristic_lengths(cube)[0] == pytest.approx(2.0)
    sheared = CUBE * [3.0, 1.0, 0.5]
    sheared[4:, 0] += 0.5  # shear the top face along x by 0.5 over the height 0.5 (45 degrees)
    brick = hex_mesh(sheared)
    assert element_measures(brick)[0] == pytest.approx(1.5)  # shear keeps the volume
    assert corner_jacobians(brick).min() == pytest.approx(math.sin(math.radians(45)))
    assert quality_report(brick).max_aspect_ratio == pytest.approx(3.0 / math.hypot(0.5, 0.5))  # slanted edges


def test_block_and_refined_counts_in_the_report():
    mesh = quad_mesh([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]], cells=((0, 1, 4, 3), (1, 2, 5, 4)))
    mesh.element_block = np.array([0, 1])
    mesh.block_names = ["epithelium", "stroma"]
    mesh.element_sets = {"refined": np.array([1])}
    report = quality_report(mesh)
    assert report.block_counts == {"epithelium": 1, "stroma": 1}
    assert report.refined_count == 1
    assert any("50.0%" in line for line in report.lines())


@pytest.mark.parametrize(
    "points, fragment",
    [
        ([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0], [1, 0], [1, 1], [0, 1]], None),
        ([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0], [1, 0], [0, 1], [1, 1]], "inverted"),
        ([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0], [1, 0], [1, 0], [0, 1]], "degenerate"),
    ],
)
def test_check_elements_names_the_first_bad_element(points, fragment):
    mesh = quad_mesh(points, cells=((0, 1, 2, 3), (4, 5, 6, 7)))
    if fragment is None:
        check_elements(mesh)
        return
    with pytest.raises(InputError, match=f"element 1 \\(block 'stroma'\\) is {fragment}"):
        check_elements(mesh)


def test_inverted_hexahedron_is_reported():
    flipped = CUBE[[4, 5, 6, 7, 0, 1, 2, 3]]
    with pytest.raises(InputError, match="element 0 .* inverted"):
        check_elements(hex_mesh(flipped))


def test_wave_speed_is_the_p_wave_speed():
    E, nu, rho = 3.08, 0.49, 1.0e-9
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    assert dilatational_wave_speed(E, nu, rho) == pytest.approx(math.sqrt((lam + 2 * mu) / rho))
    with pytest.raises(InputError, match="wave speed"):
        quality_report(hex_mesh(CUBE), wave_speed=-1.0)
