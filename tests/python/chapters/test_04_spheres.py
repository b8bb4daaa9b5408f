"""Chapter 04: the spheres the shader finds (geometrically, in float32) must be the
spheres numpy finds (with the quadratic formula, in float64), on both backends; the
--first-hit bug must differ from the right picture exactly where spheres overlap; and
planted mistakes must be rejected."""

import numpy as np
import page_claims
import pytest

from python_prototypes import camera_rays
from conftest import (BACKENDS, assert_images_agree, copy_shaders, render, run_chapter,
                      srgb_encode_8bit)
from python_prototypes.reference.spheres import (SCENES, hit_sphere_index, render_normals, scene_arrays,
                               sphere_distances)

WIDTH, HEIGHT = 200, 150


def reference_png(scene="spheres", first_hit=False):
    return srgb_encode_8bit(render_normals(scene, WIDTH, HEIGHT, first_hit=first_hit))


@pytest.mark.windows
@pytest.mark.parametrize("backend", BACKENDS)
def test_spheres_agree_with_numpy(tmp_path, backend):
    png = render("04", tmp_path / "spheres.png", "--width", WIDTH, "--height", HEIGHT,
                 "--backend", backend)
    assert_images_agree(png, reference_png(), label=backend)


def test_every_scene_agrees_with_numpy(tmp_path):
    for scene in SCENES:
        png = render("04", tmp_path / f"{scene}.png", "--width", WIDTH, "--height", HEIGHT,
                     "--scene", scene)
        assert_images_agree(png, reference_png(scene), label=scene)


def test_first_hit_bug_differs_exactly_where_spheres_overlap(tmp_path):
    bug = render("04", tmp_path / "first.png", "--width", WIDTH, "--height", HEIGHT,
                 "--first-hit")
    # The bug picture is what numpy's first-hit rendering predicts ...
    assert_images_agree(bug, reference_png(first_hit=True), label="first hit")
    # ... and where it differs from the right picture, the first sphere in the list
    # that a ray meets is not the nearest one: where spheres overlap on screen.
    directions = camera_rays.camera_rays(camera_rays.Camera(), WIDTH, HEIGHT)
    distances = sphere_distances(camera_rays.Camera().eye, directions,
                                 *scene_arrays("spheres"))
    overlap = hit_sphere_index(distances, first_hit=True) != hit_sphere_index(distances)
    differs = np.any(np.abs(bug - reference_png()) > 2.0, axis=-1)
    assert overlap.sum() > 0.01 * overlap.size  # the scene really has overlaps
    assert np.mean(differs != overlap) < 0.002, (differs.sum(), overlap.sum())
    page_claims.record("04-first-hit-overlap", f"{overlap.mean():.1%}")


# Plausible mistakes, planted in a copy of the shaders.
MISTAKES = {
    # The normal from the surface to the centre: every colour inverted.
    "inward_normal": ("sphere.glsl", "(position - sphere.center)",
                      "(sphere.center - position)"),
    # The far side of the sphere: the ray's exit instead of its entry.
    "exit_point": ("sphere.glsl", "t = tClosest - halfChord;", "t = tClosest + halfChord;"),
    # The subtraction the wrong way round: the spheres end up behind the camera.
    "backwards": ("sphere.glsl", "sphere.center - ray.origin", "ray.origin - sphere.center"),
}


@pytest.mark.parametrize("mistake", MISTAKES)
def test_check_rejects_a_planted_mistake(tmp_path, mistake):
    file_name, right, wrong = MISTAKES[mistake]
    shaders = copy_shaders("04", tmp_path)
    source = shaders / file_name
    assert right in source.read_text()
    source.write_text(source.read_text().replace(right, wrong))
    png = render("04", tmp_path / "wrong.png", "--width", WIDTH, "--height", HEIGHT,
                 "--shader-dir", shaders)
    with pytest.raises(AssertionError):
        assert_images_agree(png, reference_png())


def test_unknown_scene_is_exit_2_with_the_names(tmp_path):
    result = run_chapter("04", "--headless", "--out", tmp_path / "x.png", "--scene", "cube")
    assert result.returncode == 2
    assert "unknown scene 'cube'" in result.stderr
    for name in SCENES:
        assert name in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_bad_camera_is_exit_2(tmp_path):
    result = run_chapter("04", "--headless", "--camera-look", "0,0,0")
    assert result.returncode == 2
    assert "camera: the look direction must not be zero" in result.stderr
