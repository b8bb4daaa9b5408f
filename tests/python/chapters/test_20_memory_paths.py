"""Chapter 20: memory paths (book/docs/maintainers.md).

The chapter reads the scene through the GPU's other memory paths (uniform blocks,
buffer textures) and the tree and its triangles through buffer textures, and changes
nothing of what the path tracer computes: every way draws chapter 19's picture, which is
checked against chapter 18's and Mitsuba 3 (test_19_specialisation.py).

- Same picture: the same pixels for the same random numbers, within float rounding
  (path_checks.assert_same_picture), on scenes with every material kind, textures and
  a lens, a mesh through the tree, an environment and glass.
- The comparison catches a wrong path: a planted mistake in reading the spheres from a
  buffer texture fails it.
- The choice: constants for a scene within the limits, buffer textures past them (the
  scene and the tree); a scene of 300 spheres through buffer textures draws the generic
  shader's picture.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import path_checks
import pytest
from conftest import run_chapter
from path_checks import path_trace, spheres_scene

WAYS = {
    "default": [],
    "uniform": ["--scene-memory", "uniform"],
    "texture": ["--scene-memory", "texture"],
    "tree in storage buffers": ["--bvh-memory", "storage"],
}
SMALL = ["--width", "48", "--height", "48", "--spp", "8"]


@pytest.mark.windows
@pytest.mark.parametrize("scene", ["cornell_metals", "lens_textures", "sky_estimators",
                                   "cornell_glass"])
def test_every_way_of_reading_the_scene_draws_chapter_19s_picture(tmp_path, scene):
    reference = path_trace("19", tmp_path, "chapter19", "--scene", scene, *SMALL)
    for way, options in WAYS.items():
        image = path_trace("20", tmp_path, way.replace(" ", "_"), "--scene", scene, *SMALL,
                           *options)
        path_checks.assert_same_picture(image, reference, f"{scene}, {way}")


def test_a_wrong_way_of_reading_the_spheres_is_caught(tmp_path):
    # The sphere's radius read from the texel's first number, not its fourth.
    shaders = path_checks.shaders_with_bug(
        "20", tmp_path / "shaders",
        ("scene_memory.glsl", "return Sphere(a.xyz, a.w, b.x, b.y, 0u, 0u);",
         "return Sphere(a.xyz, a.x, b.x, b.y, 0u, 0u);"))
    reference = path_trace("20", tmp_path, "right", "--scene", "cornell_metals", *SMALL,
                           "--scene-memory", "texture")
    wrong = path_trace("20", tmp_path, "wrong", "--scene", "cornell_metals", *SMALL,
                       "--scene-memory", "texture", "--shader-dir", shaders)
    with pytest.raises(AssertionError):
        path_checks.assert_same_picture(wrong, reference, "the planted mistake")


def stats(tmp_path, *args) -> dict:
    return path_checks.render_stats("20", tmp_path, "--width", "16", "--height", "16",
                                    "--spp", "1", *args)


def test_the_choice_is_automatic_and_past_the_limits_reads_buffer_textures(tmp_path):
    box = stats(tmp_path, "--scene", "cornell_box")
    assert box["scene_memory"] == "constants" and box["bvh_memory"] == "texture"
    showcase = stats(tmp_path, "--scene", "showcase")  # 50 spheres, 6 quads
    assert showcase["scene_memory"] == "texture" and showcase["bvh_memory"] == "texture"
    tree = stats(tmp_path, "--scene", "cornell_teapot", "--bvh-memory", "storage")
    assert tree["bvh_memory"] == "storage"
    large = spheres_scene(tmp_path / "large.scene", 200)
    result = run_chapter("20", "--headless", "--scene", large, "--scene-memory",
                         "constants", "--out", tmp_path / "never.png")
    assert result.returncode == 2, result.stderr
    assert "--scene-memory texture reads any size" in result.stderr
    assert not (tmp_path / "never.png").exists()


def test_past_the_limit_the_picture_is_the_generic_shaders(tmp_path):
    scene = spheres_scene(tmp_path / "spheres_300.scene", 300)
    assert stats(tmp_path, "--scene", scene)["scene_memory"] == "texture"
    fast = path_trace("20", tmp_path, "fast", "--scene", scene, *SMALL)
    generic = path_trace("20", tmp_path, "generic", "--scene", scene, *SMALL, "--generic")
    path_checks.assert_same_picture(fast, generic, "300 spheres through buffer textures")
    assert fast.mean() > 0.01  # lit, not black
