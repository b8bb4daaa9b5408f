"""Chapter 19: specialisation (book/docs/maintainers.md).

The chapter changes how the path tracer runs, never what it computes: the shader
written for the scene it renders (its counts and features as constants, a small scene's
shapes written out as constants, the rest from storage buffers) and the generic shader
(every feature compiled in, chapter 18's) draw chapter 18's picture. Chapter 18's
pictures are checked against Mitsuba 3, closed forms and numpy prototypes
(test_18_*.py); chapter 19's are checked against chapter 18's and, on the fast path,
against Mitsuba 3 directly.

- Same picture: the same pixels, since both use the same random numbers for each pixel.
  A compiler may fold constants in another order than it computes a buffer's values,
  which changes the last bits of a few pixels and, through a bounce that goes the other
  way, a pixel entirely: the comparison allows a few pixels in a thousand to differ and
  the mean to move by 1e-5 (relative). Mesa 22's llvmpipe gives identical pixels.
- The comparison catches a wrong shader written for the scene: a planted mistake in the
  written-out quad test fails it.
- The choice: constants for a scene within the limits (scene_code.h), storage buffers
  past them; constants by hand past four times them is exit code 2, naming the scene
  file.
- A scene at the limit (32 shapes, each test written out) and a large one (300 spheres
  from storage buffers) draw the generic shader's picture: the written-out tests nest
  no deeper with more shapes (shadow rays do not return from inside them).
- The GPU timer reports the render's time, no more than the wall clock around it.
- The fast path (the Cornell box in constants) against Mitsuba 3, region by region.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import path_checks
import pytest
from conftest import ROOT, run_chapter
from path_checks import path_trace, spheres_scene

WAYS = {
    "constants": ["--scene-memory", "constants"],
    "storage": ["--scene-memory", "storage"],
    "generic": ["--generic"],
}
SMALL = ["--width", "48", "--height", "48", "--spp", "8"]


@pytest.mark.windows
@pytest.mark.parametrize("scene", ["cornell_metals", "lens_textures", "sky_estimators",
                                   "cornell_glass"])
def test_every_way_of_reading_the_scene_draws_chapter_18s_picture(tmp_path, scene):
    reference = path_trace("18", tmp_path, "chapter18", "--scene", scene, *SMALL)
    for way, options in WAYS.items():
        image = path_trace("19", tmp_path, way, "--scene", scene, *SMALL, *options)
        path_checks.assert_same_picture(image, reference, f"{scene}, {way}")


def test_a_wrong_quad_test_written_out_is_caught(tmp_path):
    # The written-out quad test forgets to bring the ray's far end in to the hit it
    # found: a quad further along, tested later, takes the pixel.
    shaders = path_checks.shaders_with_bug(
        "19", tmp_path / "shaders",
        ("scene.glsl", "tMax = t; kind = SHAPE_QUAD; index = i; hitAb = ab; }",
         "kind = SHAPE_QUAD; index = i; hitAb = ab; }"))
    options = ["--scene", "cornell_box", *SMALL, "--scene-memory", "constants"]
    reference = path_trace("19", tmp_path, "right", *options)
    wrong = path_trace("19", tmp_path, "wrong", *options, "--shader-dir", shaders)
    with pytest.raises(AssertionError):
        path_checks.assert_same_picture(wrong, reference, "the planted mistake")


def stats(tmp_path, *args) -> dict:
    return path_checks.render_stats("19", tmp_path, "--width", "16", "--height", "16",
                                    "--spp", "1", *args)


def test_the_choice_is_automatic_and_a_scene_too_large_for_constants_is_refused(tmp_path):
    assert stats(tmp_path, "--scene", "cornell_box")["scene_memory"] == "constants"
    showcase = stats(tmp_path, "--scene", "showcase")  # 50 spheres, 6 quads
    assert showcase["scene_memory"] == "storage" and showcase["specialised"] == 1
    generic = stats(tmp_path, "--scene", "cornell_box", "--generic")
    assert generic["scene_memory"] == "storage" and generic["specialised"] == 0
    large = spheres_scene(tmp_path / "large.scene", 200)
    result = run_chapter("19", "--headless", "--scene", large, "--scene-memory",
                         "constants", "--out", tmp_path / "never.png")
    assert result.returncode == 2, result.stderr
    assert "large.scene: too large to write into the shader" in result.stderr
    assert "at most 128 spheres and quads" in result.stderr
    assert "--scene-memory storage reads any size" in result.stderr
    assert not (tmp_path / "never.png").exists()


@pytest.mark.parametrize("spheres, way", [(26, "constants"), (300, "storage")])
def test_at_the_limit_and_past_it_the_picture_is_the_generic_shaders(tmp_path, spheres,
                                                                     way):
    scene = spheres_scene(tmp_path / f"spheres_{spheres}.scene", spheres)
    assert stats(tmp_path, "--scene", scene)["scene_memory"] == way
    fast = path_trace("19", tmp_path, "fast", "--scene", scene, *SMALL)
    generic = path_trace("19", tmp_path, "generic", "--scene", scene, *SMALL, "--generic")
    path_checks.assert_same_picture(fast, generic, f"{spheres} spheres through {way}")
    assert fast.mean() > 0.01  # lit, not black


def test_the_gpu_timer_times_the_render(tmp_path):
    figures = stats(tmp_path, "--scene", "cornell_box", "--spp", "16", "--width", "64",
                    "--height", "64")
    assert 0 < figures["gpu_ms"] <= figures["wall_ms"] * 1.01 + 1


def test_the_fast_path_agrees_with_mitsuba(tmp_path):
    ours = path_trace("19", tmp_path, "ours", "--scene", "cornell_box", "--width", "96",
                      "--height", "96", "--spp", "256")
    scene_file = ROOT / "assets" / "scenes" / "cornell_box.scene"
    compared = path_checks.assert_agrees_with_mitsuba(ours, 512, scene_file)
    assert len(compared) >= 5, compared


def test_the_pages_listing_is_what_the_program_writes(tmp_path):
    # Page 19 shows the start of the shader part written for the Cornell box; --verbose
    # prints what the program wrote, so the listing cannot drift from the code.
    result = run_chapter("19", "--headless", "--scene", "cornell_box", "--width", 8,
                         "--height", 8, "--spp", 1, "--verbose", "--out", tmp_path / "x.png")
    assert result.returncode == 0, result.stderr
    printed = result.stderr.split("scene_code.glsl, as written for this scene:\n", 1)[1]
    page = (ROOT / "book" / "docs" / "chapters" / "19_specialisation.md").read_text()
    listing = page.split("For the Cornell box it begins:\n\n```glsl\n", 1)[1]
    listing = listing.split("```", 1)[0].splitlines()
    assert len(listing) >= 10
    assert printed.splitlines()[:len(listing)] == listing
