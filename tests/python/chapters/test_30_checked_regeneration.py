"""Chapter 30: checked regeneration (book/docs/maintainers.md).

Chapter 23's megakernel took one sample a dispatch of a mesh's tree on a GL with a loop
limit (Mesa 22's llvmpipe): no count of samples is sure to fit it. Chapter 30 takes up
to 64, and has each of those dispatches find out whether the GL cut its loops short (a
last loop, loopsCutShort, that runs both its turns only if no loop before it was cut).
A dispatch that was cut runs again from a copy of the buffers it changes, with half as
many samples. Neither changes what is computed: each pixel's random numbers come in the
same order, and its sums are made in the order of one sample a dispatch. So:

- Both kernels draw chapter 23's picture within float rounding
  (path_checks.assert_same_picture): a mesh through the tree, textures and a lens, an
  environment, glass; and the scene read from storage buffers, which take all the
  storage blocks llvmpipe has (the report of a cut is an atomic counter). Chapter 23's pictures are checked against chapter 22's, and
  those against Mitsuba 3, closed forms and numpy prototypes.
- The teapot takes 64 samples a dispatch, on a GL with a loop limit too, and draws the
  picture of one sample a dispatch.
- A planted long walk (each nearest hit walks the tree 20 times over): where the GL has
  a loop limit (measured), its dispatches of 64 samples are cut, run again with fewer,
  and draw the picture of one sample a dispatch. With the report of the cut taken out
  (the planted mistake) the same comparison fails: a cut nobody hears of leaves wrong
  pixels in the picture. Where the GL has no limit, nothing is cut or run again.
- A walk too long even for one sample a dispatch: exit code 4, the scene named, no
  image written.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import path_checks
import pytest
from conftest import loop_limit, run_chapter
from path_checks import path_trace

SMALL = ["--width", "48", "--height", "48", "--spp", "8"]
TEAPOT = ["--scene", "cornell_teapot"]
ONE_A_DISPATCH = ["--samples-per-dispatch", "1"]
WALK = "    return bvhTraverse(ray, tMin, tMax, false, triangle, t, uv);"
REPORT = "    if (loopsCutShort()) atomicCounterIncrement(cutShortInvocations);"


@pytest.mark.windows
@pytest.mark.parametrize("scene", ["cornell_teapot", "lens_textures", "sky_showcase",
                                   "cornell_glass"])
def test_the_megakernel_draws_chapter_23s_picture(tmp_path, scene):
    # Chapter 23 takes one sample a dispatch of a tree where the GL has a loop limit,
    # chapter 30 all 8 at once.
    reference = path_trace("23", tmp_path, "chapter23", "--scene", scene, *SMALL)
    checked = path_trace("30", tmp_path, "checked", "--scene", scene, *SMALL)
    path_checks.assert_same_picture(checked, reference, f"{scene}, checked dispatches")


@pytest.mark.parametrize("options", [["--generic"], ["--scene-memory", "storage",
                                                     "--bvh-memory", "storage"]],
                         ids=["generic", "storage"])
def test_the_scene_from_storage_buffers_draws_chapter_23s_picture(tmp_path, options):
    # The scene read from storage buffers takes every storage block llvmpipe gives a
    # compute shader (16): the report of a cut must need none of them.
    scene = ["--scene", "lens_textures", *SMALL, *options]
    reference = path_trace("23", tmp_path, "chapter23", *scene)
    checked = path_trace("30", tmp_path, "checked", *scene)
    path_checks.assert_same_picture(checked, reference, f"lens_textures, {options[0]}")


def test_the_wavefront_draws_chapter_23s_picture(tmp_path):
    options = ["--scene", "lens_textures", *SMALL, "--kernel", "wavefront"]
    reference = path_trace("23", tmp_path, "chapter23", *options)
    wavefront = path_trace("30", tmp_path, "wavefront", *options)
    path_checks.assert_same_picture(wavefront, reference, "lens_textures, wavefront")


def test_the_teapot_takes_many_samples_a_dispatch(tmp_path):
    # 80 samples: a dispatch of 64, then one of the 16 left. The teapot's walks fit
    # Mesa 22's limit 64 samples at a time: nothing is cut.
    options = [*TEAPOT, "--width", "32", "--height", "32", "--spp", "80"]
    stats = path_checks.render_stats("30", tmp_path, *options)
    assert stats["samples_per_dispatch"] == 64 and stats["dispatches_redone"] == 0
    checked = path_trace("30", tmp_path, "checked", *options)
    one = path_trace("30", tmp_path, "one", *options, *ONE_A_DISPATCH)
    path_checks.assert_same_picture(checked, one, "the teapot, 64 samples a dispatch")
    assert checked.mean() > 0.01  # lit, not black


def long_walk_shaders(tmp_path, walks: int, reported: bool = True):
    """Chapter 30's shaders with each nearest hit walking the tree `walks` times over
    (the same hit, `walks` times the loop iterations); without the report of a cut if
    not `reported`."""
    long_walk = ("    bool found = false;\n"
                 f"    for (int walk = 0; walk < {walks}; ++walk)\n"
                 "        found = bvhTraverse(ray, tMin, tMax, false, triangle, t, uv);\n"
                 "    return found;")
    folder = path_checks.shaders_with_bug("30", tmp_path / f"walks{walks}{reported}",
                                          ("bvh_traversal.glsl", WALK, long_walk))
    if not reported:
        path = folder / "path.comp"
        assert path.read_text().count(REPORT) == 1
        path.write_text(path.read_text().replace(REPORT, ""))
    return folder


LONG_WALK = [*TEAPOT, "--width", "32", "--height", "32", "--spp", "64"]


def test_a_long_walk_is_cut_run_again_and_draws_the_same_picture(tmp_path):
    shaders = ["--shader-dir", long_walk_shaders(tmp_path, 20)]
    stats = path_checks.render_stats("30", tmp_path, *LONG_WALK, *shaders)
    if loop_limit("30") is None:  # measured: nothing to cut
        assert stats["samples_per_dispatch"] == 64 and stats["dispatches_redone"] == 0
    else:  # 64 samples of 20 walks a hit are past 65 535 iterations; fewer fit
        assert 1 < stats["samples_per_dispatch"] < 64 and stats["dispatches_redone"] >= 1
    checked = path_trace("30", tmp_path, "checked", *LONG_WALK, *shaders)
    one = path_trace("30", tmp_path, "one", *LONG_WALK, *shaders, *ONE_A_DISPATCH)
    path_checks.assert_same_picture(checked, one, "a long walk, checked dispatches")
    assert checked.mean() > 0.01


def test_a_cut_left_unreported_is_caught(tmp_path):
    one = path_trace("30", tmp_path, "one", *LONG_WALK, *ONE_A_DISPATCH, "--shader-dir",
                     long_walk_shaders(tmp_path, 20))
    unreported = path_trace("30", tmp_path, "unreported", *LONG_WALK, "--shader-dir",
                            long_walk_shaders(tmp_path, 20, reported=False))
    if loop_limit("30") is None:  # measured: no cut to leave unreported
        path_checks.assert_same_picture(unreported, one, "no limit, nothing cut")
    else:
        with pytest.raises(AssertionError):
            path_checks.assert_same_picture(unreported, one, "the planted mistake")


def test_a_walk_too_long_for_one_sample_fails_clearly(tmp_path):
    out = tmp_path / "never.pfm"
    options = [*TEAPOT, "--width", "8", "--height", "8", "--spp", "1", "--depth", "2"]
    result = run_chapter("30", "--headless", "--out", out, *options, "--shader-dir",
                         long_walk_shaders(tmp_path, 2000))
    if loop_limit("30") is None:  # measured: every walk runs to its end
        assert result.returncode == 0, result.stderr
    else:
        assert result.returncode == 4, result.stderr
        assert "cornell_teapot.scene" in result.stderr and "one sample" in result.stderr
        assert not out.exists()
