"""Appendix A1: chapter 12's path tracer drawn in fragment-shader passes.

A pass draws one triangle over the image; the running mean, the generators and the ray
counts wait in two framebuffers that take turns. Its pictures are chapter 12's: on
llvmpipe the same seed gives the same bits (the same streams, arithmetic and order of
samples), and with another seed the regions of the Cornell box agree within their
statistical error. It needs OpenGL 4.3 (the scene stays in storage buffers) and calls
no compute shader."""

from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

from path_checks import render_with_stats as render
from conftest import (ROOT, WINDOW_SAFETY_TIMEOUT, check_hot_reload, copy_shaders,
                      loop_limit, read_pfm, regions_agreeing, run_chapter, window_command,
                      xvfb_available)

SCENES = ROOT / "assets" / "scenes"
SIGMAS = 4.5  # as chapter 12's checks: a correct renderer fails 1 in ~150,000
SIZE = ("--width", "48", "--height", "48")
pytestmark = pytest.mark.filterwarnings("ignore::RuntimeWarning")


@pytest.fixture(scope="module")
def pictures(tmp_path_factory):
    """Chapter 12 and the appendix, global and direct, seed 1; the appendix at seed 2."""
    folder = tmp_path_factory.mktemp("pictures")
    runs = {}
    for light in ("global", "direct"):
        options = [*SIZE, "--spp", 64] + (["--direct"] if light == "direct" else [])
        runs["12", light, 1] = render("12", folder, f"c12_{light}", *options, "--seed", 1)
        runs["A1", light, 1] = render("A1", folder, f"a1_{light}", *options, "--seed", 1)
        runs["A1", light, 2] = render("A1", folder, f"a1_{light}_2", *options, "--seed", 2)
    return runs


@pytest.mark.parametrize("light", ["global", "direct"])
def test_same_seed_same_samples_as_chapter_12(pictures, light):
    # One sample per pass as chapter 12 has one per dispatch, the same random streams
    # and arithmetic: on llvmpipe (one compiler for compute and fragment shaders) the
    # same bits, and every pixel traced the same number of rays. Another GL may compile
    # the two shaders differently; then only the statistics below hold.
    ours, our_stats = pictures["A1", light, 1]
    theirs, their_stats = pictures["12", light, 1]
    assert our_stats["rays"] == their_stats["rays"]
    assert theirs.mean() > 0.01  # not a black picture
    if "llvmpipe" in our_stats["renderer"]:
        assert np.array_equal(ours, theirs)
    else:
        assert np.abs(ours - theirs).mean() < 0.01 * theirs.mean()


@pytest.mark.parametrize("light", ["global", "direct"])
def test_regions_agree_with_chapter_12_statistically(pictures, light):
    # Independent streams (seed 2 against chapter 12's seed 1): each wall and sphere's
    # mean within 4.5 standard errors of the difference.
    ours, theirs = pictures["A1", light, 2][0], pictures["12", light, 1][0]
    assert not np.array_equal(ours, theirs)
    compared = regions_agreeing(ours, theirs, SCENES / "cornell_spheres.scene", SIGMAS)
    assert len(compared) >= 7  # five walls, two spheres


def test_a_generator_that_never_moves_on_is_caught(tmp_path, pictures):
    # A check that cannot fail is not a check. Each pass handing on the generator state
    # it was given instead of the advanced one: every pass draws the same sample, and
    # the mean never improves. Not chapter 12's bits, and far noisier than its picture.
    # (Planted after the pass's own code, so that it works on any student's version.)
    shaders = copy_shaders("A1", tmp_path)
    path = shaders / "path.frag"
    end = "    // --8<-- [end:accumulate]"
    assert end in path.read_text()
    path.write_text(path.read_text().replace(
        end, "    newRandomState = texelFetch(previousRandom, samePixel, 0);\n" + end))
    stuck, _ = render("A1", tmp_path, "stuck", *SIZE, "--spp", 64, "--seed", 1,
                      "--shader-dir", shaders)
    theirs = pictures["12", "global", 1][0]
    assert not np.array_equal(stuck, theirs)
    other = pictures["A1", "global", 2][0]  # a correct picture with other streams
    assert np.abs(stuck - theirs).mean() > 3 * np.abs(other - theirs).mean()


@pytest.mark.windows
def test_splitting_the_passes_changes_nothing(tmp_path):
    one, _ = render("A1", tmp_path, "one", "--width", 24, "--height", 24, "--spp", 16)
    four, _ = render("A1", tmp_path, "four", "--width", 24, "--height", 24, "--spp", 16,
                     "--batches", 4)
    assert np.array_equal(one, four)


def test_draws_instead_of_dispatching():
    # The lesson is the passes: main.cpp loads a vertex and a fragment shader and
    # draws; no compute shader is left, and the scene keeps chapter 12's buffers.
    main = (ROOT / "chapters" / "A1_fragment_passes" / "main.cpp").read_text()
    for compute in ("loadCompute", "dispatchCovering", "glMemoryBarrier"):
        assert compute not in main, compute
    assert "accumulation.draw(path)" in main and "bindStorage(SPHERES_BINDING)" in main
    shaders = ROOT / "shaders" / "A1_fragment_passes"
    assert not list(shaders.glob("*.comp"))


def test_needs_gl_43_for_its_storage_buffers(tmp_path):
    # Storage buffers in a fragment shader are OpenGL 4.3, as compute shaders are: on a
    # 3.3 context (a Mac's 4.1 alike) it stops with exit code 4 and points at A2.
    out = tmp_path / "x.png"
    result = run_chapter("A1", "--headless", "--out", out,
                         env={"MESA_GL_VERSION_OVERRIDE": "3.3",
                              "MESA_GLSL_VERSION_OVERRIDE": "330"})
    assert result.returncode == 4, result.stderr
    assert "needs OpenGL 4.3 core" in result.stderr
    assert "OpenGL 3.3 appendix" in result.stderr
    assert not out.exists()


def test_too_many_loop_iterations_are_refused_as_in_chapter_12(tmp_path):
    # ~220 shapes x 1001 bounces: far beyond the 65535 iterations an invocation gets on
    # Mesa 22's llvmpipe. Refused where the appendix measures a limit for its fragment
    # shaders; drawn where there is none (paths end long before 1000 bounces).
    limit = loop_limit("A1")
    out = tmp_path / "x.png"
    result = run_chapter("A1", "--headless", "--scene", "cornell_gems", "--depth", 1000,
                         "--width", 8, "--height", 8, "--out", out)
    if limit is None:
        assert result.returncode == 0, result.stderr
        assert out.exists()
        return
    assert result.returncode == 4, result.stderr
    for words in ("cornell_gems.scene", f"after {limit} (measured)", "A lower --depth"):
        assert words in result.stderr, words
    assert not out.exists()


@pytest.mark.skipif(not xvfb_available(), reason="Xvfb is not installed")
def test_window_refines_and_a_camera_move_starts_over(tmp_path, window_env):
    out = tmp_path / "window.pfm"
    result = subprocess.run(window_command("A1", out, "--frames", 20, "--frame-samples", 3,
                                           "--script-camera-move"),
                            capture_output=True, text=True, timeout=WINDOW_SAFETY_TIMEOUT,
                            env=window_env)
    assert result.returncode == 0, result.stderr
    stats = json.loads(result.stdout.strip().splitlines()[-1])
    # Frames 0 and 1 add 3 samples each, frame 2 moves and starts over, 2..19 add 3 each.
    assert stats["samples_per_pixel"] == 18 * 3
    assert stats["camera_z"] < 3.9 - 0.5
    assert read_pfm(out)[..., :3].mean() > 0.05


@pytest.mark.skipif(not xvfb_available(), reason="Xvfb is not installed")
def test_window_hot_reloads_and_survives_a_broken_shader(tmp_path, window_env):
    # The edit follows the pass's own code, which a starter leaves to the student.
    end = "    // --8<-- [end:accumulate]"
    image = check_hot_reload("A1", copy_shaders("A1", tmp_path), "path.frag",
                             (end, "    newMean = vec4(0.25, 0.5, 0.75, 1.0);\n" + end),
                             tmp_path / "window.pfm", "--frame-samples", 1,
                             env=window_env)
    assert np.allclose(image, [0.25, 0.5, 0.75])
