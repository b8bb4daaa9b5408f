"""Chapter 06: spheres and triangles (Moller-Trumbore in float32) must agree with
numpy's plane-and-edge-functions version in float64, on both backends; the barycentric
coordinates kept for chapter 08 must be right; without the normal flip the floor,
seen from behind, must go dark; and planted mistakes must be rejected."""

import numpy as np
import page_claims
import pytest

from python_prototypes import camera_rays
from conftest import (BACKENDS, assert_images_agree, copy_shaders, render, run_chapter,
                      srgb_encode_8bit)
from python_prototypes.reference.triangles import SCENES, Surfaces, render_barycentrics, render_shaded

WIDTH, HEIGHT = 200, 150


def reference_png(scene="spheres"):
    return srgb_encode_8bit(render_shaded(scene, WIDTH, HEIGHT))


@pytest.mark.windows
@pytest.mark.parametrize("backend", BACKENDS)
def test_triangles_agree_with_numpy(tmp_path, backend):
    png = render("06", tmp_path / "triangles.png", "--width", WIDTH, "--height", HEIGHT,
                 "--backend", backend)
    assert_images_agree(png, reference_png(), label=backend)


def test_every_scene_agrees_with_numpy(tmp_path):
    for scene in SCENES:
        png = render("06", tmp_path / f"{scene}.png", "--width", WIDTH, "--height", HEIGHT,
                     "--scene", scene)
        assert_images_agree(png, reference_png(scene), label=scene)


def test_barycentric_coordinates_in_the_hit_record(tmp_path):
    """Chapter 08 interpolates normals with them: show (u, v) as colours and compare."""
    shaders = copy_shaders("06", tmp_path)
    trace = shaders / "trace.comp"
    text = trace.read_text()
    assert "color = shade(hit);" in text
    trace.write_text(text.replace("color = shade(hit);", "color = vec3(hit.barycentric, 0);"))
    png = render("06", tmp_path / "uv.png", "--width", WIDTH, "--height", HEIGHT,
                 "--scene", "pyramid", "--shader-dir", shaders)
    reference = srgb_encode_8bit(render_barycentrics("pyramid", WIDTH, HEIGHT))
    assert_images_agree(png, reference)


def test_without_normal_flip_the_floor_seen_from_behind_goes_dark(tmp_path):
    png = render("06", tmp_path / "no_flip.png", "--width", WIDTH, "--height", HEIGHT,
                 "--no-normal-flip")
    reference = reference_png()
    with pytest.raises(AssertionError):
        assert_images_agree(png, reference)
    # The floor's corners are wound clockwise seen from above, so its normals point
    # down: unflipped, it faces away from the light and shadows itself. The pyramid,
    # wound outwards, and the spheres are unchanged.
    surfaces = Surfaces(SCENES["spheres"])
    camera = camera_rays.Camera()
    distances = surfaces.distances(camera.eye, camera_rays.camera_rays(camera, WIDTH, HEIGHT))
    nearest = np.where(np.isfinite(distances).any(axis=-1), np.argmin(distances, axis=-1), -1)
    floor = np.isin(nearest, [len(surfaces.radii), len(surfaces.radii) + 1])
    differs = np.any(np.abs(png - reference) > 2.0, axis=-1)
    assert np.mean(differs[floor]) > 0.95
    assert np.mean(differs[~floor]) < 0.005
    assert np.all(png[differs] < reference[differs])  # darker
    page_claims.check("06-no-normal-flip", png[differs].mean() / reference[differs].mean())


# Plausible mistakes, planted in a copy of the shaders.
MISTAKES = {
    # The third edge test forgotten: u + v > 1 not rejected, triangles become
    # parallelograms.
    "parallelogram": ("triangle.glsl", "if (v < 0.0 || u + v > 1.0)",
                      "if (v < 0.0 || v > 1.0)"),
    # One-sided triangles (back-face culling): the floor, wound the other way, vanishes.
    "culling": ("triangle.glsl", "if (abs(determinant) < 1e-12)", "if (determinant < 1e-12)"),
    # The flip's test the wrong way round: every triangle's normal faces away from the
    # ray. (Swapping edge1 and edge2 in the cross product, on the other hand, is a
    # mistake the flip repairs: two-sided triangles do not care about winding.)
    "flip_sign": ("triangle.glsl", "dot(normal, ray.direction) > 0.0",
                  "dot(normal, ray.direction) < 0.0"),
}


@pytest.mark.parametrize("mistake", MISTAKES)
def test_check_rejects_a_planted_mistake(tmp_path, mistake):
    file_name, right, wrong = MISTAKES[mistake]
    shaders = copy_shaders("06", tmp_path)
    source = shaders / file_name
    assert right in source.read_text()
    source.write_text(source.read_text().replace(right, wrong))
    png = render("06", tmp_path / "wrong.png", "--width", WIDTH, "--height", HEIGHT,
                 "--shader-dir", shaders)
    with pytest.raises(AssertionError):
        assert_images_agree(png, reference_png())


def test_unknown_scene_is_exit_2_with_the_names(tmp_path):
    result = run_chapter("06", "--headless", "--out", tmp_path / "x.png", "--scene", "cube")
    assert result.returncode == 2
    assert "unknown scene 'cube'" in result.stderr
    assert all(name in result.stderr for name in SCENES)
    assert list(tmp_path.iterdir()) == []
