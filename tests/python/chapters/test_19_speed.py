"""Chapter 19: speed (book/docs/maintainers.md).

The chapter changes how the path tracer runs, never what it computes: every way of
reading the scene (storage buffers, uniform blocks, buffer textures, constants written
out into the shader), the tree through storage buffers or buffer textures, and the
generic shader (every feature compiled in) draw chapter 18's picture. Chapter 18's
pictures are checked against Mitsuba 3, closed forms and numpy prototypes
(test_18_*.py); chapter 19's are checked against chapter 18's and, on the fast path,
against Mitsuba 3 directly.

- Same picture: the same pixels, since both use the same random numbers for each pixel
  (the environment's draw is made with or without one). A compiler may fold constants in
  another order than it computes a buffer's values, which changes the last bits of a
  few pixels and, through a bounce that goes the other way, a pixel entirely: the
  comparison allows a few pixels in a thousand to differ and the mean to move by 1e-5
  (relative). Mesa 22's llvmpipe gives identical pixels.
- The comparison catches a wrong path: a planted mistake in one way of reading the
  spheres fails it.
- The choice: constants for a scene within the limits (scene_code.h), buffer textures
  past them; constants by hand past four times them is exit code 2, naming the scene
  file.
- A scene at the limit (32 shapes, each test written out) and a large one (300 spheres
  through buffer textures) draw the generic shader's picture: the written-out tests
  nest no deeper with more shapes (shadow rays do not return from inside them).
- The tree's leaves priced as the four tests they run: fewer nodes than chapter 18's
  tree (which pricing by count gives again), and the same picture.
- The GPU timer reports the render's time, no more than the wall clock around it.
- The fast path (the Cornell box in constants) against Mitsuba 3, region by region.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import json

import numpy as np
import path_checks
import pytest
from conftest import ROOT, run_chapter
from path_checks import path_trace

WAYS = {
    "constants": ["--scene-memory", "constants"],
    "storage": ["--scene-memory", "storage"],
    "uniform": ["--scene-memory", "uniform"],
    "texture": ["--scene-memory", "texture"],
    "tree in storage buffers": ["--bvh-memory", "storage"],
    "generic": ["--generic"],
}
SMALL = ["--width", "48", "--height", "48", "--spp", "8"]


@pytest.mark.parametrize("scene", ["cornell_metals", "lens_textures", "sky_estimators",
                                   "cornell_glass"])
def test_every_way_of_reading_the_scene_draws_chapter_18s_picture(tmp_path, scene):
    reference = path_trace("18", tmp_path, "chapter18", "--scene", scene, *SMALL)
    for way, options in WAYS.items():
        image = path_trace("19", tmp_path, way.replace(" ", "_"), "--scene", scene, *SMALL,
                           *options)
        path_checks.assert_same_picture(image, reference, f"{scene}, {way}")


def test_a_wrong_way_of_reading_the_spheres_is_caught(tmp_path):
    # The sphere's radius read from the texel's first number, not its fourth.
    shaders = path_checks.shaders_with_bug(
        "19", tmp_path / "shaders",
        ("scene_memory.glsl", "return Sphere(a.xyz, a.w, b.x, b.y, 0u, 0u);",
         "return Sphere(a.xyz, a.x, b.x, b.y, 0u, 0u);"))
    reference = path_trace("19", tmp_path, "right", "--scene", "cornell_metals", *SMALL,
                           "--scene-memory", "texture")
    wrong = path_trace("19", tmp_path, "wrong", "--scene", "cornell_metals", *SMALL,
                       "--scene-memory", "texture", "--shader-dir", shaders)
    with pytest.raises(AssertionError):
        path_checks.assert_same_picture(wrong, reference, "the planted mistake")


def stats(tmp_path, *args, chapter="19") -> dict:
    result = run_chapter(chapter, "--headless", "--out", tmp_path / "out.pfm", "--json",
                         "--width", "16", "--height", "16", "--spp", "1", *args)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout.strip().splitlines()[-1])


def test_the_choice_is_automatic_and_a_scene_too_large_for_constants_is_refused(tmp_path):
    assert stats(tmp_path, "--scene", "cornell_box")["scene_memory"] == "constants"
    showcase = stats(tmp_path, "--scene", "showcase")  # 50 spheres, 6 quads
    assert showcase["scene_memory"] == "texture" and showcase["bvh_memory"] == "texture"
    generic = stats(tmp_path, "--scene", "cornell_box", "--generic")
    assert generic["scene_memory"] == "storage" and generic["specialised"] == 0
    large = spheres_scene(tmp_path / "large.scene", 200)
    result = run_chapter("19", "--headless", "--scene", large, "--scene-memory",
                         "constants", "--out", tmp_path / "never.png")
    assert result.returncode == 2, result.stderr
    assert "large.scene: too large to write into the shader" in result.stderr
    assert "at most 128 spheres and quads" in result.stderr
    assert not (tmp_path / "never.png").exists()


def spheres_scene(path, count: int):
    """`count` small spheres in rows above the Cornell room's floor, every fifth one
    glowing, the rest alternately white and red: a scene of count + 6 shapes."""
    lines = ["camera eye 0 0 3.9 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.025",
             "material white albedo 0.8 0.8 0.8", "material red albedo 0.8 0.1 0.1",
             "material lamp albedo 0.8 0.8 0.8 emission 4 4 4",
             "quad -1 -1 1 2 0 0 0 0 -2 white", "quad -1 1 -1 2 0 0 0 0 2 white",
             "quad -1 -1 -1 2 0 0 0 2 0 white", "quad -1 -1 1 0 0 -2 0 2 0 red",
             "quad 1 -1 -1 0 0 2 0 2 0 white",
             "quad -0.25 0.99 -0.25 0.5 0 0 0 0 0.5 lamp"]
    side = int(np.ceil(np.sqrt(count)))
    for i in range(count):
        x, z = -0.9 + 1.8 * (i % side + 0.5) / side, -0.9 + 1.8 * (i // side + 0.5) / side
        material = "lamp" if i % 5 == 0 else ("white", "red")[i % 2]
        lines.append(f"sphere {x:.4f} {-0.9 + 0.05 * (i % 3):.4f} {z:.4f} "
                     f"{0.6 / side:.4f} {material}")
    path.write_text("\n".join(lines) + "\n")
    return path


def test_leaves_priced_as_written_out_make_fewer_nodes_and_the_same_picture(tmp_path):
    # A leaf costs its four written-out tests whatever it holds (bvh.h): priced so, a
    # range of up to four triangles stays one leaf. Priced by count it is chapter 18's
    # tree, node for node.
    teapot = ["--scene", "cornell_teapot"]
    written_out, by_count = stats(tmp_path, *teapot), stats(
        tmp_path, *teapot, "--bvh-leaves-by-count")
    chapter_18 = stats(tmp_path, *teapot, chapter="18")
    assert by_count["bvh_nodes"] == chapter_18["bvh_nodes"]
    assert written_out["bvh_nodes"] < 0.7 * by_count["bvh_nodes"]
    assert 6320 / written_out["bvh_leaves"] > 3.0  # triangles a leaf, at most 4
    full = path_trace("19", tmp_path, "written_out", *teapot, *SMALL)
    smaller = path_trace("19", tmp_path, "by_count", *teapot, *SMALL,
                         "--bvh-leaves-by-count")
    path_checks.assert_same_picture(full, smaller, "the teapot, leaves priced two ways")


@pytest.mark.parametrize("spheres, way", [(26, "constants"), (300, "texture")])
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
