"""Chapter 05: the shaded picture (Lambert, shadow rays, a floor plane) must agree with
numpy's, on both backends; without the shadow offset, shadow acne must make it
disagree; and planted mistakes must be rejected."""

import numpy as np
import page_claims
import pytest

from python_prototypes import camera_rays
from conftest import (BACKENDS, assert_images_agree, copy_shaders, render, run_chapter,
                      srgb_encode_8bit)
from python_prototypes.reference.shading import SCENES, Surfaces, light_visible, primary_hits, render_shaded

WIDTH, HEIGHT = 200, 150


def reference_png(scene="spheres"):
    return srgb_encode_8bit(render_shaded(scene, WIDTH, HEIGHT))


@pytest.mark.windows
@pytest.mark.parametrize("backend", BACKENDS)
def test_shading_agrees_with_numpy(tmp_path, backend):
    png = render("05", tmp_path / "shaded.png", "--width", WIDTH, "--height", HEIGHT,
                 "--backend", backend)
    assert_images_agree(png, reference_png(), label=backend)


def test_every_scene_agrees_with_numpy(tmp_path):
    for scene in SCENES:
        png = render("05", tmp_path / f"{scene}.png", "--width", WIDTH, "--height", HEIGHT,
                     "--scene", scene)
        assert_images_agree(png, reference_png(scene), label=scene)


def test_without_shadow_offset_acne_darkens_lit_surfaces(tmp_path):
    acne = render("05", tmp_path / "acne.png", "--width", WIDTH, "--height", HEIGHT,
                  "--no-shadow-offset")
    reference = reference_png()
    with pytest.raises(AssertionError):
        assert_images_agree(acne, reference)
    wrong = np.any(np.abs(acne - reference) > 2.0, axis=-1)
    assert wrong.mean() > 0.02  # many pixels, not a few silhouette pixels
    page_claims.record("05-acne-gpu", f"{wrong.mean():.1%}")
    # Acne is light wrongly blocked: the wrong pixels are darker. (Not all: where a
    # sphere touches the floor, starting 1 mm off the surface can itself matter.)
    brighter = np.any(acne > reference + 2.0, axis=-1)
    assert brighter.sum() < 0.01 * wrong.sum()
    page_claims.check("05-no-shadow-offset", acne[wrong].mean() / reference[wrong].mean())


def test_float64_without_offset_has_acne_too():
    """The book's claim: acne is not a float32 problem. Shadow rays that start exactly on
    the surface find it again at t = +-1e-16 in float64 as at +-1e-7 in float32."""
    surfaces = Surfaces(SCENES["spheres"])
    _, hit, points, normals, _ = primary_hits(surfaces, camera_rays.Camera(), WIDTH, HEIGHT)
    lit = hit[..., 0] & (np.sum(normals * (surfaces.light - points), axis=-1) > 0)
    with_offset, _ = light_visible(surfaces, points, normals)
    without_offset, _ = light_visible(surfaces, points, normals, shadow_offset=0.0)
    acne = (with_offset != without_offset)[..., 0] & lit
    assert acne.sum() > 0.03 * lit.sum()
    # The page's figure: the share of the float64 picture's pixels that change.
    changed = np.any(np.abs(reference_png() - srgb_encode_8bit(render_shaded(
        "spheres", WIDTH, HEIGHT, shadow_offset=0.0))) > 2.0, axis=-1)
    page_claims.record("05-acne-float64", f"{changed.mean():.1%}")


# Plausible mistakes, planted in a copy of the shaders.
MISTAKES = {
    # A shadow ray whose direction is not of unit length: hitSphere's geometry and the
    # Lambert cosine both assume it is.
    "unnormalized": ("shading.glsl", "Ray(shadowOrigin, toLight / lightDistance)",
                     "Ray(shadowOrigin, toLight)"),
    # The direction to the light the wrong way round.
    "light_backwards": ("shading.glsl", "vec3 toLight = lightPosition - shadowOrigin;",
                        "vec3 toLight = shadowOrigin - lightPosition;"),
    # The plane equation's sign: the floor seen at the wrong distance.
    "plane_sign": ("plane.glsl", "(plane.offset - dot(plane.normal, ray.origin))",
                   "(dot(plane.normal, ray.origin) - plane.offset)"),
}


@pytest.mark.parametrize("mistake", MISTAKES)
def test_check_rejects_a_planted_mistake(tmp_path, mistake):
    file_name, right, wrong = MISTAKES[mistake]
    shaders = copy_shaders("05", tmp_path)
    source = shaders / file_name
    assert right in source.read_text()
    source.write_text(source.read_text().replace(right, wrong))
    png = render("05", tmp_path / "wrong.png", "--width", WIDTH, "--height", HEIGHT,
                 "--shader-dir", shaders)
    with pytest.raises(AssertionError):
        assert_images_agree(png, reference_png())


def test_unknown_scene_is_exit_2_with_the_names(tmp_path):
    result = run_chapter("05", "--headless", "--out", tmp_path / "x.png", "--scene", "cube")
    assert result.returncode == 2
    assert "unknown scene 'cube'" in result.stderr
    assert all(name in result.stderr for name in SCENES)
    assert list(tmp_path.iterdir()) == []
