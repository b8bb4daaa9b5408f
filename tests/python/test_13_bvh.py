"""Chapter 13: the bounding volume hierarchy. The tree must change nothing but the
speed: its images are compared with brute force (the same program with --brute-force,
and chapter 12, a different program that tests every shape) pixel for pixel, for camera
rays, random bounce rays and whole paths; a million-triangle teapot, which brute force
cannot draw where the GL limits loops (Mesa 22's llvmpipe), is compared with a numpy
ray caster on a sample of pixels. The builder's invariants are ctest's
(tests/cpp/test_bvh*.cpp); speed is ./course bench's."""

from __future__ import annotations

import json
import sys

import numpy as np
import pytest

from conftest import ROOT, copy_shaders, loop_limit, read_pfm, run_chapter

sys.path.insert(0, str(ROOT / "python_prototypes"))
import camera_rays  # noqa: E402
import obj_io  # noqa: E402
import path_checks  # noqa: E402
import scene_io  # noqa: E402
import teapot  # noqa: E402

ROOM = (ROOT / "assets" / "scenes" / "cornell_room.scene").read_text()
SCENES = ROOT / "assets" / "scenes"


def room_with(tmp_path, mesh_line: str, name: str = "room.scene"):
    """The empty Cornell room plus one `mesh` line (paths as in any scene file)."""
    path = tmp_path / name
    path.write_text(ROOM + "\n" + mesh_line + "\n")
    return path


def render(tmp_path, prefix: str, name: str, *args) -> np.ndarray:
    """Renders to a PFM (linear, exact floats) and returns (height, width, 3)."""
    out = tmp_path / f"{name}.pfm"
    result = run_chapter(prefix, "--headless", "--out", out, *map(str, args))
    assert result.returncode == 0, result.stderr
    return read_pfm(out)[..., :3]


TEAPOT_552 = "mesh meshes/teapot_552.obj white scale 0.3 rotate_y 30 translate 0 -1 0"
TEAPOT_6320 = "mesh meshes/teapot_6320.obj white scale 0.28 rotate_y -30 translate 0 -1 0"


# --- The tree finds what brute force finds ---------------------------------------------

@pytest.mark.parametrize("mesh", [TEAPOT_552, TEAPOT_6320], ids=["552", "6320"])
@pytest.mark.parametrize("view", ["normals", "distance"])
def test_camera_rays_hit_the_same_triangles_as_brute_force(tmp_path, mesh, view):
    scene = room_with(tmp_path, mesh)
    common = ["--scene", scene, "--width", 64, "--height", 64, "--spp", 1, "--view", view]
    tree = render(tmp_path, "13", "tree", *common)
    brute = render(tmp_path, "13", "brute", *common, "--brute-force")
    # The teapot covers a good part of the picture (not an empty test) ...
    background = render(tmp_path, "13", "room", "--scene", SCENES / "cornell_room.scene",
                        *common[2:])
    assert np.mean(np.any(tree != background, axis=-1)) > 0.05
    # ... and every pixel is the same float: the same triangle at the same distance.
    assert np.array_equal(tree, brute), np.argwhere(np.any(tree != brute, axis=-1))[:10]


# Plausible traversal bugs, each planted in a copy of the shaders: the comparison with
# brute force above must catch them (a check that cannot fail is not a check).
PLANTED_BUGS = {
    "fourth triangle of a leaf skipped": (
        "if (count > 3u) bvhTestTriangle(", "if (count > 4u) bvhTestTriangle("),
    "put-aside child pruned too eagerly": (
        "if (stackEnter[stackSize] >= t) continue;",
        "if (stackEnter[stackSize] >= 0.9 * t) continue;"),
    "far child dropped instead of put aside": (
        "if (enterFar < t && stackSize < BVH_STACK_SIZE) {",
        "if (enterFar < 0.0 && stackSize < BVH_STACK_SIZE) {"),
}


@pytest.mark.parametrize("bug", PLANTED_BUGS)
def test_the_comparison_catches_a_planted_traversal_bug(tmp_path, bug):
    shaders = copy_shaders("13", tmp_path / "shaders")
    traversal = shaders / "bvh_traversal.glsl"
    original, planted = PLANTED_BUGS[bug]
    text = traversal.read_text()
    assert original in text, bug
    traversal.write_text(text.replace(original, planted))
    scene = room_with(tmp_path, TEAPOT_6320)
    common = ["--scene", scene, "--width", 64, "--height", 64, "--spp", 1, "--view",
              "distance"]
    buggy = render(tmp_path, "13", "buggy", *common, "--shader-dir", shaders)
    brute = render(tmp_path, "13", "brute", *common, "--brute-force")
    assert not np.array_equal(buggy, brute), bug


def test_random_bounce_rays_find_the_same_hits(tmp_path):
    # The same random directions (the generator's streams do not depend on the tree),
    # so the same hits give the same ambient occlusion to the last bit.
    scene = room_with(tmp_path, TEAPOT_552)
    common = ["--scene", scene, "--width", 48, "--height", 48, "--spp", 6, "--view",
              "bounce"]
    tree = render(tmp_path, "13", "tree", *common)
    brute = render(tmp_path, "13", "brute", *common, "--brute-force")
    assert 0.2 < tree.mean() < 0.95  # some rays blocked, some open
    assert np.array_equal(tree, brute)


def test_paths_are_the_same_as_brute_force(tmp_path):
    scene = room_with(tmp_path, TEAPOT_552)
    common = ["--scene", scene, "--width", 32, "--height", 32, "--spp", 4, "--depth", 6]
    tree = render(tmp_path, "13", "tree", *common)
    brute = render(tmp_path, "13", "brute", *common, "--brute-force")
    assert np.array_equal(tree, brute)


@pytest.mark.parametrize("scene, args", [
    ("cornell_gems.scene", ["--spp", 4]),                  # 220 gem facets, full paths
    ("cornell_box.scene", ["--spp", 4]),                   # quads only: an empty tree
    ("cornell_teapot.scene", ["--spp", 2, "--direct"]),    # 6 320 facets, direct light
], ids=["gems", "box", "teapot_direct"])
def test_same_picture_as_chapter_12(tmp_path, scene, args):
    # Chapter 12 is a different program: it tests every shape, triangles in file order.
    # The tree reorders the triangles (and the emitters that point at them), and must
    # still give every path the same hits and the same light.
    common = ["--scene", SCENES / scene, "--width", 40, "--height", 40, *args]
    ours = render(tmp_path, "13", "tree", *common)
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


def test_a_million_triangles_against_a_numpy_ray_caster(tmp_path):
    # The teapot at 126 x 126 cells per patch: 1 015 056 triangles, written by the same
    # tessellator that chapter 13's benchmark uses; numpy keeps its own copy of them.
    segments = 126
    patches, control_points = teapot.load_patches()
    positions, _, triangles = teapot.tessellate(patches, control_points, segments)
    assert len(triangles) == 1015056
    mesh_path = tmp_path / "teapot_1m.obj"
    teapot.write_obj(mesh_path, positions, None, triangles)
    scene_path = room_with(tmp_path, f"mesh {mesh_path} white scale 0.28 rotate_y -30 "
                                     "translate 0 -1 0")

    size = 48
    result = run_chapter("13", "--headless", "--scene", scene_path, "--width", size,
                         "--height", size, "--spp", 1, "--view", "distance", "--out",
                         tmp_path / "distance.pfm", "--json")
    assert result.returncode == 0, result.stderr
    stats = json.loads(result.stdout.strip().splitlines()[-1])
    assert stats["triangles"] == 1015056 and stats["bvh_max_depth"] <= 64
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


# --- What it reports, and what it refuses ----------------------------------------------

def test_json_and_verbose_describe_the_tree():
    result = run_chapter("13", "--headless", "--width", 16, "--height", 16, "--spp", 1,
                         "--out", "teapot.png", "--json", "--verbose")
    assert result.returncode == 0, result.stderr
    stats = json.loads(result.stdout.strip().splitlines()[-1])
    assert stats["triangles"] == 6320
    # Two children per node: a binary tree with n inner nodes has n + 1 leaves; each
    # leaf holds 1 to 4 triangles.
    assert stats["bvh_leaves"] == stats["bvh_nodes"] + 1
    assert 6320 / 4 <= stats["bvh_leaves"] <= 6320
    assert 11 <= stats["bvh_max_depth"] <= 64  # at least log2(6320 / 4)
    assert 0 < stats["bvh_sah_cost"] < 6320 / 10  # far below brute force's 6320
    assert stats["bvh_bytes"] >= 64 * stats["bvh_nodes"]
    assert stats["bvh_build_ms"] > 0
    assert "BVH: 6320 triangles ->" in result.stderr


def test_brute_force_is_refused_where_the_loop_limit_would_cut_it_short(tmp_path):
    # The teapot scene at --depth 6, testing every facet: about 88 000 loop iterations.
    # Where the GL ends loops sooner (as the chapter measures: Mesa 22's llvmpipe),
    # brute force is refused; where it has no limit, it draws the tree's picture.
    common = ["--width", 16, "--height", 16, "--spp", 1]
    tree = render(tmp_path, "13", "tree", *common)  # the tree renders it anyway
    limit = loop_limit("13")
    if limit is None:
        assert np.array_equal(render(tmp_path, "13", "brute", *common, "--brute-force"), tree)
        return
    result = run_chapter("13", "--headless", *map(str, common), "--out", "teapot.png",
                         "--brute-force")
    assert result.returncode == 4, result.stderr
    for words in ("cornell_teapot.scene", f"after {limit} (measured)", "Without --brute-force"):
        assert words in result.stderr
    assert not (tmp_path / "teapot.png").exists()


def test_obj_stands_in_the_room(tmp_path):
    # --obj: the mesh on the floor of the empty room, in the middle, half as wide.
    common = ["--width", 48, "--height", 48, "--spp", 1, "--view", "distance"]
    mesh = ROOT / "build" / "assets" / "meshes" / "teapot_552.obj"
    with_mesh = render(tmp_path, "13", "obj", "--obj", mesh, *common)
    empty = render(tmp_path, "13", "room", "--scene", SCENES / "cornell_room.scene", *common)
    nearer = with_mesh[..., 0] < empty[..., 0] - 1e-4
    assert nearer.mean() > 0.02  # 1 m wide, 2.2 m inside a 3.9 m deep view
    rows, cols = np.nonzero(nearer)
    assert abs(cols.mean() - 23.5) < 4  # centred left to right
    assert rows.max() > 30              # down on the floor, in the lower half
    assert not np.any(with_mesh[..., 0] > empty[..., 0] + 1e-4)  # nothing behind walls


def test_obj_errors_name_the_file_and_line(tmp_path):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")
    result = run_chapter("13", "--headless", "--obj", bad, "--out", tmp_path / "x.png")
    assert result.returncode == 3
    assert f"{bad}:4" in result.stderr
    assert not (tmp_path / "x.png").exists()


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


def test_the_teapot_is_shaded_with_its_blended_normals(tmp_path):
    """--view normals against numpy: where a camera ray meets the 552-triangle teapot,
    the normal is its corners' normals (the file's, turned into the world) blended with
    the hit's barycentric weights, not the facet's own, which differs by degrees."""
    scene_path = room_with(tmp_path, TEAPOT_552)
    size = 48
    gpu = render(tmp_path, "13", "normals", "--scene", scene_path, "--width", size,
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
