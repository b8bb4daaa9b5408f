"""Checks for the Python prototypes: teapot tessellator, pinhole camera and OBJ reader."""

import csv
import math
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[3]

from python_prototypes import camera_rays
from python_prototypes import obj_io
from python_prototypes import teapot

OBJ_DIR = REPO / "tests" / "data" / "obj"
BAD_OBJ_DIR = OBJ_DIR / "bad"


def read_tsv(path):
    with open(path, newline="") as table:
        return list(csv.DictReader(table, delimiter="\t"))


# ---------------------------------------------------------------------------------------
# Teapot
# ---------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def teapot_patches():
    assert teapot.DEFAULT_PATCH_FILE.exists(), f"no teapot data at {teapot.DEFAULT_PATCH_FILE}"
    return teapot.load_patches(teapot.DEFAULT_PATCH_FILE)


@pytest.fixture(scope="module")
def teapot_3(teapot_patches):
    patches, control_points = teapot_patches
    return teapot.tessellate(patches, control_points, 3)


def test_teapot_data_has_32_patches(teapot_patches):
    patches, control_points = teapot_patches
    assert patches.shape == (32, 16)
    assert control_points.shape == (306, 3)


def test_teapot_n3_has_about_500_triangles(teapot_3):
    _, _, triangles = teapot_3
    assert 500 <= len(triangles) <= 600
    assert len(triangles) == teapot.expected_triangle_count(3)


def test_teapot_normals_are_unit_length(teapot_3):
    _, normals, _ = teapot_3
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-9)


def test_teapot_body_normals_point_away_from_the_axis(teapot_patches):
    positions, normals, _ = teapot.tessellate(*teapot_patches, 10)
    radius = np.hypot(positions[:, 0], positions[:, 2])
    # The body, away from the lid, the bottom, and the spout and handle (near z = 0).
    body = ((radius > 1.2) & (positions[:, 1] > 0.3) & (positions[:, 1] < 2.2)
            & (np.abs(positions[:, 2]) > 0.4))
    radial = positions[body][:, [0, 2]] / radius[body, np.newaxis]
    outward = np.sum(normals[body][:, [0, 2]] * radial, axis=1)
    assert body.sum() > 50
    assert np.all(outward > 0)


def test_teapot_normals_agree_with_winding_and_enclose_positive_volume(teapot_3):
    positions, normals, triangles = teapot_3
    a, b, c = (positions[triangles[:, k]] for k in range(3))
    face_normals = np.cross(b - a, c - a)
    corner_normals = normals[triangles].sum(axis=1)
    assert np.all(np.sum(face_normals * corner_normals, axis=1) > 0)
    signed_volume = np.sum(a * np.cross(b, c)) / 6.0
    assert signed_volume > 0  # counter-clockwise from outside encloses positive volume


def test_teapot_lid_top_and_bottom_centre_normals(teapot_3):
    positions, normals, _ = teapot_3
    top = np.argmax(positions[:, 1])
    bottom_centre = np.argmin(np.linalg.norm(positions, axis=1))
    assert np.allclose(normals[top], [0.0, 1.0, 0.0], atol=1e-6)
    assert np.allclose(positions[bottom_centre], 0.0, atol=1e-9)
    assert np.allclose(normals[bottom_centre], [0.0, -1.0, 0.0], atol=1e-6)


def test_teapot_stands_on_y0_and_is_y_up(teapot_3):
    positions, _, _ = teapot_3
    low, high = positions.min(axis=0), positions.max(axis=0)
    assert low[1] == pytest.approx(0.0, abs=1e-9)
    assert high[1] == pytest.approx(3.15, abs=1e-6)
    assert high[0] - low[0] > 6.0  # spout to handle runs along x


def test_teapot_welding_merges_patch_edges(teapot_3):
    positions, _, triangles = teapot_3
    unwelded = 32 * 4 * 4  # (N + 1)^2 grid points per patch for N = 3
    assert len(positions) < unwelded
    assert len(np.unique(triangles)) == len(positions)  # every vertex is used
    assert np.all(triangles[:, 0] != triangles[:, 1])
    assert np.all(triangles[:, 1] != triangles[:, 2])
    assert np.all(triangles[:, 2] != triangles[:, 0])


def test_teapot_triangle_budget():
    assert teapot.segments_for_triangles(500) == 3
    assert teapot.segments_for_triangles(6000) == 10
    assert teapot.segments_for_triangles(100_000) == 40
    budget = 1_000_000
    segments = teapot.segments_for_triangles(budget)
    assert teapot.expected_triangle_count(segments) >= budget
    assert teapot.expected_triangle_count(segments - 1) < budget


def test_teapot_obj_rereads_to_the_same_arrays(teapot_3, tmp_path):
    positions, normals, triangles = teapot_3
    path = tmp_path / "teapot.obj"
    teapot.write_obj(path, positions, normals, triangles)
    read_positions, read_normals, tri_positions, tri_normals = obj_io.read_obj(path)
    assert np.allclose(read_positions, positions, atol=1e-6)
    assert np.allclose(read_normals, normals, atol=1e-6)
    assert np.array_equal(tri_positions, triangles)
    assert np.array_equal(tri_normals, triangles)


def test_teapot_cli_writes_obj_without_normals(teapot_patches, tmp_path, capsys):
    path = tmp_path / "flat.obj"
    teapot.main(["--triangles", "500", "--no-normals", "--out", str(path)])
    assert "552 triangles" in capsys.readouterr().out
    positions, normals, tri_positions, tri_normals = obj_io.read_obj(path)
    assert normals is None and tri_normals is None
    assert len(tri_positions) == 552


# ---------------------------------------------------------------------------------------
# Camera
# ---------------------------------------------------------------------------------------

def default_rays(width, height, **changes):
    camera = camera_rays.Camera(**changes)
    return camera, camera_rays.camera_rays(camera, width, height)


def test_camera_centre_ray_is_the_look_direction():
    camera, directions = default_rays(65, 33)
    expected = np.array(camera.look_direction) / np.linalg.norm(camera.look_direction)
    assert np.allclose(directions[16, 32], expected, atol=1e-12)


def test_camera_directions_are_unit_length_float64():
    _, directions = default_rays(40, 30)
    assert directions.shape == (30, 40, 3) and directions.dtype == np.float64
    assert np.allclose(np.linalg.norm(directions, axis=2), 1.0, atol=1e-12)


def test_camera_row_0_is_the_top_and_column_0_the_left():
    camera, directions = default_rays(40, 30, look_direction=(0.0, 0.0, -1.0))
    assert directions[0, 20, 1] > 0 > directions[29, 20, 1]  # up is +y
    assert directions[15, 0, 0] < 0 < directions[15, 39, 0]  # right is +x


def test_camera_corner_rays_are_symmetric():
    # Looking straight down -z, the four corners mirror each other in x and y.
    _, directions = default_rays(32, 24, look_direction=(0.0, 0.0, -1.0))
    top_left, top_right = directions[0, 0], directions[0, -1]
    bottom_left, bottom_right = directions[-1, 0], directions[-1, -1]
    assert np.allclose(top_right, top_left * [-1, 1, 1], atol=1e-12)
    assert np.allclose(bottom_left, top_left * [1, -1, 1], atol=1e-12)
    assert np.allclose(bottom_right, top_left * [-1, -1, 1], atol=1e-12)


def test_camera_corner_rays_make_equal_angles_with_forward():
    camera, directions = default_rays(32, 24)  # tilted camera: symmetric about forward
    forward = np.array(camera.look_direction) / np.linalg.norm(camera.look_direction)
    corners = directions[[0, 0, -1, -1], [0, -1, 0, -1]]
    assert np.allclose(corners @ forward, corners[0] @ forward, atol=1e-12)


def test_camera_horizontal_field_of_view():
    width, height = 64, 48
    camera, directions = default_rays(width, height)
    # Pixel centres sit half a pixel inside the sensor edges: undo that, from the
    # angles of the edge rays to forward.
    forward = np.array(camera.look_direction) / np.linalg.norm(camera.look_direction)
    _, right, _ = camera_rays.camera_basis(camera.look_direction, camera.up)
    middle_row = directions[height // 2]  # any row works: project out true_up
    left, right_edge = middle_row[0], middle_row[-1]

    def offset_on_sensor(direction):  # signed distance from the centre, along right
        return camera.focal_length * (direction @ right) / (direction @ forward)

    pixel_size = camera.sensor_width / width
    half_width = offset_on_sensor(right_edge) + pixel_size / 2
    assert offset_on_sensor(left) - pixel_size / 2 == pytest.approx(-half_width)
    measured = 2.0 * math.atan(half_width / camera.focal_length)
    expected = 2.0 * math.atan(camera.sensor_width / 2.0 / camera.focal_length)
    assert measured == pytest.approx(expected, rel=1e-12)
    assert math.degrees(expected) == pytest.approx(54.43, abs=0.01)


def test_camera_square_pixels():
    camera, directions = default_rays(40, 20, look_direction=(0.0, 0.0, -1.0))
    plane_hits = directions / -directions[..., 2:3] * camera.focal_length
    step_x = plane_hits[10, 21, 0] - plane_hits[10, 20, 0]
    step_y = plane_hits[10, 20, 1] - plane_hits[11, 20, 1]
    assert step_x == pytest.approx(step_y, rel=1e-12)
    assert step_x == pytest.approx(camera.sensor_width / 40, rel=1e-12)


def test_camera_rejects_up_parallel_to_forward():
    with pytest.raises(ValueError):
        camera_rays.camera_ray_directions(4, 4, (0, 0, 0), (0, 2, 0), (0, 1, 0),
                                          0.035, 0.036)


def test_ray_colors_map_directions_to_0_1():
    colors = camera_rays.ray_colors(np.array([[-1.0, 0.0, 1.0]]))
    assert np.allclose(colors, [[0.0, 0.5, 1.0]])


def test_camera_cli_writes_float32_npy(tmp_path):
    path = tmp_path / "rays.npy"
    camera_rays.main(["--width", "7", "--height", "5", "--out-npy", str(path)])
    written = np.load(path)
    assert written.dtype == np.float32 and written.shape == (5, 7, 3)
    _, expected = default_rays(7, 5)
    assert np.allclose(written, expected, atol=1e-7)


def test_camera_figure_is_written(tmp_path):
    path = tmp_path / "camera.png"
    camera_rays.main(["--figure", str(path)])
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# ---------------------------------------------------------------------------------------
# OBJ reader and the OBJ corpus
# ---------------------------------------------------------------------------------------

VALID_FILES = read_tsv(OBJ_DIR / "expected_valid.tsv")
BAD_FILES = read_tsv(BAD_OBJ_DIR / "expected.tsv")


@pytest.mark.parametrize("row", VALID_FILES, ids=[row["file"] for row in VALID_FILES])
def test_obj_valid_file_counts(row):
    positions, normals, tri_positions, tri_normals = obj_io.read_obj(OBJ_DIR / row["file"])
    assert len(positions) == int(row["positions"])
    assert (0 if normals is None else len(normals)) == int(row["normals"])
    assert len(tri_positions) == int(row["triangles"])
    assert (tri_normals is None) == (normals is None)
    assert tri_positions.min() >= 0 and tri_positions.max() < len(positions)


def test_obj_corpus_lists_every_file():
    listed = {row["file"] for row in VALID_FILES}
    assert listed == {path.name for path in OBJ_DIR.glob("*.obj")}
    listed_bad = {row["file"] for row in BAD_FILES}
    assert listed_bad == {path.name for path in BAD_OBJ_DIR.glob("*.obj")}


def test_obj_fan_triangulation():
    _, _, pentagon, _ = obj_io.read_obj(OBJ_DIR / "pentagon.obj")
    assert pentagon.tolist() == [[0, 1, 2], [0, 2, 3], [0, 3, 4]]
    _, _, quad, _ = obj_io.read_obj(OBJ_DIR / "quad_vt.obj")
    assert quad.tolist() == [[0, 1, 2], [0, 2, 3]]


def test_obj_negative_indices_match_positive_ones():
    positions, normals, tri_positions, tri_normals = obj_io.read_obj(
        OBJ_DIR / "negative_idx.obj")
    assert tri_positions.tolist() == [[0, 1, 2], [0, 2, 3]]
    assert tri_normals.tolist() == [[0, 0, 0], [0, 0, 0]]
    crlf = obj_io.read_obj(OBJ_DIR / "crlf.obj")  # the same square with positive indices
    assert np.array_equal(positions, crlf[0]) and np.array_equal(normals, crlf[1])
    assert np.array_equal(tri_positions, crlf[2]) and np.array_equal(tri_normals, crlf[3])


def test_obj_crlf_and_comments_match_plain_files():
    crlf_bytes = (OBJ_DIR / "crlf.obj").read_bytes()
    assert crlf_bytes.count(b"\r\n") == crlf_bytes.count(b"\n") > 0
    comments = obj_io.read_obj(OBJ_DIR / "comments.obj")
    crlf = obj_io.read_obj(OBJ_DIR / "crlf.obj")
    assert np.array_equal(comments[0], crlf[0]) and np.array_equal(comments[2], crlf[2])


@pytest.mark.parametrize("name", ["no_normals.obj", "cube_normals.obj"])
def test_obj_cubes_are_closed_and_wound_outward(name):
    positions, normals, triangles, tri_normals = obj_io.read_obj(OBJ_DIR / name)
    edges = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]],
                            triangles[:, [2, 0]]])
    # Closed and consistently wound: every directed edge appears once, reversed once.
    assert len({tuple(edge) for edge in edges}) == 36
    assert {tuple(edge) for edge in edges} == {tuple(edge[::-1]) for edge in edges}
    a, b, c = (positions[triangles[:, k]] for k in range(3))
    face_normals = np.cross(b - a, c - a)
    centre_to_face = (a + b + c) / 3 - 0.5
    assert np.all(np.sum(face_normals * centre_to_face, axis=1) > 0)
    if normals is not None:
        assert np.allclose(normals[tri_normals[:, 0]], face_normals, atol=1e-12)


@pytest.mark.parametrize("row", BAD_FILES, ids=[row["file"] for row in BAD_FILES])
def test_obj_bad_file_is_rejected_at_the_listed_line(row):
    path = BAD_OBJ_DIR / row["file"]
    with pytest.raises(obj_io.ObjError) as error:
        obj_io.read_obj(path)
    message = str(error.value)
    assert message.startswith(f"{path}:{row['line']}: ")
    assert row["substring"] in message.lower()


def test_obj_bad_readme_matches_expected_tsv():
    readme = (BAD_OBJ_DIR / "README.md").read_text()
    for row in BAD_FILES:
        assert f"| `{row['file']}` | {row['line']} | `{row['substring']}` |" in readme


def test_binary_garbage_is_deterministic():
    data = (BAD_OBJ_DIR / "binary_garbage.obj").read_bytes()
    assert len(data) == 512 and data[0] == 0
