"""Chapter 21: a tree priced as it runs (book/docs/maintainers.md).

The chapter walks the tree node after node until every lane is at a leaf, keeps its
stack packed, and builds the tree with its leaves priced as the four tests the walk runs
rather than by the triangles they hold. None of it changes what a ray hits, so:

- The new walk draws chapter 20's picture (its tree priced by count, walked chapter
  18's way), on the teapot and on a textured mesh behind a lens, with either tree,
  within float rounding (path_checks.assert_same_picture).
- The comparison catches a wrong walk: a planted mistake in taking the next child off
  the stack (the ray's entry compared the wrong way) fails it.
- The leaves priced as written out: fewer nodes than chapter 20's tree (which pricing by
  count gives again, node for node), at most four triangles a leaf, the same picture.
  Each tree's shape is checked in C++ too (tests/cpp/test_bvh_priced.cpp).

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import page_claims
import path_checks
import pytest
from path_checks import path_trace

SMALL = ["--width", "48", "--height", "48", "--spp", "8"]
TREES = {"priced": [], "by_count": ["--bvh-leaves-by-count"]}


@pytest.mark.windows
@pytest.mark.parametrize("scene", ["cornell_teapot", "lens_textures"])
def test_the_walk_draws_chapter_20s_picture(tmp_path, scene):
    reference = path_trace("20", tmp_path, "chapter20", "--scene", scene, *SMALL)
    for tree, options in TREES.items():
        image = path_trace("21", tmp_path, tree, "--scene", scene, *SMALL, *options)
        path_checks.assert_same_picture(image, reference, f"{scene}, leaves {tree}")


def test_a_wrong_pop_is_caught(tmp_path):
    # A child put aside is taken up when the ray enters it *after* the nearest hit so
    # far: the near ones are skipped, and rays pass through the teapot.
    shaders = path_checks.shaders_with_bug(
        "21", tmp_path / "shaders",
        ("bvh_traversal.glsl", "haveCurrent = stackEnter[stackSize] < t;",
         "haveCurrent = stackEnter[stackSize] >= t;"))
    options = ["--scene", "cornell_teapot", *SMALL]
    reference = path_trace("21", tmp_path, "right", *options)
    wrong = path_trace("21", tmp_path, "wrong", *options, "--shader-dir", shaders)
    with pytest.raises(AssertionError):
        path_checks.assert_same_picture(wrong, reference, "the planted mistake")


def stats(tmp_path, *args, chapter="21") -> dict:
    return path_checks.render_stats(chapter, tmp_path, "--width", "16", "--height", "16",
                                    "--spp", "1", *args)


def test_leaves_priced_as_written_out_make_fewer_nodes(tmp_path):
    # A leaf costs its four written-out tests whatever it holds (bvh.h): priced so, a
    # range of up to four triangles stays one leaf. Priced by count it is chapter 20's
    # tree, node for node.
    teapot = ["--scene", "cornell_teapot"]
    written_out, by_count = stats(tmp_path, *teapot), stats(
        tmp_path, *teapot, "--bvh-leaves-by-count")
    chapter_20 = stats(tmp_path, *teapot, chapter="20")
    assert by_count["bvh_nodes"] == chapter_20["bvh_nodes"]
    assert written_out["bvh_nodes"] < 0.7 * by_count["bvh_nodes"]
    assert 6320 / written_out["bvh_leaves"] > 3.0  # triangles a leaf, at most 4
    for name, figures in (("by-count", by_count), ("priced", written_out)):
        page_claims.record(f"21-teapot-nodes-{name}", f"{figures['bvh_nodes']:,}".replace(",", " "))
        page_claims.record(f"21-teapot-depth-{name}", str(figures["bvh_max_depth"]))
