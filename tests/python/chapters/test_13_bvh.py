"""Chapters 13 and 14: the bounding volume hierarchy, median split (13) and SAH (14).
The tree must change nothing but the speed: camera rays' hits are compared with a numpy
ray caster (every pixel of a teapot in the room, and a sample of a million-triangle
teapot, which brute force cannot draw where the GL limits loops: Mesa 22's llvmpipe),
whole paths with chapter 12 (a different program that tests every shape) pixel for
pixel, and the smooth teapot with Mitsuba 3. Both chapters where both apply; 14's own
checks (brute force in the same program, bounce rays, the tree's statistics, the SAH's
saving) are in test_14_bvh_sah.py. The builder's invariants are ctest's
(tests/cpp/test_bvh*.cpp); speed is ./course bench's."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from conftest import ROOT, read_pfm, run_chapter

from python_prototypes import camera_rays
from python_prototypes import obj_io
import path_checks
from python_prototypes import scene_io
from python_prototypes import teapot

ROOM = (ROOT / "assets" / "scenes" / "cornell_room.scene").read_text()
SCENES = ROOT / "assets" / "scenes"


def room_with(tmp_path, mesh_line: str, name: str = "room.scene"):
    """The empty Cornell room plus one `mesh` line (paths as in any scene file)."""
    path = tmp_path / name
    path.write_text(ROOM + "\n" + mesh_line + "\n")
    return path


def render(tmp_path, prefix: str, name: str, *args) -> np.ndarray:
    """Renders to a PFM (linear, exact floats) and returns (height, width, 3); kept
    while its inputs are unchanged (path_checks.path_trace)."""
    return path_checks.path_trace(prefix, tmp_path, name, *args)


TEAPOT_552 = "mesh meshes/teapot_552.obj white scale 0.3 rotate_y 30 translate 0 -1 0"
TEAPOT_6320 = "mesh meshes/teapot_6320.obj white scale 0.28 rotate_y -30 translate 0 -1 0"


# The chapter these checks render with: 13 here; test_14_bvh_sah.py imports the checks
# that take `chapter` and runs them on chapter 14 with a fixture of its own, so that
# each chapter's checks live with it (and its starter needs no later chapter).
@pytest.fixture
def chapter() -> str:
    return "13"


# --- The tree finds what every triangle finds ------------------------------------------

def numpy_distances(scene_path, size, mesh_positions=None):
    """--view distance as numpy sees it: for each pixel's centre ray, the nearest of the
    scene's mesh triangles and room quads (inf for none), float64 Moller-Trumbore
    against every triangle. mesh_positions: the first mesh's own positions (default:
    its OBJ file's)."""
    scene = scene_io.load_scene(scene_path, [ROOT / "build" / "assets"])
    mesh = scene.meshes[0]
    positions, _, triangles, _ = obj_io.read_obj(mesh.path)
    if mesh_positions is not None:
        positions = mesh_positions
    world = mesh.world_from_mesh()
    corners = (positions @ world[:3, :3].T + world[:3, 3])[triangles]
    camera = scene.camera
    directions = camera_rays.camera_ray_directions(size, size, camera.eye, camera.look,
                                                   camera.up, camera.focal_length,
                                                   camera.sensor_width).reshape(-1, 3)
    origin = np.array(camera.eye, dtype=np.float64)
    teapot = numpy_first_hits(origin, directions, corners)
    nearest = np.minimum(teapot, numpy_room_hits(origin, directions, scene))
    return nearest.reshape(size, size), (teapot < np.inf).reshape(size, size)


def distance_disagreements(found, expected):
    """Pixels whose distance is not numpy's (relative 1e-4; a miss is 0 in the PFM)."""
    expected = np.where(np.isfinite(expected), expected, 0.0)
    return np.abs(found - expected) > 1e-4 * np.maximum(expected, 1.0)


@pytest.mark.windows
@pytest.mark.parametrize("mesh", [TEAPOT_552, TEAPOT_6320], ids=["552", "6320"])
def test_camera_rays_find_what_numpy_finds(tmp_path, chapter, mesh):
    scene = room_with(tmp_path, mesh)
    size = 48
    found = render(tmp_path, chapter, "tree", "--scene", scene, "--width", size, "--height",
                   size, "--spp", 1, "--view", "distance")[..., 0]
    expected, on_teapot = numpy_distances(scene, size)
    assert on_teapot.mean() > 0.05  # the teapot covers a good part of the picture
    wrong = distance_disagreements(found, expected)
    # float32 against float64: a ray through a crack between two facets may find the
    # next surface in one and not the other; allow two pixels for that.
    assert wrong.sum() <= 2, np.argwhere(wrong)[:10]


# The watchdog's limit on one step when COURSE_GPU_TIMEOUT_SECONDS is not set.
DEFAULT_GPU_STEP_SECONDS = float(re.search(
    r"kDefaultGpuStepSeconds = ([0-9.]+);",
    (ROOT / "common" / "course" / "gpu_watchdog.h").read_text())[1])


# Plausible traversal bugs of chapter 13, each planted in a copy of its shaders: the
# comparison with numpy above must catch them (a check that cannot fail is not a check).
PLANTED_BUGS = {
    "fourth triangle of a leaf skipped": (
        "if (count > 3u) bvhTestTriangle(", "if (count > 4u) bvhTestTriangle("),
    "right child dropped instead of put aside": (
        "if (enterRight < t && stackSize < BVH_STACK_SIZE)",
        "if (enterRight < 0.0 && stackSize < BVH_STACK_SIZE)"),
    "put-aside child taken from the bottom of the stack": (
        "current = stack[--stackSize];", "current = stack[0]; --stackSize;"),
}


@pytest.mark.parametrize("bug", PLANTED_BUGS)
def test_the_comparison_catches_a_planted_traversal_bug(tmp_path, bug):
    """A bug either draws wrong distances or never ends. The stack bug loops forever:
    a GL with a loop limit (Mesa 22's llvmpipe) cuts it short and the picture is wrong;
    any other (Mesa 25's, a GPU) runs it until the course's watchdog ends the program
    with exit code 4, saying why and after how long: its default limit (the program's
    own clock, not the test's: a busy machine only starts the step later)."""
    original, planted = PLANTED_BUGS[bug]
    shaders = path_checks.shaders_with_bug("13", tmp_path,
                                           ("bvh_traversal.glsl", original, planted))
    scene = room_with(tmp_path, TEAPOT_6320)
    size = 48
    out = tmp_path / "buggy.pfm"
    result = run_chapter("13", "--headless", "--out", out, "--scene", scene, "--width",
                         size, "--height", size, "--spp", 1, "--view", "distance",
                         "--shader-dir", shaders, env={"COURSE_GPU_TIMEOUT_SECONDS": ""})
    if result.returncode == 4 and "finished no step of the render" in result.stderr:
        assert f"for {DEFAULT_GPU_STEP_SECONDS:.0f} s" in result.stderr, result.stderr
        assert not out.exists()
        return
    assert result.returncode == 0, result.stderr
    buggy = read_pfm(out)[..., 0]
    expected, _ = numpy_distances(scene, size)
    assert distance_disagreements(buggy, expected).sum() > 2, bug


@pytest.mark.parametrize("scene, args", [
    ("cornell_gems.scene", ["--spp", 4]),                  # 220 gem facets, full paths
    ("cornell_box.scene", ["--spp", 4]),                   # quads only: an empty tree
    ("cornell_teapot.scene", ["--spp", 2, "--direct"]),    # 6 320 facets, direct light
], ids=["gems", "box", "teapot_direct"])
def test_same_picture_as_chapter_12(tmp_path, chapter, scene, args):
    # Chapter 12 is a different program: it tests every shape, triangles in file order.
    # The tree reorders the triangles (and the emitters that point at them), and must
    # still give every path the same hits and the same light.
    common = ["--scene", SCENES / scene, "--width", 40, "--height", 40, *args]
    ours = render(tmp_path, chapter, "tree", *common)
    theirs = render(tmp_path, "12", "eleven_nee", *common)
    assert np.array_equal(ours, theirs), np.abs(ours - theirs).max()


# --- A million triangles -----------------------------------------------------------------

def numpy_first_hits(origin, directions, corners):
    """Distance to the nearest triangle along each ray (inf for none), Moller-Trumbore
    in float64 against every triangle: (rays,) from origin (3,), directions (rays, 3),
    corners (triangles, 3, 3)."""
    return numpy_nearest_triangles(origin, directions, corners)[1]


def numpy_room_hits(origin, directions, scene):
    """Distance to the nearest of the scene's quads along each ray (inf for none)."""
    nearest = np.full(len(directions), np.inf)
    for quad in scene.quads:
        o, e, f = (np.array(v, dtype=np.float64) for v in (quad.origin, quad.edge1,
                                                            quad.edge2))
        normal = np.cross(e, f)
        facing = directions @ normal
        with np.errstate(divide="ignore", invalid="ignore"):
            t = ((o - origin) @ normal) / facing
        point = origin + t[:, None] * directions - o
        w = normal / normal.dot(normal)
        a = np.cross(point, f) @ w
        b = np.cross(e, point) @ w
        inside = (t > 0) & (a >= 0) & (a <= 1) & (b >= 0) & (b <= 1)
        nearest = np.where(inside & (t < nearest), t, nearest)
    return nearest


def test_a_million_triangles_against_a_numpy_ray_caster(tmp_path, chapter):
    # The teapot at 126 x 126 cells per patch: 1 015 056 triangles, written by the same
    # tessellator that chapter 14's benchmark uses; numpy keeps its own copy of them.
    segments = 126
    patches, control_points = teapot.load_patches()
    positions, _, triangles = teapot.tessellate(patches, control_points, segments)
    assert len(triangles) == 1015056
    mesh_path = tmp_path / "teapot_1m.obj"
    teapot.write_obj(mesh_path, positions, None, triangles)
    scene_path = room_with(tmp_path, f"mesh {mesh_path} white scale 0.28 rotate_y -30 "
                                     "translate 0 -1 0")

    size = 48
    result = run_chapter(chapter, "--headless", "--scene", scene_path, "--width", size,
                         "--height", size, "--spp", 1, "--view", "distance", "--out",
                         tmp_path / "distance.pfm", "--json")
    assert result.returncode == 0, result.stderr
    stats = json.loads(result.stdout.strip().splitlines()[-1])
    assert stats["triangles"] == 1015056
    assert stats.get("bvh_max_depth", 0) <= 64  # 14 reports its depth
    gpu = read_pfm(tmp_path / "distance.pfm")[..., 0]

    # numpy: the scene as scene_io reads it, the teapot's corners placed in the world
    # (as written in the OBJ file: six decimals), the camera rays of camera_rays.py.
    scene = scene_io.load_scene(scene_path)
    world = scene.meshes[0].world_from_mesh()
    placed = np.round(positions, 6) @ world[:3, :3].T + world[:3, 3]
    corners = placed[triangles]
    camera = scene.camera
    directions = camera_rays.camera_ray_directions(size, size, camera.eye, camera.look,
                                                   camera.up, camera.focal_length,
                                                   camera.sensor_width)
    # A sample of pixels: every 4th pixel of the middle rows, where the teapot is.
    rows, cols = np.meshgrid(np.arange(20, 40, 2), np.arange(4, 44, 4), indexing="ij")
    rows, cols = rows.ravel(), cols.ravel()
    origin = np.array(camera.eye, dtype=np.float64)
    sample = directions[rows, cols]
    teapot_hits = numpy_first_hits(origin, sample, corners)
    expected = np.minimum(teapot_hits, numpy_room_hits(origin, sample, scene))
    on_teapot = teapot_hits < np.inf
    assert on_teapot.sum() >= 30, "the sample must see the teapot"
    found = gpu[rows, cols]
    agree = np.abs(found - expected) <= 1e-4 * expected
    # float32 against float64: a ray through a crack between two facets may find the
    # next surface in one and not the other; allow one pixel of the sample for that.
    assert (~agree).sum() <= 1, list(zip(rows[~agree], cols[~agree], found[~agree],
                                         expected[~agree]))


# --- Smooth normals against Mitsuba 3 -----------------------------------------------------

@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # one-pixel regions have no spread
def test_smooth_teapot_agrees_with_mitsuba(tmp_path):
    """The teapot's vertex normals, shaded as Mitsuba's `obj` shades them: each region of
    cornell_teapot (the walls, the light, the teapot) within 2% of Mitsuba 3's mean,
    and within 4.5 standard errors of the two renders' noise."""
    size = 48
    ours = render(tmp_path, "13", "teapot", "--width", size, "--height", size,
                  "--spp", 1024, "--depth", 6)
    compared = path_checks.assert_agrees_with_mitsuba(
        ours, 1024, SCENES / "cornell_teapot.scene", [ROOT / "build" / "assets"],
        most_relative=0.02)
    assert "teapot" in compared and len(compared) >= 5, compared


def numpy_nearest_triangles(origin, directions, corners):
    """For each ray (from origin (3,), directions (rays, 3)): the nearest of corners'
    triangles (triangles, 3, 3) by Moller-Trumbore in float64, as (its index, -1 for
    none; its distance, inf for none; its barycentric (u, v))."""
    p0 = corners[:, 0]
    edge1, edge2 = corners[:, 1] - p0, corners[:, 2] - p0
    to_origin = origin - p0
    q = np.cross(to_origin, edge1)
    found, distances, uvs = [], [], []
    for direction in directions:
        p = np.cross(direction, edge2)
        determinant = np.einsum("ij,ij->i", edge1, p)
        with np.errstate(divide="ignore", invalid="ignore"):
            inverse = 1.0 / determinant
            u = np.einsum("ij,ij->i", to_origin, p) * inverse
            v = (q @ direction) * inverse
            t = np.einsum("ij,ij->i", edge2, q) * inverse
        hit = (np.abs(determinant) > 1e-20) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
        if not hit.any():
            found.append(-1), distances.append(np.inf), uvs.append((0.0, 0.0))
            continue
        index = np.flatnonzero(hit)[np.argmin(t[hit])]
        found.append(index), distances.append(t[index]), uvs.append((u[index], v[index]))
    return np.array(found), np.array(distances), np.array(uvs)


def test_the_teapot_is_shaded_with_its_blended_normals(tmp_path, chapter):
    """--view normals against numpy: where a camera ray meets the 552-triangle teapot,
    the normal is its corners' normals (the file's, turned into the world) blended with
    the hit's barycentric weights, not the facet's own, which differs by degrees."""
    scene_path = room_with(tmp_path, TEAPOT_552)
    size = 48
    gpu = render(tmp_path, chapter, "normals", "--scene", scene_path, "--width", size,
                 "--height", size, "--spp", 1, "--view", "normals") * 2.0 - 1.0
    scene = scene_io.load_scene(scene_path, [ROOT / "build" / "assets"])
    mesh = scene.meshes[0]
    positions, normals, triangles, normal_triangles = obj_io.read_obj(mesh.path)
    world = mesh.world_from_mesh()
    corners = (positions @ world[:3, :3].T + world[:3, 3])[triangles]
    turned = normals @ world[:3, :3].T
    turned /= np.linalg.norm(turned, axis=1, keepdims=True)
    camera = scene.camera
    directions = camera_rays.camera_ray_directions(size, size, camera.eye, camera.look,
                                                   camera.up, camera.focal_length,
                                                   camera.sensor_width)
    rows, cols = np.meshgrid(np.arange(16, 40, 2), np.arange(8, 40, 2), indexing="ij")
    rows, cols = rows.ravel(), cols.ravel()
    hit, _, uv = numpy_nearest_triangles(np.array(camera.eye, dtype=np.float64),
                                         directions[rows, cols], corners)
    on = hit >= 0
    assert on.sum() >= 60, "the sample must see the teapot"
    u, v = uv[on, 0:1], uv[on, 1:2]
    n = turned[normal_triangles[hit[on]]]
    blended = (1 - u - v) * n[:, 0] + u * n[:, 1] + v * n[:, 2]
    blended /= np.linalg.norm(blended, axis=1, keepdims=True)
    c = corners[hit[on]]
    flat = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
    flat /= np.linalg.norm(flat, axis=1, keepdims=True)
    found = gpu[rows[on], cols[on]]
    smooth_error = np.linalg.norm(found - blended, axis=1)
    flat_error = np.linalg.norm(found - flat, axis=1)
    # float32 against float64, and a ray through a crack between facets: one pixel.
    assert (smooth_error > 2e-3).sum() <= 1, np.sort(smooth_error)[-5:]
    # The check can tell: the facets' own normals are far from what was drawn.
    assert np.median(flat_error) > 10 * 2e-3, np.median(flat_error)
