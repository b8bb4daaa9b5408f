"""python_prototypes/volumes.py: the .vol reader and writer, the trilinear lookup
against closed forms, the optical depth against exact integrals, and the cloud."""

import numpy as np
import pytest

from python_prototypes import volumes


def linear_grid(resolution=(5, 4, 3)):
    """Values a + b x + c y + d z at the cells' centres of a box from (-1, 0, 2) to
    (1, 2, 3): trilinear interpolation reproduces that function exactly between them."""
    x, y, z = resolution
    box_min, box_max = np.array([-1.0, 0.0, 2.0]), np.array([1.0, 2.0, 3.0])
    size = (box_max - box_min) / np.array(resolution)
    cz, cy, cx = np.meshgrid(*[box_min[a] + (np.arange(n) + 0.5) * size[a]
                               for a, n in ((2, z), (1, y), (0, x))], indexing="ij")
    return volumes.Grid((0.5 + 0.2 * cx + 0.1 * cy + 0.3 * cz).astype(np.float32),
                        box_min, box_max), size


def test_a_grid_survives_writing_and_reading(tmp_path):
    grid, _ = linear_grid()
    volumes.write_vol(tmp_path / "g.vol", grid)
    again = volumes.read_vol(tmp_path / "g.vol")
    assert np.array_equal(again.density, grid.density)
    assert np.allclose(again.box_min, grid.box_min) and np.allclose(again.box_max, grid.box_max)
    assert (tmp_path / "g.vol").stat().st_size == 48 + 4 * grid.density.size
    assert not list(tmp_path.glob("*.partial"))


def test_a_file_that_is_not_a_grid_is_refused(tmp_path):
    (tmp_path / "bad.vol").write_bytes(b"VOX" + bytes(60))
    with pytest.raises(ValueError, match="not a one-channel float32 .vol grid"):
        volumes.read_vol(tmp_path / "bad.vol")


def test_trilinear_reproduces_a_linear_function_between_the_centres():
    grid, size = linear_grid()
    rng = np.random.default_rng(2)
    inner_min, inner_max = grid.box_min + size / 2, grid.box_max - size / 2
    points = inner_min + rng.random((500, 3)) * (inner_max - inner_min)
    expected = 0.5 + points @ np.array([0.2, 0.1, 0.3])
    assert np.allclose(volumes.density_at(grid, points), expected, atol=1e-6)


def test_near_a_face_the_faces_values_hold_and_outside_the_grid_is_empty():
    grid, size = linear_grid()
    centre = (grid.box_min + grid.box_max) / 2
    # Within half a cell of the face x = min, x is clamped to the first centre.
    near = np.array([[grid.box_min[0] + size[0] / 4, centre[1], centre[2]]])
    at_centre = np.array([[grid.box_min[0] + size[0] / 2, centre[1], centre[2]]])
    assert np.allclose(volumes.density_at(grid, near), volumes.density_at(grid, at_centre))
    outside = np.array([[grid.box_min[0] - 1e-3, centre[1], centre[2]],
                        [centre[0], grid.box_max[1] + 0.5, centre[2]]])
    assert np.array_equal(volumes.density_at(grid, outside), [0.0, 0.0])


def test_the_optical_depth_of_a_constant_grid_is_scale_density_chord():
    grid = volumes.Grid(np.full((3, 3, 3), 0.25, np.float32), np.array([-1.0] * 3),
                        np.array([1.0] * 3))
    direction = np.array([1.0, 0.5, 0.25]) / np.linalg.norm([1.0, 0.5, 0.25])
    depth = volumes.optical_depth(grid, 8.0, (-3.0, -1.5, -0.75), direction, 10.0)
    chord = 2.0 / direction[0]  # enters at x = -1, leaves at x = 1 (y, z stay inside)
    assert depth == pytest.approx(8.0 * 0.25 * chord, rel=1e-3)


def test_the_optical_depth_along_a_linear_grid_is_its_integral():
    grid, size = linear_grid()
    # Along x through the inner region: y, z fixed; the density is linear in x there.
    y, z = 1.0, 2.5
    x0, x1 = grid.box_min[0] + size[0] / 2, grid.box_max[0] - size[0] / 2
    depth = volumes.optical_depth(grid, 2.0, (x0, y, z), (1.0, 0.0, 0.0), x1 - x0)
    exact = 2.0 * ((0.5 + 0.1 * y + 0.3 * z) * (x1 - x0) + 0.1 * (x1 ** 2 - x0 ** 2))
    assert depth == pytest.approx(exact, rel=1e-6)


def test_the_cloud_is_bounded_densest_one_and_empty_at_its_edges():
    cloud = volumes.cloud()
    d = cloud.density
    assert d.shape == (48, 48, 48) and d.dtype == np.float32
    assert d.max() == 1.0 and d.min() == 0.0 and 0.05 < (d > 0).mean() < 0.5
    assert not (d[[0, -1]].any() or d[:, [0, -1]].any() or d[:, :, [0, -1]].any())
    assert np.array_equal(volumes.cloud().density, d)  # the same every build
