"""The numpy reference for chapters 07 and 08 (python_prototypes/reference/mesh_scene.py)
against values worked out by hand: the framing formula, Lambert-lit faces, the floor in a
cube's shadow (ambient only), the sky, the side a ray sees; then flat against smooth
shading. Needs no build (the teapot comes from the committed patch file)."""

import math
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]
from python_prototypes import camera_rays
from python_prototypes import obj_io
from python_prototypes import teapot
from python_prototypes.reference import mesh_scene

OBJ = ROOT / "tests" / "data" / "obj"
WIDTH, HEIGHT = 160, 120
MESH_ALBEDO = np.array([0.9, 0.55, 0.25])
FLOOR_ALBEDO = np.array([0.7, 0.7, 0.7])


def load(name):
    return obj_io.read_obj(OBJ / name)  # positions, normals, triangles, normal triangles


def trace(name, smooth=False):
    positions, normals, triangles, normal_triangles = load(name)
    return mesh_scene.trace_mesh(positions, triangles, normals, normal_triangles, WIDTH,
                                 HEIGHT, smooth)


def scene_of(name):
    """(framing, ray directions (HEIGHT, WIDTH, 3)) of the picture of a corpus file."""
    framing = mesh_scene.frame_camera(load(name)[0], WIDTH, HEIGHT)
    directions = camera_rays.camera_ray_directions(WIDTH, HEIGHT, framing.eye, framing.look,
                                                   (0, 1, 0), 0.035, 0.036)
    return framing, directions


def pixel_showing(point, framing):
    """(row, column) of the pixel whose square contains the image of a world point."""
    forward, right, true_up = camera_rays.camera_basis(framing.look, (0, 1, 0))
    offset = np.asarray(point, dtype=np.float64) - framing.eye
    depth = offset @ forward
    across = 0.035 * (offset @ right) / depth / 0.036                 # in sensor widths
    up = 0.035 * (offset @ true_up) / depth / (0.036 * HEIGHT / WIDTH)  # sensor heights
    return int(math.floor((0.5 - up) * HEIGHT)), int(math.floor((across + 0.5) * WIDTH))


def hit_plane(origin, direction, axis, value):
    """Where the ray meets the plane {x[axis] = value}."""
    t = (value - origin[axis]) / direction[axis]
    assert t > 0
    return origin + t * direction


def segment_crosses_unit_cube(start, end):
    """Slab test: does the open segment from start to end pass through [0, 1]^3?"""
    start, end = np.asarray(start, dtype=np.float64), np.asarray(end, dtype=np.float64)
    enter, leave = 1e-9, 1.0 - 1e-9
    for axis in range(3):
        step = end[axis] - start[axis]
        if abs(step) < 1e-15:
            if not 0.0 <= start[axis] <= 1.0:
                return False
            continue
        near, far = sorted(((0.0 - start[axis]) / step, (1.0 - start[axis]) / step))
        enter, leave = max(enter, near), min(leave, far)
    return enter < leave


def lambert(albedo, normal, point, framing, geometric_normal=None):
    """The colour of a lit point: the shadow ray starts off the surface along the
    geometric normal (the shading normal unless given), and Lambert uses its direction."""
    geometric = normal if geometric_normal is None else np.asarray(geometric_normal, float)
    start = point + geometric * 1e-4 * (1.0 + framing.radius)
    to_light = framing.light_position - start
    cosine = max(0.0, float(np.dot(normal, to_light / np.linalg.norm(to_light))))
    return albedo * (0.1 + 0.9 * cosine)


# ---------------------------------------------------------------------------------------
# Framing, light, floor
# ---------------------------------------------------------------------------------------

def test_frame_camera_follows_the_formula():
    framing = mesh_scene.frame_camera(load("cube_normals.obj")[0], WIDTH, HEIGHT)
    radius = math.sqrt(3.0) / 2.0  # half the unit cube's diagonal
    look = np.array([0.0, -0.35, -1.0]) / math.hypot(0.35, 1.0)
    half_fov = math.atan(0.027 / 2 / 0.035)  # 4:3, so the sensor's height decides
    distance = radius / math.sin(half_fov)  # the bounding sphere just fits
    assert np.allclose(framing.look, look)
    assert np.allclose(framing.eye, np.array([0.5, 0.5, 0.5]) - look * distance)
    assert np.allclose(framing.light_position, [0.5 + 2 * radius, 0.5 + 4 * radius,
                                                0.5 + 3 * radius])
    assert framing.floor_y == 0.0
    # A tall picture is framed by its width instead.
    tall = mesh_scene.frame_camera(load("cube_normals.obj")[0], 100, 200)
    tall_distance = radius / math.sin(math.atan(0.036 / 2 / 0.035))
    assert np.isclose(np.linalg.norm(tall.eye - [0.5, 0.5, 0.5]), tall_distance)


def test_floor_is_two_triangles_under_the_mesh():
    framing = mesh_scene.frame_camera(load("cube_normals.obj")[0], WIDTH, HEIGHT)
    floor = mesh_scene.floor_triangles(framing)
    half = 20 * math.sqrt(3.0) / 2.0
    x0, x1, z0, z1 = 0.5 - half, 0.5 + half, 0.5 - half, 0.5 + half
    assert np.allclose(floor, [[(x0, 0, z0), (x1, 0, z0), (x1, 0, z1)],
                               [(x0, 0, z0), (x1, 0, z1), (x0, 0, z1)]])


# ---------------------------------------------------------------------------------------
# Pixels worked out by hand
# ---------------------------------------------------------------------------------------

# Smooth shading keeps these faces flat: a lone triangle's vertex normals are its face
# normal, and cube_normals.obj has one normal per face. no_normals.obj's smooth normals
# are averaged at the corners, so only its flat shading is worked out here.
@pytest.mark.parametrize("name, target, axis, normal, modes", [
    ("tri_v.obj", (1 / 3, 1 / 3, 0.0), 2, (0, 0, 1), (False, True)),  # facing us
    ("cube_normals.obj", (0.5, 0.5, 1.0), 2, (0, 0, 1), (False, True)),  # the front
    ("cube_normals.obj", (0.5, 1.0, 0.5), 1, (0, 1, 0), (False, True)),  # the top
    ("no_normals.obj", (0.7, 0.3, 1.0), 2, (0, 0, 1), (False,)),
])
def test_a_face_toward_the_light_has_the_lambert_value(name, target, axis, normal, modes):
    framing, directions = scene_of(name)
    row, column = pixel_showing(target, framing)
    point = hit_plane(framing.eye, directions[row, column], axis, target[axis])
    assert np.allclose(point, target, atol=0.05), "the pixel must show the face"
    expected = lambert(MESH_ALBEDO, np.array(normal, dtype=float), point, framing)
    for smooth in modes:
        image = trace(name, smooth).image
        assert np.allclose(image[row, column], expected, atol=1e-9), (smooth, row, column)


def test_smooth_normals_are_interpolated_with_barycentrics():
    # One triangle with its legs along x and y, so a point's barycentrics are
    # u = x (for p1) and v = y (for p2); each corner has its own normal.
    positions = np.array([(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)])
    normals = np.array([(0.0, 0.0, 1.0), (1.0, 0.0, 1.0), (0.0, 1.0, 1.0)])
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    triangles = np.array([[0, 1, 2]])
    framing = mesh_scene.frame_camera(positions, WIDTH, HEIGHT)
    directions = camera_rays.camera_ray_directions(WIDTH, HEIGHT, framing.eye, framing.look,
                                                   (0, 1, 0), 0.035, 0.036)
    row, column = pixel_showing((0.6, 0.2, 0.0), framing)
    point = hit_plane(framing.eye, directions[row, column], 2, 0.0)
    u, v = point[0], point[1]
    normal = (1 - u - v) * normals[0] + u * normals[1] + v * normals[2]
    expected = lambert(MESH_ALBEDO, normal / np.linalg.norm(normal), point, framing,
                       geometric_normal=(0.0, 0.0, 1.0))
    image = mesh_scene.render_mesh(positions, triangles, normals, triangles, WIDTH, HEIGHT,
                                   smooth=True)
    assert np.allclose(image[row, column], expected, atol=1e-9)


def test_the_floor_in_the_cubes_shadow_is_ambient_only():
    framing, directions = scene_of("cube_normals.obj")
    light = framing.light_position
    # The shadow of a point in the middle of the cube's left face (which faces away from
    # the light) falls on the floor to the left of the cube, where the camera sees it.
    left_face = np.array([0.0, 0.5, 0.5])
    on_floor = light + (left_face - light) * light[1] / (light[1] - left_face[1])
    row, column = pixel_showing(on_floor, framing)
    point = hit_plane(framing.eye, directions[row, column], 1, 0.0)
    assert segment_crosses_unit_cube(point, light), "the cube is between it and the light"
    assert not segment_crosses_unit_cube(framing.eye, point), "and not in front of it"

    result = trace("cube_normals.obj")
    assert result.triangle[row, column] >= 12  # a floor triangle, after the cube's 12
    assert np.allclose(result.image[row, column], 0.07, atol=1e-12)  # 0.7 * ambient 0.1

    # To the right of the cube, the floor is lit: Lambert with N = (0, 1, 0).
    lit = np.array([1.3, 0.0, 1.1])
    row, column = pixel_showing(lit, framing)
    point = hit_plane(framing.eye, directions[row, column], 1, 0.0)
    assert not segment_crosses_unit_cube(point, light)
    expected = lambert(FLOOR_ALBEDO, np.array([0.0, 1.0, 0.0]), point, framing)
    assert np.allclose(result.image[row, column], expected, atol=1e-9)


def test_background_pixels_are_the_sky():
    framing, directions = scene_of("cube_normals.obj")
    result = trace("cube_normals.obj")
    sky = result.triangle < 0
    assert sky[0].all(), "the top row looks over the floor's far edge"
    direction = directions[0, 0]
    blend = 0.5 * (direction[1] + 1.0)
    expected = (1 - blend) * np.array([1.0, 1.0, 1.0]) + blend * np.array([0.5, 0.7, 1.0])
    assert np.allclose(result.image[0, 0], expected, atol=1e-12)
    assert np.allclose(result.image[sky], mesh_scene.sky(directions[sky]), atol=1e-12)


def test_triangles_are_two_sided():
    positions, _, triangles, _ = load("tri_v.obj")
    front = mesh_scene.render_mesh(positions, triangles, width=WIDTH, height=HEIGHT)
    back = mesh_scene.render_mesh(positions, triangles[:, ::-1], width=WIDTH, height=HEIGHT)
    assert np.array_equal(front, back)


def test_the_geometric_normal_decides_which_side_the_ray_sees():
    # tri_v.obj's triangle faces the camera; wound the other way, it shows its back.
    # Give its corners normals that face the camera anyway: the smooth normal alone
    # would call that the front, lit by the light in front. The flat triangle decides,
    # both normals turn, and the corner normals now point away from the light.
    positions, _, triangles, _ = load("tri_v.obj")
    back = triangles[:, ::-1]
    towards_camera = np.array([[0.0, 0.0, 1.0]])
    corner_normals = np.zeros_like(back)
    result = mesh_scene.trace_mesh(positions, back, towards_camera, corner_normals, WIDTH,
                                   HEIGHT, smooth=True)
    on_mesh = result.triangle == 0
    assert on_mesh.sum() > 100
    assert np.allclose(result.geometric_normal[on_mesh], [0, 0, 1])  # turned to the ray
    assert np.allclose(result.normal[on_mesh], [0, 0, -1])            # turned with it
    assert np.allclose(result.image[on_mesh], MESH_ALBEDO * 0.1)      # ambient only


def test_area_weighted_vertex_normals():
    positions, _, triangles, _ = load("no_normals.obj")
    normals = mesh_scene.vertex_normals(positions, triangles)
    # Vertex 1 (0, 0, 0) is in two triangles of each of the faces -x, -y and -z.
    assert np.allclose(normals[0], np.array([-1, -1, -1]) / math.sqrt(3))
    # Vertex 2 (1, 0, 0): two triangles of +x, but only one each of -y and -z.
    assert np.allclose(normals[1], np.array([2, -1, -1]) / math.sqrt(6))
    # A vertex in no triangle has no normal: (0, 0, 0), as in the chapter's C++.
    lonely = mesh_scene.vertex_normals(np.vstack([positions, [5.0, 5.0, 5.0]]), triangles)
    assert np.array_equal(lonely[-1], [0.0, 0.0, 0.0])


# ---------------------------------------------------------------------------------------
# Flat against smooth
# ---------------------------------------------------------------------------------------

def test_smooth_equals_flat_on_a_cube_with_face_normals():
    assert np.allclose(trace("cube_normals.obj", smooth=True).image,
                       trace("cube_normals.obj").image, atol=1e-12)


@pytest.fixture(scope="module")
def low_poly_teapot():
    if not teapot.DEFAULT_PATCH_FILE.exists():
        pytest.skip(f"no teapot patch file at {teapot.DEFAULT_PATCH_FILE}")
    patches, control_points = teapot.load_patches()
    positions, normals, triangles = teapot.tessellate(patches, control_points, segments=3)
    flat = mesh_scene.trace_mesh(positions, triangles, normals, triangles, WIDTH, HEIGHT)
    smooth = mesh_scene.trace_mesh(positions, triangles, normals, triangles, WIDTH, HEIGHT,
                                   smooth=True)
    return len(triangles), flat, smooth


def test_smooth_differs_from_flat_on_the_low_poly_teapot(low_poly_teapot):
    triangle_count, flat, smooth = low_poly_teapot
    assert triangle_count == 552
    assert np.array_equal(flat.triangle, smooth.triangle)  # same hits, other normals
    on_mesh = (flat.triangle >= 0) & (flat.triangle < triangle_count)
    difference = np.abs(flat.image - smooth.image).max(axis=-1)
    assert np.all(difference[~on_mesh] == 0.0)  # floor and sky are the same
    assert np.mean(difference[on_mesh] > 0.02) > 0.3  # facets show on many mesh pixels


def test_the_teapot_is_framed_lit_from_the_right_and_casts_a_shadow(low_poly_teapot):
    triangle_count, flat, _ = low_poly_teapot
    on_mesh = (flat.triangle >= 0) & (flat.triangle < triangle_count)
    assert on_mesh.sum() > 0.05 * WIDTH * HEIGHT
    assert not (on_mesh[0].any() or on_mesh[-1].any() or on_mesh[:, 0].any()
                or on_mesh[:, -1].any()), "the whole teapot is in the picture"
    rows, columns = np.nonzero(on_mesh)
    middle = np.median(columns)
    brightness = flat.image.sum(axis=-1)
    assert (brightness[rows[columns > middle], columns[columns > middle]].mean()
            > brightness[rows[columns < middle], columns[columns < middle]].mean())
    on_floor = flat.triangle >= triangle_count
    assert np.isclose(flat.image[on_floor], 0.07).all(axis=-1).sum() > 50  # the shadow
