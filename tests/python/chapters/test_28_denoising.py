"""Chapter 28: denoising, checked against Mitsuba 3 and against the path tracer's own
raw picture (book/docs/maintainers.md).

- Quality: the Cornell box at 8 samples a pixel, denoised, is closer to Mitsuba 3's
  render at 4 096 samples than the raw picture at 64 samples is (the error measure of
  the issue: mean((x - ref)^2 / (ref^2 + 0.01))), over several seeds.
- No light lost: a filter moves noise, not light. The denoised picture's mean over the
  seeds stays within 2% of the reference's, and so do its 24 x 24 blocks' means (the
  raw picture's, from the same samples, stand beside them).
- A correct filter written another way (a Gaussian kernel instead of the B3 spline's)
  passes; planted mistakes fail: the weights' sum not divided out, the albedo not put
  back, the taps' step not doubled from pass to pass.
- The features: --aux-out writes the albedo, normal and depth the filter is guided by;
  on the room's walls (away from edges) they are what the scene says.
- Bad input: an unknown --denoise, or an --aux-out into a folder that does not exist,
  are exit code 2 before anything is rendered.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import numpy as np
import path_checks
import pytest
from conftest import ROOT, run_chapter

from python_prototypes import mitsuba_reference, scene_io
from python_prototypes.pfm import read_pfm

SCENES = ROOT / "assets" / "scenes"
SIZE = 96
BLOCK = 24
SEEDS = (1, 2, 3, 4)
REFERENCE_SPP = 4096

# The planted bugs: (file, the right text, the wrong one). Each must fail its check.
NOT_NORMALISED = ("denoise.comp",
                  "    return vec4(sum / weights, variance / (weights * weights));\n",
                  "    return vec4(sum, variance);\n")
ALBEDO_NOT_BACK = ("denoise.comp", "filtered[index].rgb * albedo + ", "filtered[index].rgb + ")
STEP_NOT_DOUBLED = ("denoise.comp", "ivec2(x, y) * int(tapStep)", "ivec2(x, y)")
# A correct filter written another way: a sampled Gaussian (sigma 1) for the B3 spline.
GAUSSIAN_KERNEL = ("denoise.comp",
                   "float[5](1.0 / 16.0, 1.0 / 4.0, 3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0)",
                   "float[5](0.054, 0.244, 0.403, 0.244, 0.054)")


def relative_mse(image, reference) -> float:
    return float(np.mean((image - reference) ** 2 / (reference ** 2 + 0.01)))


def block_means(image) -> np.ndarray:
    return image.reshape(SIZE // BLOCK, BLOCK, SIZE // BLOCK, BLOCK, 3).mean(axis=(1, 3))


@pytest.fixture(scope="module")
def reference():
    """Mitsuba 3's Cornell box, 96 x 96 at 4 096 samples a pixel (kept once made)."""
    scene = scene_io.load_scene(str(SCENES / "cornell_box.scene"), [])
    return path_checks.kept_mitsuba(scene, SIZE, SIZE, REFERENCE_SPP, 6, seed=0,
                                    variant="llvm_ad_rgb")


def render(tmp_path, label, spp, denoise, seed, shader_dir=None):
    extra = ["--shader-dir", shader_dir] if shader_dir else []
    return path_checks.path_trace("28", tmp_path, f"{label}_{seed}", "--scene", "cornell_box",
                                  "--width", SIZE, "--height", SIZE, "--spp", spp,
                                  "--denoise", denoise, "--seed", seed, *extra)


def denoised_error(tmp_path, reference, label, shader_dir=None) -> tuple[float, list]:
    images = [render(tmp_path, label, 8, "atrous", seed, shader_dir) for seed in SEEDS]
    return np.mean([relative_mse(image, reference) for image in images]), images


def assert_denoised_well(tmp_path, reference, label, shader_dir=None):
    """8 samples denoised beat 64 raw, and the light is all there (whole and by block)."""
    error, images = denoised_error(tmp_path, reference, label, shader_dir)
    raw_64 = np.mean([relative_mse(render(tmp_path, "raw64", 64, "none", seed), reference)
                      for seed in SEEDS[:2]])
    assert error < raw_64, f"denoised at 8 spp {error:.5f}, raw at 64 spp {raw_64:.5f}"
    mean = np.mean(images, axis=0)
    assert abs(mean.mean() / reference.mean() - 1) < 0.02
    shift = block_means(mean) / block_means(reference) - 1
    assert np.abs(shift).max() < 0.05, np.round(shift.mean(axis=-1), 3)


def test_eight_samples_denoised_beat_sixty_four_raw_and_keep_the_light(tmp_path, reference):
    assert_denoised_well(tmp_path, reference, "atrous")


def test_a_gaussian_kernel_instead_of_the_spline_passes(tmp_path, reference):
    shader_dir = path_checks.shaders_with_bug("28", tmp_path, GAUSSIAN_KERNEL)
    assert_denoised_well(tmp_path, reference, "gaussian_kernel", shader_dir)


@pytest.mark.parametrize("bug", [NOT_NORMALISED, ALBEDO_NOT_BACK, STEP_NOT_DOUBLED],
                         ids=["not_normalised", "albedo_not_back", "step_not_doubled"])
def test_planted_bug_fails(tmp_path, reference, bug):
    shader_dir = path_checks.shaders_with_bug("28", tmp_path, bug)
    with pytest.raises(AssertionError):
        assert_denoised_well(tmp_path, reference, "bug", shader_dir)


def test_the_features_are_what_the_scene_says(tmp_path):
    """Away from edges every sample of a pixel meets the same wall: its albedo is the
    wall's, its normal the wall's, its depth the distance along the pixel's ray (within
    the spread of the pixel's samples)."""
    prefix = tmp_path / "aux"
    result = run_chapter("28", "--headless", "--scene", "cornell_box", "--width", SIZE,
                         "--height", SIZE, "--spp", 4, "--out", tmp_path / "out.pfm",
                         "--aux-out", prefix)
    assert result.returncode == 0, result.stderr
    albedo = read_pfm(f"{prefix}_albedo.pfm")
    normal = read_pfm(f"{prefix}_normal.pfm") * 2.0 - 1.0
    depth = read_pfm(f"{prefix}_depth.pfm")[..., 0]
    scene = scene_io.load_scene(str(SCENES / "cornell_box.scene"), [])
    materials = scene.materials
    left = (SIZE // 2, 3)  # the red wall, seen at the image's left edge
    assert np.allclose(albedo[left], materials["red"].albedo, atol=1e-6)
    assert normal[left][0] > 0.999  # facing the room: +x
    back = (SIZE // 3, SIZE // 2)  # the back wall, straight ahead
    assert np.allclose(albedo[back], materials["white"].albedo, atol=1e-6)
    assert normal[back][2] > 0.999
    direction = mitsuba_reference.ray_directions(scene.camera, SIZE, SIZE)[back]
    direction = direction / np.linalg.norm(direction)
    to_back_wall = (-1.0 - scene.camera.eye[2]) / direction[2]  # the wall z = -1
    assert depth[back] == pytest.approx(to_back_wall, rel=0.01)
    assert read_pfm(f"{prefix}_variance.pfm")[back][0] > 0.0


@pytest.mark.parametrize("arguments,words", [
    (["--denoise", "median"], "--denoise"),
    (["--aux-out", "no/such/folder/aux"], "no/such/folder"),
])
def test_bad_options_are_exit_2(tmp_path, arguments, words):
    result = run_chapter("28", "--headless", "--out", tmp_path / "out.png", "--width", 16,
                         "--height", 16, "--spp", 1, *arguments)
    assert result.returncode == 2 and words in result.stderr, result.stderr
