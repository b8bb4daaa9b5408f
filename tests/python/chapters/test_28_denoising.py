"""Chapter 28: denoising, checked against Mitsuba 3, against the path tracer's own raw
picture and against Intel's Open Image Denoise (book/docs/maintainers.md).

- Quality, on four scenes of different character (the Cornell box, the teapot, glass
  spheres with their caustics, the textured room seen through a lens): 8 samples a
  pixel, denoised, are closer to Mitsuba 3's render at 4 096 samples than the raw
  picture at 64 samples is (the issue's measure: mean((x - ref)^2 / (ref^2 + 0.01))).
  Beside OIDN fed the same colour, albedo and normal: within 1.75 times its error (the
  issue's target is 1.5, which the bench measures at 16 384 samples: 0.88 to
  1.46 times, the page's table).
- No light lost: a filter moves noise, not light. Each region's mean (the pixels that
  see one named shape) over the seeds stays within 2% of the reference's, or within the
  noise of the raw picture's mean from the same samples where that is larger (glass).
- A correct filter written another way (a Gaussian kernel instead of the B3 spline's)
  passes; planted mistakes fail: the weights' sum not divided out, the albedo not put
  back.
- The filter is the numpy prototype's (python_prototypes/denoise.py): given what the
  chapter started from (--aux-out: the features, the illumination and its variance, the
  light seen directly), the prototype's a-trous filter gives the chapter's picture
  within float rounding, on each scene. The three planted mistakes fail it, and so does
  a step not doubled from pass to pass (a weaker filter that still beats raw 64).
- The features: --aux-out writes the albedo, normal and depth the filter is guided by;
  on the room's walls (away from edges) they are what the scene says.
- Bad input: an unknown --denoise, or an --aux-out into a folder that does not exist,
  are exit code 2 before anything is rendered.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import numpy as np
import path_checks
import pytest
from conftest import ROOT, region_standard_error, run_chapter
from path_checks import SIGMAS

from course_tools import mitsuba_cache
from course_tools.bench import denoise as bench_denoise
from python_prototypes import denoise, mitsuba_reference, scene_io
from python_prototypes.denoise import relative_mse
from python_prototypes.pfm import read_pfm

SCENE_FOLDER = ROOT / "assets" / "scenes"
MESH_FOLDERS = [ROOT / "build" / "assets"]
SCENES = ("cornell_box", "cornell_teapot", "cornell_glass", "lens_textures")
SIZE = 160
SEEDS = (1, 2)
REFERENCE_SPP = 4096
# Ours against OIDN at 8 samples (the target is 1.5; measured 0.88 to 1.46: a
# margin for another Mesa's pictures and this check's reference at 4 096 samples).
MOST_AGAINST_OIDN = 1.75

# The planted bugs: (file, the right text, the wrong one). Each must fail its check.
NOT_NORMALISED = ("denoise.comp",
                  "    return vec4(sum / weights, variance / (weights * weights));\n",
                  "    return vec4(sum, variance);\n")
ALBEDO_NOT_BACK = ("denoise.comp", "filtered[index].rgb * albedoAt(index) +",
                   "filtered[index].rgb +")
STEP_NOT_DOUBLED = ("denoise.comp", "ivec2(x, y) * int(tapStep)", "ivec2(x, y)")
# A correct filter written another way: a sampled Gaussian (sigma 1) for the B3 spline.
GAUSSIAN_KERNEL = ("denoise.comp",
                   "float[5](1.0 / 16.0, 1.0 / 4.0, 3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0)",
                   "float[5](0.054, 0.244, 0.403, 0.244, 0.054)")


def load(scene: str):
    return scene_io.load_scene(str(SCENE_FOLDER / f"{scene}.scene"),
                               [str(f) for f in MESH_FOLDERS])


@pytest.fixture(scope="module")
def references():
    """Mitsuba 3's render of each scene, SIZE x SIZE at 4 096 samples a pixel (kept once
    made), made as a test asks for it."""
    made = {}

    def reference(scene: str):
        if scene not in made:
            made[scene] = path_checks.kept_mitsuba(load(scene), SIZE, SIZE, REFERENCE_SPP,
                                                   6, seed=0, variant="llvm_ad_rgb")
        return made[scene]
    return reference


def render(tmp_path, scene, label, spp, denoise, seed, *extra):
    return path_checks.path_trace("28", tmp_path, f"{scene}_{label}_{seed}", "--scene", scene,
                                  "--width", SIZE, "--height", SIZE, "--spp", spp,
                                  "--denoise", denoise, "--seed", seed, *extra)


def assert_light_kept(scene, denoised, raw, reference):
    """Each region's brightness, the denoised pictures' mean against the reference's:
    within 2%, or SIGMAS standard errors of the raw pictures' mean (the same samples,
    unfiltered) where those are wider."""
    masks = mitsuba_cache.kept_region_masks(load(scene), SIZE, SIZE)
    for region, mask in masks.items():
        if mask.sum() < 20:
            continue
        theirs = reference[mask].mean()
        relative = denoised[mask].mean() / theirs - 1
        error = region_standard_error(raw[mask], reference[mask]).mean() / theirs
        print(f"{scene} {region}: {relative:+.2%} (raw's standard error {error:.2%})")
        assert abs(relative) < max(0.02, SIGMAS * error), (region, relative, error)


def assert_denoised_well(tmp_path, scene, reference, label="atrous", shader_dir=None):
    """8 samples denoised beat 64 raw, and every region keeps its light. Returns the
    denoised error."""
    extra = ["--shader-dir", shader_dir] if shader_dir else []
    denoised = [render(tmp_path, scene, label, 8, "atrous", seed, *extra) for seed in SEEDS]
    raw = [render(tmp_path, scene, "raw", 8, "none", seed) for seed in SEEDS]
    error = np.mean([relative_mse(image, reference) for image in denoised])
    raw_64 = relative_mse(render(tmp_path, scene, "raw64", 64, "none", SEEDS[0]), reference)
    print(f"{scene} {label}: denoised at 8 spp {error:.5f}, raw at 64 spp {raw_64:.5f}")
    assert error < raw_64, f"denoised at 8 spp {error:.5f}, raw at 64 spp {raw_64:.5f}"
    assert_light_kept(scene, np.mean(denoised, axis=0), np.mean(raw, axis=0), reference)
    return error


@pytest.mark.parametrize("scene", SCENES)
def test_eight_samples_denoised_beat_sixty_four_raw_and_keep_the_light(tmp_path, references,
                                                                        scene):
    assert_denoised_well(tmp_path, scene, references(scene))


@pytest.mark.parametrize("scene", SCENES)
def test_within_reach_of_open_image_denoise(tmp_path, references, scene):
    """OIDN (a trained network) on the same raw colour, albedo and normal: ours within
    MOST_AGAINST_OIDN times its error."""
    pytest.importorskip("pyoidn", reason="pip install -r requirements/test.txt")
    reference = references(scene)
    ours, theirs = [], []
    for seed in SEEDS:
        prefix = tmp_path / f"{scene}_{seed}"
        result = run_chapter("28", "--headless", "--scene", scene, "--width", SIZE,
                             "--height", SIZE, "--spp", 8, "--seed", seed, "--denoise", "none",
                             "--out", f"{prefix}.pfm", "--aux-out", prefix)
        assert result.returncode == 0, result.stderr
        cleaned, _ = bench_denoise.oidn(prefix)
        theirs.append(relative_mse(cleaned, reference))
        ours.append(relative_mse(render(tmp_path, scene, "atrous", 8, "atrous", seed),
                                 reference))
    print(f"{scene}: ours {np.mean(ours):.5f}, OIDN {np.mean(theirs):.5f}")
    assert np.mean(ours) < MOST_AGAINST_OIDN * np.mean(theirs)


def test_a_gaussian_kernel_instead_of_the_spline_passes(tmp_path, references):
    shader_dir = path_checks.shaders_with_bug("28", tmp_path, GAUSSIAN_KERNEL)
    assert_denoised_well(tmp_path, "cornell_box", references("cornell_box"),
                         "gaussian_kernel", shader_dir)


@pytest.mark.parametrize("bug", [NOT_NORMALISED, ALBEDO_NOT_BACK],
                         ids=["not_normalised", "albedo_not_back"])
def test_planted_bug_fails(tmp_path, references, bug):
    shader_dir = path_checks.shaders_with_bug("28", tmp_path, bug)
    with pytest.raises(AssertionError):
        assert_denoised_well(tmp_path, "cornell_box", references("cornell_box"), "bug",
                             shader_dir)


def assert_filter_is_the_prototypes(tmp_path, scene, shader_dir=None):
    """The chapter's denoised picture (64 x 64, 8 spp) against the prototype's filter of
    the chapter's own starting point: float32 against float64, so 99% of the pixels
    within 3e-3 of each other and the mean difference within 3e-4 (where a pixel's two
    depth differences are nearly equal and opposite, rounding may pick the other)."""
    prefix = tmp_path / scene
    extra = ["--shader-dir", shader_dir] if shader_dir else []
    result = run_chapter("28", "--headless", "--scene", scene, "--width", 64, "--height", 64,
                         "--spp", 8, "--out", f"{prefix}.pfm", "--aux-out", prefix, *extra)
    assert result.returncode == 0, result.stderr

    def aux(name):
        return read_pfm(f"{prefix}_{name}.pfm").astype(np.float64)

    features = denoise.Features(aux("albedo"), aux("normal") * 2.0 - 1.0, aux("depth")[..., 0],
                                aux("depth_spread")[..., 0])
    expected = denoise.atrous(None, aux("variance")[..., 0], features,
                              illumination=aux("illumination"), emitted=aux("emitted"),
                              samples=8)
    ours = read_pfm(f"{prefix}.pfm").astype(np.float64)
    apart = np.abs(ours - expected) / (np.abs(expected) + 1e-3)
    print(f"{scene}: 99% within {np.quantile(apart, 0.99):.1e}, mean {apart.mean():.1e}")
    assert np.quantile(apart, 0.99) < 3e-3 and apart.mean() < 3e-4


@pytest.mark.parametrize("scene", SCENES)
def test_the_filter_is_the_prototypes(tmp_path, scene):
    assert_filter_is_the_prototypes(tmp_path, scene)


@pytest.mark.parametrize("bug", [NOT_NORMALISED, ALBEDO_NOT_BACK, STEP_NOT_DOUBLED],
                         ids=["not_normalised", "albedo_not_back", "step_not_doubled"])
def test_planted_bug_is_not_the_prototypes_filter(tmp_path, bug):
    shader_dir = path_checks.shaders_with_bug("28", tmp_path, bug)
    with pytest.raises(AssertionError):
        assert_filter_is_the_prototypes(tmp_path, "cornell_box", shader_dir)


@pytest.mark.windows
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
    scene = load("cornell_box")
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
