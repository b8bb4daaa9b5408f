"""Chapter 31: a tree without a stack (book/docs/maintainers.md).

Chapter 30 walks the mesh's tree with a stack: at each node it tests both children's
boxes, goes on into the nearer and puts the farther aside. Chapter 31 lays the boxes out
in the order a ray of each octant of directions visits them, each box saying where to go
on if the ray misses it, and rounds each box outwards onto a grid of 16-bit steps. The
walk tests a box a turn and needs no stack. None of this changes which triangle a ray
finds nearest: the boxes only decide what is tested, and a box rounded outwards holds
everything the exact one did. So:

- Both kernels, the tree read from buffer textures and from storage buffers, draw
  chapter 30's picture within float rounding (path_checks.assert_same_picture), and so do random bounce rays, which run in
  all 8 octants. Chapter 30's pictures are checked against chapter 23's, and so on back
  to Mitsuba 3, closed forms and numpy prototypes.
- Meshes that test the grid: one flat along an axis (its grid's step there is not
  zero), and a cube whose faces lie on its boxes' planes, met by grazing rays.
- A planted mistake in the walk (a missed node skips one box too many) draws another
  picture, and the comparison says so: the checks above can fail.
- The teapot still takes 64 samples a dispatch, on a GL with a loop limit too; a planted
  long walk is cut, run again and draws the same picture (chapter 30's checks, here).

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import path_checks
import pytest
from conftest import loop_limit
from path_checks import path_trace

SMALL = ["--width", "48", "--height", "48", "--spp", "8"]
TEAPOT = ["--scene", "cornell_teapot"]
ONE_A_DISPATCH = ["--samples-per-dispatch", "1"]
WALK = "    return bvhTraverse(ray, tMin, tMax, false, triangle, t, uv);"
SKIP = "            next = enters || isLeaf ? next + 1u : box.next >> BVH_COUNT_BITS;"


@pytest.mark.windows
@pytest.mark.parametrize("scene", ["cornell_teapot", "lens_textures", "cornell_glass"])
def test_the_walk_draws_chapter_30s_picture(tmp_path, scene):
    reference = path_trace("30", tmp_path, "chapter30", "--scene", scene, *SMALL)
    stackless = path_trace("31", tmp_path, "stackless", "--scene", scene, *SMALL)
    path_checks.assert_same_picture(stackless, reference, f"{scene}, without a stack")


# (The generic shader reads the tree as the specialised one does: chapter 30 checks it.)
@pytest.mark.parametrize("options", [["--scene-memory", "storage", "--bvh-memory", "storage"],
                                     ["--kernel", "wavefront"]],
                         ids=["storage", "wavefront"])
def test_every_way_of_reading_draws_chapter_30s_picture(tmp_path, options):
    scene = [*TEAPOT, *SMALL, *options]
    reference = path_trace("30", tmp_path, "chapter30", *scene)
    stackless = path_trace("31", tmp_path, "stackless", *scene)
    path_checks.assert_same_picture(stackless, reference, f"the teapot, {options[-1]}")


def test_bounce_rays_of_every_octant_find_chapter_30s_hits(tmp_path):
    # One random diffuse ray a pixel from the camera ray's hit, 16 times: rays leave the
    # floor, the walls, the ceiling and the teapot in every direction.
    options = [*TEAPOT, "--width", "64", "--height", "64", "--spp", "16", "--view",
               "bounce"]
    reference = path_trace("30", tmp_path, "chapter30", *options)
    stackless = path_trace("31", tmp_path, "stackless", *options)
    path_checks.assert_same_picture(stackless, reference, "bounce rays")
    assert 0.2 < stackless.mean() < 0.9  # some rays blocked, most not


# A square on the floor and a cube standing on it, written as meshes: every triangle
# lies in a plane of its own box and of its neighbours', and the square is flat along y.
SQUARE = """v -0.9 -0.999 -0.9
v 0.9 -0.999 -0.9
v 0.9 -0.999 0.9
v -0.9 -0.999 0.9
f 1 3 2
f 1 4 3
"""
CUBE = "".join(f"v {x} {y} {z}\n" for x in (-0.3, 0.3) for y in (-1.0, -0.4)
               for z in (-0.3, 0.3)) + """f 1 2 4
f 1 4 3
f 5 7 8
f 5 8 6
f 1 5 6
f 1 6 2
f 3 4 8
f 3 8 7
f 1 3 7
f 1 7 5
f 2 6 8
f 2 8 4
"""
ROOM = """camera eye 0.4 0.2 3.9 look -0.1 -0.15 -1 up 0 1 0 focal 0.035 sensor 0.025
material white albedo 0.8 0.8 0.8
material red albedo 0.8 0.1 0.1
material lamp albedo 0.8 0.8 0.8 emission 12 12 12
quad -1 -1 1 2 0 0 0 0 -2 white
quad -1 1 -1 2 0 0 0 0 2 white
quad -1 -1 -1 2 0 0 0 2 0 white
quad -0.25 0.99 -0.25 0.5 0 0 0 0 0.5 lamp
"""


@pytest.mark.parametrize("meshes", [["square.obj"], ["cube.obj"],
                                    ["square.obj", "cube.obj"]],
                         ids=["flat", "cube", "both"])
def test_meshes_on_the_grids_planes_draw_chapter_30s_picture(tmp_path, meshes):
    (tmp_path / "square.obj").write_text(SQUARE)
    (tmp_path / "cube.obj").write_text(CUBE)
    scene = tmp_path / "planes.scene"
    scene.write_text(ROOM + "".join(f"mesh {m} red\n" for m in meshes))
    for view in ("distance", "radiance"):
        options = ["--scene", scene, "--width", "64", "--height", "64", "--spp", "4",
                   "--view", view]
        reference = path_trace("30", tmp_path, f"chapter30-{view}", *options)
        stackless = path_trace("31", tmp_path, f"stackless-{view}", *options)
        path_checks.assert_same_picture(stackless, reference, f"{meshes}, {view}")
        assert stackless.mean() > 0.01


def test_a_wrong_skip_is_caught(tmp_path):
    # A box the ray misses sends the walk one box past its subtree: the next box's
    # triangles are never tested, and some rays go through the teapot. (Never past the
    # order's end: a walk that ran past it would never end where the GL has no loop
    # limit, Mesa 25's llvmpipe, and the watchdog would stop it instead.)
    wrong = SKIP.replace("box.next >> BVH_COUNT_BITS",
                         "min((box.next >> BVH_COUNT_BITS) + 1u, end)")
    shaders = path_checks.shaders_with_bug("31", tmp_path / "skip", ("bvh_traversal.glsl",
                                                                     SKIP, wrong))
    options = [*TEAPOT, *SMALL, "--view", "distance"]
    reference = path_trace("30", tmp_path, "chapter30", *options)
    skipping = path_trace("31", tmp_path, "skipping", *options, "--shader-dir", shaders)
    with pytest.raises(AssertionError):
        path_checks.assert_same_picture(skipping, reference, "the planted mistake")


def test_the_teapot_takes_many_samples_a_dispatch(tmp_path):
    # 80 samples: a dispatch of 64, then one of the 16 left. A walk tests one box a turn
    # (chapter 30: a node, two boxes, a turn), and still fits Mesa 22's limit 64 samples
    # at a time.
    options = [*TEAPOT, "--width", "32", "--height", "32", "--spp", "80"]
    stats = path_checks.render_stats("31", tmp_path, *options)
    assert stats["samples_per_dispatch"] == 64 and stats["dispatches_redone"] == 0
    many = path_trace("31", tmp_path, "many", *options)
    one = path_trace("31", tmp_path, "one", *options, *ONE_A_DISPATCH)
    path_checks.assert_same_picture(many, one, "the teapot, 64 samples a dispatch")
    assert many.mean() > 0.01


def test_a_long_walk_is_cut_run_again_and_draws_the_same_picture(tmp_path):
    long_walk = ("    bool found = false;\n"
                 "    for (int walk = 0; walk < 20; ++walk)\n"
                 "        found = bvhTraverse(ray, tMin, tMax, false, triangle, t, uv);\n"
                 "    return found;")
    shaders = ["--shader-dir", path_checks.shaders_with_bug(
        "31", tmp_path / "walks", ("bvh_traversal.glsl", WALK, long_walk))]
    options = [*TEAPOT, "--width", "32", "--height", "32", "--spp", "64"]
    stats = path_checks.render_stats("31", tmp_path, *options, *shaders)
    if loop_limit("31") is None:  # measured: nothing to cut
        assert stats["samples_per_dispatch"] == 64 and stats["dispatches_redone"] == 0
    else:  # 64 samples of 20 walks a hit are past 65 535 iterations; fewer fit
        assert 1 < stats["samples_per_dispatch"] < 64 and stats["dispatches_redone"] >= 1
    checked = path_trace("31", tmp_path, "checked", *options, *shaders)
    one = path_trace("31", tmp_path, "one", *options, *shaders, *ONE_A_DISPATCH)
    path_checks.assert_same_picture(checked, one, "a long walk, checked dispatches")
    assert checked.mean() > 0.01
