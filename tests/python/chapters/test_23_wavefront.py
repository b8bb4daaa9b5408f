"""Chapter 23: wavefront path tracing (book/docs/maintainers.md).

The chapter runs chapter 22's path tracer two ways, the megakernel (one invocation
follows a pixel's path to its end) and the wavefront (one kernel per step, over queues of
paths), and changes nothing of what either computes: both call the same steps
(path_steps.glsl) with the same random numbers for each pixel, in the same order. So:

- Both ways draw chapter 22's picture, within float rounding
  (path_checks.assert_same_picture), on scenes with every material kind, textures and a
  lens, a mesh through the tree, an environment, every estimator, direct light only,
  the deepest paths, the generic shader and storage buffers. Chapter 22's pictures are
  checked against Mitsuba 3, closed forms and numpy prototypes; the wavefront's Cornell
  box is checked against Mitsuba 3 directly too.
- The comparison catches a wrong wavefront: a push that is not atomic (lanes that
  push together take the same place and lose each other's paths), and dispatch
  commands that round the queue's work groups down (the last paths of a queue are
  never run).
- The wavefront's kernels trace one ray each, so chapter 12's brute force fits Mesa
  22's loop limit where the megakernel's whole path does not; it draws the tree's
  picture.
- A view other than the radiance needs the megakernel: exit code 2, no image.
- The pool of path slots: a pool smaller than the image (--paths) runs it in waves and
  draws the same picture; a large image takes as many slots as the GL's limits allow
  (asked at run time: llvmpipe's storage blocks hold 762 600 of them), and draws the
  same picture too.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import path_checks
import pytest
from conftest import ROOT, run_chapter
from path_checks import path_trace

SMALL = ["--width", "48", "--height", "48", "--spp", "8"]
WAVEFRONT = ["--kernel", "wavefront"]


# Every material kind, under the sky; a textured mesh through the tree and a lens; an
# environment with every estimator's share; glass.
@pytest.mark.windows
@pytest.mark.parametrize("scene", ["sky_showcase", "lens_textures", "sky_estimators",
                                   "cornell_glass"])
def test_both_kernels_draw_chapter_22s_picture(tmp_path, scene):
    reference = path_trace("22", tmp_path, "chapter22", "--scene", scene, *SMALL)
    megakernel = path_trace("23", tmp_path, "megakernel", "--scene", scene, *SMALL)
    path_checks.assert_same_picture(megakernel, reference, f"{scene}, megakernel")
    wavefront = path_trace("23", tmp_path, "wavefront", "--scene", scene, *SMALL, *WAVEFRONT)
    path_checks.assert_same_picture(wavefront, reference, f"{scene}, wavefront")


@pytest.mark.parametrize("options", [["--estimator", "nee"], ["--estimator", "bsdf"],
                                     ["--direct"], ["--depth", "1000"], ["--generic"],
                                     ["--scene-memory", "storage", "--bvh-memory",
                                      "storage"]],
                         ids=["nee", "bsdf", "direct", "depth_1000", "generic", "storage"])
def test_the_wavefront_draws_the_megakernels_picture_with_every_option(tmp_path, options):
    scene = ["--scene", "lens_textures"]
    megakernel = path_trace("23", tmp_path, "megakernel", *scene, *SMALL, *options)
    wavefront = path_trace("23", tmp_path, "wavefront", *scene, *SMALL, *options, *WAVEFRONT)
    path_checks.assert_same_picture(wavefront, megakernel, " ".join(options))
    assert wavefront.mean() > 0.01  # lit, not black


@pytest.mark.parametrize("bug", [
    ("wavefront.glsl", "uint place = atomicAdd(queues[queue].size, 1u);",
     "uint place = queues[queue].size;\n    queues[queue].size = place + 1u;"),
    ("wavefront_dispatch.comp",
     "(size + QUEUE_GROUP_SIZE - 1u) / QUEUE_GROUP_SIZE", "size / QUEUE_GROUP_SIZE"),
], ids=["push_not_atomic", "groups_rounded_down"])
def test_a_wrong_wavefront_is_caught(tmp_path, bug):
    shaders = path_checks.shaders_with_bug("23", tmp_path / "shaders", bug)
    scene = ["--scene", "cornell_metals"]
    reference = path_trace("23", tmp_path, "right", *scene, *SMALL, *WAVEFRONT)
    wrong = path_trace("23", tmp_path, "wrong", *scene, *SMALL, *WAVEFRONT,
                       "--shader-dir", shaders)
    with pytest.raises(AssertionError):
        path_checks.assert_same_picture(wrong, reference, "the planted mistake")


def test_the_wavefronts_brute_force_draws_the_trees_picture(tmp_path):
    # 6 320 triangles tested for every ray: the megakernel's path needs 2 x 7 times as
    # many loop iterations, past Mesa 22's limit; a wavefront kernel traces one ray.
    scene = ["--scene", "cornell_teapot", "--width", "32", "--height", "32", "--spp", "2"]
    tree = path_trace("23", tmp_path, "tree", *scene)
    brute = path_trace("23", tmp_path, "brute", *scene, "--brute-force", *WAVEFRONT)
    path_checks.assert_same_picture(brute, tree, "brute force through the wavefront")


def stats(tmp_path, *args) -> dict:
    return path_checks.render_stats("23", tmp_path, *args)


def test_other_views_need_the_megakernel(tmp_path):
    result = run_chapter("23", "--headless", "--view", "normals", *WAVEFRONT,
                         "--out", tmp_path / "never.png")
    assert result.returncode == 2, result.stderr
    assert "--kernel wavefront traces paths only" in result.stderr
    assert not (tmp_path / "never.png").exists()


def test_the_wavefront_agrees_with_mitsuba(tmp_path):
    ours = path_trace("23", tmp_path, "ours", "--scene", "cornell_box", "--width", "96",
                      "--height", "96", "--spp", "256", *WAVEFRONT)
    scene_file = ROOT / "assets" / "scenes" / "cornell_box.scene"
    compared = path_checks.assert_agrees_with_mitsuba(ours, 512, scene_file)
    assert len(compared) >= 5, compared


def wavefront_stats(tmp_path, *args) -> dict:
    return stats(tmp_path, *WAVEFRONT, *args)


def test_a_pool_smaller_than_the_image_runs_it_in_waves(tmp_path):
    # 48 x 48 = 2 304 pixels through 1 000 path slots: waves of 1 000, 1 000 and 304.
    scene = ["--scene", "sky_showcase", *SMALL]
    assert wavefront_stats(tmp_path, *scene, "--paths", 1000)["paths_in_flight"] == 1000
    megakernel = path_trace("23", tmp_path, "megakernel", *scene)
    waves = path_trace("23", tmp_path, "waves", *scene, *WAVEFRONT, "--paths", "1000")
    path_checks.assert_same_picture(waves, megakernel, "three waves of the image")


def test_a_large_image_takes_as_many_paths_as_the_gl_allows(tmp_path):
    # 1024 x 1024 pixels: a slot for each is 176 MiB, past llvmpipe's 128 MiB storage
    # blocks, so there it runs in two waves of 762 600; a GL that allows more, in one.
    scene = ["--scene", "cornell_box", "--width", "1024", "--height", "1024", "--spp",
             "1", "--depth", "2"]
    paths = wavefront_stats(tmp_path, *scene)["paths_in_flight"]
    assert 0 < paths <= 1024 * 1024
    megakernel = path_trace("23", tmp_path, "megakernel", *scene)
    wavefront = path_trace("23", tmp_path, "wavefront", *scene, *WAVEFRONT)
    path_checks.assert_same_picture(wavefront, megakernel, f"waves of {paths} paths")
