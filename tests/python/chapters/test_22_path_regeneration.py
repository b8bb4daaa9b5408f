"""Chapter 22: path regeneration (book/docs/maintainers.md).

The chapter cuts chapter 21's path tracer into steps (path_steps.glsl) and runs them in
one kernel that takes up a pixel's next sample as soon as a path ends, several samples
a dispatch; it changes nothing of what is computed: the steps use the same random
numbers for each pixel, in the same order, and the sums are made in the order of one
sample a dispatch. So:

- The path in steps draws chapter 21's picture, within float rounding
  (path_checks.assert_same_picture), on scenes with every material kind, textures and a
  lens, a mesh through the tree, an environment and glass. Chapter 21's pictures are
  checked against chapter 18's, Mitsuba 3, closed forms and numpy prototypes.
- Path regeneration draws the picture of --samples-per-dispatch 1, on the Cornell box
  and on the showcase. A running mean that counts its samples wrong, and a pixel's next
  path that does not start from a camera ray, are caught by that comparison.
- How many samples a dispatch takes follows the loop limit: fewer for a scene of many
  spheres (each bounce loops over them), one for a mesh's tree on a GL that has a limit
  (measured).

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import path_checks
import pytest
from conftest import SMALLEST_KNOWN_LOOP_LIMIT, loop_limit
from path_checks import path_trace

SMALL = ["--width", "48", "--height", "48", "--spp", "8"]


# Every material kind, under the sky; a textured mesh through the tree and a lens; an
# environment with every estimator's share; glass.
@pytest.mark.windows
@pytest.mark.parametrize("scene", ["sky_showcase", "lens_textures", "sky_estimators",
                                   "cornell_glass"])
def test_the_path_in_steps_draws_chapter_21s_picture(tmp_path, scene):
    reference = path_trace("21", tmp_path, "chapter21", "--scene", scene, *SMALL)
    steps = path_trace("22", tmp_path, "steps", "--scene", scene, *SMALL)
    path_checks.assert_same_picture(steps, reference, f"{scene}, the path in steps")


def stats(tmp_path, *args) -> dict:
    return path_checks.render_stats("22", tmp_path, *args)


ONE_A_DISPATCH = ["--samples-per-dispatch", "1"]


@pytest.mark.parametrize("scene, most", [("cornell_box", 64), ("sky_showcase", 56)])
def test_regeneration_draws_the_picture_of_one_sample_a_dispatch(tmp_path, scene, most):
    # 80 samples: a dispatch of 64 (the Cornell box's 18 quads) or 56 (the showcase's 51
    # shapes, each bounce looping over them twice: 7 x 56 x (2 x 51 + 65) loop
    # iterations fit 65 535), then one of the samples left.
    options = ["--scene", scene, "--width", "48", "--height", "48", "--spp", "80"]
    assert stats(tmp_path, *options)["samples_per_dispatch"] == most
    regenerating = path_trace("22", tmp_path, "regenerating", *options)
    one = path_trace("22", tmp_path, "one", *options, *ONE_A_DISPATCH)
    path_checks.assert_same_picture(regenerating, one, f"{scene}, {most} samples a dispatch")
    assert regenerating.mean() > 0.01  # lit, not black


@pytest.mark.parametrize("bug", [
    ("path.comp", "mean += (path.radiance - mean) / float(sampleIndex + done);",
     "mean += (path.radiance - mean) / float(sampleIndex + 1u);"),
    ("path.comp", "        path = startPath(cameraRay(pixel, random));  // the next",
     "        path.radiance = vec3(0.0); path.bounce = 0;  // the next"),
], ids=["mean_counts_wrong", "path_not_restarted"])
def test_a_wrong_regeneration_is_caught(tmp_path, bug):
    shaders = path_checks.shaders_with_bug("22", tmp_path / "shaders", bug)
    options = ["--scene", "cornell_box", *SMALL]
    one = path_trace("22", tmp_path, "one", *options, *ONE_A_DISPATCH)
    wrong = path_trace("22", tmp_path, "wrong", *options, "--shader-dir", shaders)
    with pytest.raises(AssertionError):
        path_checks.assert_same_picture(wrong, one, "the planted mistake")


def test_many_spheres_take_fewer_samples_a_dispatch(tmp_path):
    # 300 spheres, each bounce's two loops over them: 64 samples of depth 6 would be
    # 7 x 64 x (600 + ...) loop iterations, past the limit every GL is known to allow.
    spheres = "".join(f"sphere {x * 0.3 - 2.85:.2f} {y * 0.3 - 0.4:.2f} -3 0.1 m\n"
                      for x in range(20) for y in range(15))
    scene = tmp_path / "many.scene"
    scene.write_text("camera eye 0 1 3 look 0 0 -3 up 0 1 0 focal 0.035 sensor 0.036\n"
                     "material m albedo 0.5 0.5 0.5\n"
                     "material glow albedo 0 0 0 emission 4 4 4\n"
                     "quad -3 3 -5 6 0 0 0 0 4 glow\n" + spheres)
    options = ["--scene", scene, "--width", "16", "--height", "16", "--spp", "20"]
    taken = stats(tmp_path, *options)["samples_per_dispatch"]
    assert 1 < taken < 64
    assert taken * 7 * 2 * 301 <= SMALLEST_KNOWN_LOOP_LIMIT
    regenerating = path_trace("22", tmp_path, "regenerating", *options)
    one = path_trace("22", tmp_path, "one", *options, *ONE_A_DISPATCH)
    path_checks.assert_same_picture(regenerating, one, f"{taken} samples a dispatch")
    assert regenerating.mean() > 0.001


def test_a_tree_regenerates_only_without_a_loop_limit(tmp_path):
    # A walk of the tree has no length known in advance: on a GL that ends loops (Mesa
    # 22's llvmpipe, measured) the teapot takes one sample a dispatch, else up to 64.
    options = ["--scene", "cornell_teapot", "--width", "24", "--height", "24", "--spp", "4"]
    expected = 1 if loop_limit("22") is not None else 4  # all 4 samples at once
    assert stats(tmp_path, *options)["samples_per_dispatch"] == expected
    # The views take one sample a dispatch, as do the window's frames.
    assert stats(tmp_path, "--scene", "cornell_box", "--view", "normals",
                 "--spp", "4")["samples_per_dispatch"] == 1
