"""Chapter 14: the tree built with the surface area heuristic. Like chapter 13's, it must
change nothing but the speed: here the same program with --brute-force gives the same
floats for camera rays, random bounce rays and whole paths (chapter 13's checks against
numpy, chapter 12 and Mitsuba run on 14 too: test_13_bvh.py). And it must be the better
tree: fewer traversal steps per camera ray than chapter 13's median split, measured by
--view cost (deterministic: one ray through each pixel's centre), the figure the book
quotes. The builder's invariants are ctest's (tests/cpp/test_bvh*.cpp); speed is
./course bench's."""

from __future__ import annotations

import json

import numpy as np
import page_claims
import path_checks
import pytest

from conftest import ROOT, loop_limit, run_chapter
from test_13_bvh import SCENES, TEAPOT_552, TEAPOT_6320, render, room_with
# Chapter 13's checks against numpy, chapter 12 and the blended normals, run on chapter
# 14 (the `chapter` fixture below).
from test_13_bvh import (test_a_million_triangles_against_a_numpy_ray_caster,  # noqa: F401
                         test_camera_rays_find_what_numpy_finds,
                         test_same_picture_as_chapter_12,
                         test_the_teapot_is_shaded_with_its_blended_normals)

from course_tools.grading import grading_statistics  # decode_cost: the heat map back to steps


@pytest.fixture
def chapter() -> str:
    return "14"


# --- The tree finds what brute force finds ---------------------------------------------

@pytest.mark.windows
@pytest.mark.parametrize("mesh", [TEAPOT_552, TEAPOT_6320], ids=["552", "6320"])
@pytest.mark.parametrize("view", ["normals", "distance"])
def test_camera_rays_hit_the_same_triangles_as_brute_force(tmp_path, mesh, view):
    scene = room_with(tmp_path, mesh)
    common = ["--scene", scene, "--width", 64, "--height", 64, "--spp", 1, "--view", view]
    tree = render(tmp_path, "14", "tree", *common)
    brute = render(tmp_path, "14", "brute", *common, "--brute-force")
    # The teapot covers a good part of the picture (not an empty test) ...
    background = render(tmp_path, "14", "room", "--scene", SCENES / "cornell_room.scene",
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
    original, planted = PLANTED_BUGS[bug]
    shaders = path_checks.shaders_with_bug("14", tmp_path,
                                           ("bvh_traversal.glsl", original, planted))
    scene = room_with(tmp_path, TEAPOT_6320)
    common = ["--scene", scene, "--width", 64, "--height", 64, "--spp", 1, "--view",
              "distance"]
    buggy = render(tmp_path, "14", "buggy", *common, "--shader-dir", shaders)
    brute = render(tmp_path, "14", "brute", *common, "--brute-force")
    assert not np.array_equal(buggy, brute), bug


def test_random_bounce_rays_find_the_same_hits(tmp_path):
    # The same random directions (the generator's streams do not depend on the tree),
    # so the same hits give the same ambient occlusion to the last bit.
    scene = room_with(tmp_path, TEAPOT_552)
    common = ["--scene", scene, "--width", 48, "--height", 48, "--spp", 6, "--view",
              "bounce"]
    tree = render(tmp_path, "14", "tree", *common)
    brute = render(tmp_path, "14", "brute", *common, "--brute-force")
    assert 0.2 < tree.mean() < 0.95  # some rays blocked, some open
    assert np.array_equal(tree, brute)


def test_paths_are_the_same_as_brute_force(tmp_path):
    scene = room_with(tmp_path, TEAPOT_552)
    common = ["--scene", scene, "--width", 32, "--height", 32, "--spp", 4, "--depth", 6]
    tree = render(tmp_path, "14", "tree", *common)
    brute = render(tmp_path, "14", "brute", *common, "--brute-force")
    assert np.array_equal(tree, brute)



# --- What it reports, and what it refuses ----------------------------------------------

def test_json_and_verbose_describe_the_tree():
    result = run_chapter("14", "--headless", "--width", 16, "--height", 16, "--spp", 1,
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
    tree = render(tmp_path, "14", "tree", *common)  # the tree renders it anyway
    limit = loop_limit("14")
    if limit is None:
        assert np.array_equal(render(tmp_path, "14", "brute", *common, "--brute-force"), tree)
        return
    result = run_chapter("14", "--headless", *map(str, common), "--out", "teapot.png",
                         "--brute-force")
    assert result.returncode == 4, result.stderr
    for words in ("cornell_teapot.scene", f"after {limit} (measured)", "Without --brute-force"):
        assert words in result.stderr
    assert not (tmp_path / "teapot.png").exists()




# --- What the SAH buys ------------------------------------------------------------------

def steps_per_ray(tmp_path, chapter: str, *args) -> float:
    """Mean traversal steps of the camera rays that enter the tree (--view cost)."""
    cost = render(tmp_path, chapter, f"cost{chapter}", "--width", 64, "--height", 64,
                  "--spp", 1, "--view", "cost", *args)
    steps, off_map = grading_statistics.decode_cost(cost)
    assert off_map < 1e-3
    working = steps > steps.min() + 0.5
    return float(steps[working].mean())


@pytest.mark.parametrize("scene", ["cornell_teapot.scene", "cornell_gems.scene",
                                   "cornell_teapot_million.scene"])
def test_the_sah_tree_takes_fewer_steps_than_the_median_split(tmp_path, scene):
    # The book's claim (chapters/14_bvh_sah.md): on the teapot about 40% fewer steps per
    # camera ray than chapter 13's tree. Deterministic, so the bound can be tight-ish.
    median = steps_per_ray(tmp_path, "13", "--scene", SCENES / scene)
    sah = steps_per_ray(tmp_path, "14", "--scene", SCENES / scene)
    name = scene.removesuffix(".scene")  # the page's table, from these figures
    page_claims.record(f"14-steps-median-{name}", f"{median:.1f}")
    page_claims.record(f"14-steps-sah-{name}", f"{sah:.1f}")
    page_claims.record(f"14-steps-saved-{name}", f"{1 - sah / median:.0%}")
    assert sah < 0.8 * median, (sah, median)
