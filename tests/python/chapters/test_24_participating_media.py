"""Chapter 24: participating media, checked with closed forms, a furnace, chi-square and
Mitsuba 3's volumetric path tracer (book/docs/maintainers.md).

- media.glsl on the GPU (tests/data/media/phase_probe.comp through tests/cpp/bsdf_probe)
  against python_prototypes/media.py: the Henyey-Greenstein phase function value by
  value, its sampling by chi-square, and the free flight's weight, whose mean over
  many flights is the closed form (the transmittance to the surface, or sigma_s times
  the transmittance integrated up to it).
- Beer-Lambert through a ball of absorbing medium in front of a glowing wall: every
  pixel's mean is the wall's radiance times exp(-sigma_t chord), the chord through the
  ball along the pixel's rays (numpy, 8 x 8 rays a pixel).
- A white furnace: a ball of medium that only scatters (albedo 1), in an environment of
  radiance 1: it vanishes, whatever its phase function, density or colour.
- Mitsuba 3 `volpath`, region by region within 2%: fog around the camera, a ball of
  smoke behind an invisible boundary, and tinted glass (an absorbing medium inside
  dielectric spheres).
- Planted bugs, each failing the check that catches it.
- Bad media: exit code 3 at the line (a grid in this chapter, too many media, an open
  mesh given an interior); chapter 18 refuses a scene with media.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import numpy as np
import path_checks
import pytest
from conftest import ROOT, run_chapter
from path_checks import SIGMAS, mean_and_error

from python_prototypes import chi_square, media
from python_prototypes import mitsuba_reference as mr
from python_prototypes import scene_io, volumes
from python_prototypes.pfm import write_pfm

pytestmark = pytest.mark.filterwarnings("ignore::RuntimeWarning")

PROBE_SHADER = ROOT / "tests" / "data" / "media" / "phase_probe.comp"
SCENES = ROOT / "assets" / "scenes"
MESH_FOLDERS = [ROOT / "build" / "assets"]

# The planted bugs: (file, the right text, the wrong one). Each must fail its check.
NO_SHADOW_TRANSMITTANCE = (
    "path.comp", "kept *= transmittanceThrough(media[medium], blocked ? hit.t : distance);",
    "kept *= 1.0;")
PHASE_NOT_CANCELLED = (  # the sampled direction weighted as if drawn uniformly
    "path.comp", "directionPdf = henyeyGreenstein(dot(ray.direction, next), here.g);",
    "directionPdf = henyeyGreenstein(dot(ray.direction, next), here.g);"
    " throughput *= 4.0 * PI * directionPdf;")
BOUNDARY_BLOCKS_SHADOWS = (
    "path.comp", "if (materials[hit.material].kind != MATERIAL_BOUNDARY) return vec3(0.0);",
    "return vec3(0.0);")
ONE_CHANNELS_DENSITY = (  # the distance drawn from a random channel, divided by green's
    "media.glsl", "float pdf = (density.r + density.g + density.b) / 3.0;",
    "float pdf = density.g;")
DISTANCE_KEPT_BY_SUBTRACTION = (  # each crossing moves the origin off the line: overshoots
    "path.comp", "distance = forever ? FOREVER : dot(end - ray.origin, ray.direction);",
    "distance -= hit.t;")
PHASE_BACKWARDS = ("media.glsl", "cosTheta = (1.0 + g * g - s * s) / (2.0 * g);",
                   "cosTheta = -(1.0 + g * g - s * s) / (2.0 * g);")


def shaders_with(tmp_path, bug=None):
    return path_checks.shaders_with_bug("24", tmp_path, bug, [PROBE_SHADER])


def path_trace(tmp_path, name, *args, shader_dir=None) -> np.ndarray:
    extra = ["--shader-dir", shader_dir] if shader_dir else []
    return path_checks.path_trace("24", tmp_path, name, *extra, *args)


# --- media.glsl on the GPU against numpy --------------------------------------------------

def run_probe(shader_dir, queries, tmp_path) -> np.ndarray:
    return path_checks.run_bsdf_probe(PROBE_SHADER.name, shader_dir, queries, tmp_path)


def probe_queries(travel, g, u, given, sigma_a=(0, 0, 0), sigma_s=(0, 0, 0), surface=1.0):
    count = len(travel)
    q = np.zeros((count, 20))
    q[:, 0:3], q[:, 3] = travel, g
    q[:, 4:8] = u
    q[:, 8:11] = given
    q[:, 12:15], q[:, 15] = sigma_a, surface
    q[:, 16:19] = sigma_s
    return q


def unit_vectors(rng, count):
    v = rng.normal(size=(count, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


@pytest.mark.parametrize("g", [-0.7, 0.0, 0.3, 0.9])
def test_gpu_phase_function_is_the_prototypes(tmp_path, g):
    rng = np.random.default_rng(4)
    travel, given = unit_vectors(rng, 4096), unit_vectors(rng, 4096)
    answers = run_probe(shaders_with(tmp_path), probe_queries(travel, g, rng.random((4096, 4)),
                                                              given), tmp_path)
    expected = media.henyey_greenstein(np.sum(travel * given, axis=1), g)
    assert np.allclose(answers[:, 4], expected, rtol=2e-5, atol=1e-7)
    # The sampled directions are unit vectors, and the phase there is the prototype's.
    sampled = answers[:, 0:3]
    assert np.allclose(np.linalg.norm(sampled, axis=1), 1.0, atol=1e-5)
    assert np.allclose(answers[:, 3], media.henyey_greenstein(np.sum(travel * sampled, axis=1),
                                                              g), rtol=1e-4, atol=1e-6)


def gpu_phase_chi_square(shader_dir, tmp_path, g, samples=200_000):
    travel = np.array([0.0, 0.0, 1.0])

    def sample_directions(rng, count):
        queries = probe_queries(np.tile(travel, (count, 1)), g, rng.random((count, 4)),
                                np.tile(travel, (count, 1)))
        return run_probe(shader_dir, queries, tmp_path)[:, 0:3], np.ones(count, dtype=bool)

    return chi_square.chi_square_test(sample_directions,
                                      lambda d: media.henyey_greenstein(d[..., 2], g),
                                      samples, seed=7, test_count=3)


@pytest.mark.parametrize("g", [-0.5, 0.0, 0.8])
def test_gpu_phase_samples_pass_chi_square(tmp_path, g):
    result = gpu_phase_chi_square(shaders_with(tmp_path), tmp_path, g)
    assert result.accepted, str(result)


def test_backwards_phase_sampling_fails_chi_square(tmp_path):
    result = gpu_phase_chi_square(shaders_with(tmp_path, PHASE_BACKWARDS), tmp_path, 0.8)
    assert not result.accepted, str(result)


def free_flight_means(shader_dir, tmp_path, sigma_a, sigma_s, surface, count=200_000):
    """The mean weight of flights that reach the surface (each counted 0 otherwise),
    and of those that scatter: estimates of T(surface) and of the light scattered on
    the way, sigma_s (1 - T) / sigma_t; with their standard errors."""
    rng = np.random.default_rng(11)
    travel = np.tile([0.0, 0.0, 1.0], (count, 1))
    queries = probe_queries(travel, 0.0, rng.random((count, 4)), travel, sigma_a, sigma_s,
                            surface)
    answers = run_probe(shader_dir, queries, tmp_path)
    scattered = answers[:, 8] > 0.5
    weights = answers[:, 12:15]
    return (mean_and_error(np.where(scattered[:, None], 0.0, weights)),
            mean_and_error(np.where(scattered[:, None], weights, 0.0)), answers[0, 16:19])


CHROMATIC = ((0.1, 0.4, 1.5), (0.9, 0.6, 2.5), 0.8)  # sigma_a, sigma_s, surface distance


def assert_free_flights_unbiased(shader_dir, tmp_path):
    sigma_a, sigma_s, surface = CHROMATIC
    (through, through_error), (scatter, scatter_error), transmittance = free_flight_means(
        shader_dir, tmp_path, sigma_a, sigma_s, surface)
    sigma_t = np.add(sigma_a, sigma_s)
    expected_through = np.exp(-sigma_t * surface)
    assert np.allclose(transmittance, expected_through, rtol=1e-5)
    assert np.all(np.abs(through - expected_through) < SIGMAS * through_error + 1e-4)
    expected_scatter = np.array(sigma_s) * (1 - expected_through) / sigma_t
    assert np.all(np.abs(scatter - expected_scatter) < SIGMAS * scatter_error + 1e-4), \
        (scatter, expected_scatter, scatter_error)


def test_free_flights_are_unbiased_in_every_channel(tmp_path):
    assert_free_flights_unbiased(shaders_with(tmp_path), tmp_path)


def test_one_channels_density_for_all_fails_the_closed_form(tmp_path):
    with pytest.raises(AssertionError):
        assert_free_flights_unbiased(shaders_with(tmp_path, ONE_CHANNELS_DENSITY), tmp_path)


# --- Beer-Lambert through a ball ------------------------------------------------------------

BALL = "medium ink homogeneous sigma_a {a} sigma_s 0 0 0\n"
ABSORBING = (0.4, 1.2, 3.0)
WALL = (2.0, 3.0, 4.0)


def absorbing_ball_scene(folder):
    path = folder / "ball.scene"
    path.write_text(
        "camera eye 0 0 4 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.025\n"
        + BALL.format(a=" ".join(map(str, ABSORBING)))
        + "material edge boundary\n"
        f"material wall albedo 0 0 0 emission {' '.join(map(str, WALL))}\n"
        "quad -3 -3 -1  6 0 0  0 6 0 wall name wall\n"
        "sphere 0 0 0 0.8 edge interior ink name ball\n")
    return path


def expected_through_ball(scene_file, size, subsamples=8):
    """Each pixel's mean, the wall's radiance times exp(-sigma_a chord) averaged over
    subsamples x subsamples rays across the pixel; and which pixels the ball covers
    wholly (every ray crosses it) and which it misses."""
    scene = scene_io.load_scene(scene_file)
    directions = mr.ray_directions(scene.camera, size, size, subsamples)
    eye = np.array(scene.camera.eye)
    b = directions @ eye  # |eye + t d|^2 = r^2: t^2 + 2 b t + |eye|^2 - r^2 = 0
    discriminant = b * b - (eye @ eye - 0.8 ** 2)
    chord = 2.0 * np.sqrt(np.maximum(discriminant, 0.0))
    kept = np.exp(-chord[..., None] * np.array(ABSORBING)) * np.array(WALL)
    by_pixel = chord.reshape(size, subsamples, size, subsamples)
    # Covered: every ray crosses at least half the ball's width, away from its edge,
    # where the chord changes too fast across a pixel for its 8 x 8 rays to stand for it.
    return (kept.reshape(size, subsamples, size, subsamples, 3).mean(axis=(1, 3)),
            by_pixel.min(axis=(1, 3)) > 0.8, by_pixel.max(axis=(1, 3)) == 0)


@pytest.mark.windows
def test_light_through_an_absorbing_ball_follows_beer_lambert(tmp_path):
    scene_file = absorbing_ball_scene(tmp_path)
    image = path_trace(tmp_path, "ball", "--scene", scene_file, "--width", 48, "--height", 48,
                       "--spp", 1024, "--depth", 1)
    expected, covered, missed = expected_through_ball(scene_file, 48)
    assert covered.sum() > 100 and missed.sum() > 1000
    # Where the ball covers a pixel, the chord changes little across it: each pixel's
    # mean within 2% (4 standard errors of 1024 rays spread over the pixel). Where it
    # misses, the wall itself. Over all pixels, the mean.
    assert np.allclose(image[covered], expected[covered], rtol=0.02)
    assert np.array_equal(image[missed], expected[missed])
    assert np.allclose(image.mean(axis=(0, 1)), expected.mean(axis=(0, 1)), rtol=0.002)


# The floor under the ball, in a 32 x 32 picture of the smoke room: its light comes
# through the ball.
UNDER_THE_BALL = (slice(24, 32), slice(8, 24))


def lit_with_and_without_an_empty_boundary(tmp_path, shader_dir=None):
    """The smoke room direct-lit twice: its ball a boundary around a medium of nothing,
    and no ball at all. Returns the difference, pixel by pixel."""
    text = (SCENES / "cornell_smoke.scene").read_text()
    empty = text.replace("sigma_a 0.3 0.3 0.3 sigma_s 1.5 4 9 g 0.5", "sigma_a 0 0 0 sigma_s 0 0 0")
    assert empty != text
    (tmp_path / "empty.scene").write_text(empty)
    (tmp_path / "none.scene").write_text(
        "\n".join(line for line in text.splitlines()
                  if not line.startswith(("sphere", "medium", "material edge"))) + "\n")
    args = ("--width", 32, "--height", 32, "--spp", 1024, "--direct")
    through = path_trace(tmp_path, "empty", "--scene", tmp_path / "empty.scene", *args,
                         shader_dir=shader_dir)
    alone = path_trace(tmp_path, "none", "--scene", tmp_path / "none.scene", *args,
                       shader_dir=shader_dir)
    return through - alone


def test_an_empty_boundary_changes_nothing(tmp_path):
    """The room lit through an empty boundary exactly as without it: over the picture,
    and on the floor under the ball."""
    difference = lit_with_and_without_an_empty_boundary(tmp_path)
    for pixels in (difference, difference[UNDER_THE_BALL]):
        mean, error = mean_and_error(pixels.reshape(-1, 3))
        assert np.all(np.abs(mean) < SIGMAS * error + 1e-4), (mean, error)


def test_shadow_distance_kept_by_subtraction_fails(tmp_path):
    """A shadow ray that keeps its distance by subtracting each hit's t, while every
    crossing moves its origin off the line, runs past its stop after two crossings and
    meets the light itself: half the floor's light under the ball is lost."""
    shader_dir = shaders_with(tmp_path, DISTANCE_KEPT_BY_SUBTRACTION)
    difference = lit_with_and_without_an_empty_boundary(tmp_path, shader_dir)
    mean, error = mean_and_error(difference[UNDER_THE_BALL].reshape(-1, 3))
    assert np.all(mean < -SIGMAS * error - 1e-4), (mean, error)


# --- The white furnace ---------------------------------------------------------------------

def furnace_scene(folder, g, sigma_s):
    sky = folder / "white.pfm"
    write_pfm(sky, np.ones((8, 16, 3), dtype=np.float32))
    path = folder / "furnace.scene"
    path.write_text(
        "camera eye 0 0 3 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.025\n"
        f"medium cloud homogeneous sigma_a 0 0 0 sigma_s {sigma_s} g {g}\n"
        "material edge boundary\n"
        "sphere 0 0 0 0.7 edge interior cloud name cloud\n"
        f"environment {sky.name}\n")
    return path


def assert_furnace_white(image):
    """1 everywhere: over the image, and in each 8 x 8 block, within the noise (the
    standard error from the spread of the block's own pixels) and 2e-3."""
    path_checks.assert_mean_everywhere(image, 1.0, margin=2e-3)


@pytest.mark.parametrize("g, sigma_s", [(0.0, "2 2 2"), (0.7, "1 3 6"), (-0.4, "4 4 4")])
def test_a_scattering_ball_vanishes_in_the_furnace(tmp_path, g, sigma_s):
    image = path_trace(tmp_path, "furnace", "--scene", furnace_scene(tmp_path, g, sigma_s),
                       "--width", 32, "--height", 32, "--spp", 256, "--depth", 200)
    assert_furnace_white(image)


@pytest.mark.parametrize("bug", [NO_SHADOW_TRANSMITTANCE, PHASE_NOT_CANCELLED,
                                 BOUNDARY_BLOCKS_SHADOWS],
                         ids=["no_shadow_transmittance", "phase_not_cancelled",
                              "boundary_blocks_shadows"])
def test_planted_bug_fails_the_furnace(tmp_path, bug):
    image = path_trace(tmp_path, "furnace", "--scene", furnace_scene(tmp_path, 0.7, "1 3 6"),
                       "--width", 32, "--height", 32, "--spp", 256, "--depth", 200,
                       shader_dir=shaders_with(tmp_path, bug))
    with pytest.raises(AssertionError):
        assert_furnace_white(image)


# --- Mitsuba 3's volumetric path tracer -----------------------------------------------------

MITSUBA_SCENES = {  # scene: (our spp, Mitsuba's spp, the regions that must be compared)
    "cornell_fog": (512, 1024, {"back", "floor", "small_box", "large_box"}),
    "cornell_smoke": (512, 1024, {"smoke", "back", "floor"}),
    "cornell_tinted_glass": (1024, 2048, {"smooth_glass", "rough_glass", "back"}),
}


@pytest.mark.parametrize("name", MITSUBA_SCENES)
def test_media_agree_with_mitsuba_volpath(tmp_path, name):
    spp, mitsuba_spp, regions = MITSUBA_SCENES[name]
    scene_file = SCENES / f"{name}.scene"
    reference = path_checks.mitsuba_regions(scene_file, mitsuba_spp, 64, MESH_FOLDERS)
    ours = path_trace(tmp_path, name, "--scene", scene_file, "--width", 64, "--height", 64,
                      "--spp", spp)
    compared = path_checks.assert_regions_within_two_percent(ours, reference, MESH_FOLDERS)
    assert regions <= set(compared), compared


def test_boundary_treated_as_opaque_fails_mitsuba(tmp_path):
    scene_file = SCENES / "cornell_smoke.scene"
    reference = path_checks.mitsuba_regions(scene_file, 1024, 64, MESH_FOLDERS)
    wrong = ("path.comp", "if (material.kind == MATERIAL_BOUNDARY) {", "if (false) {")
    ours = path_trace(tmp_path, "opaque", "--scene", scene_file, "--width", 64, "--height", 64,
                      "--spp", 512, shader_dir=shaders_with(tmp_path, wrong))
    with pytest.raises(AssertionError):
        path_checks.assert_regions_within_two_percent(ours, reference, MESH_FOLDERS)


# --- Bad media ------------------------------------------------------------------------------

def tiny_grid(path):
    """A 1 x 1 x 1 .vol grid (common/course/volume_grid.h): density 1 in a unit box."""
    volumes.write_vol(path, volumes.Grid(np.ones((1, 1, 1), np.float32),
                                         np.array([-0.5] * 3), np.array([0.5] * 3)))


@pytest.mark.parametrize("lines, line, said", [
    ("medium smoke grid tiny.vol albedo 1 1 1\n", 3,
     "medium 'smoke' is a grid: this program renders homogeneous media only; grids come "
     "in chapter 25"),
    ("".join(f"medium m{i} homogeneous sigma_a 0 0 0 sigma_s 1 1 1\n" for i in range(9)),
     11, "more than 8 media: this program's table holds 8"),
    ("medium fog homogeneous sigma_a 0 0 0 sigma_s 1 1 1\n"
     "mesh teapot.obj edge interior fog\n", 4,
     "is not closed"),
])
def test_media_mistakes_are_exit_3_at_their_line(tmp_path, lines, line, said):
    tiny_grid(tmp_path / "tiny.vol")
    (tmp_path / "teapot.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    scene = tmp_path / "bad.scene"
    scene.write_text("camera eye 0 0 4 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.025\n"
                     "material edge boundary\n"
                     + lines +
                     "material lamp albedo 0 0 0 emission 1 1 1\n"
                     "sphere 0 3 0 0.5 lamp\n")
    result = run_chapter("24", "--scene", scene, "--out", tmp_path / "x.png")
    assert result.returncode == 3, result.stderr
    assert f"{scene}:{line}: " in result.stderr and said in result.stderr, result.stderr


def test_chapter_18_refuses_media_and_says_where_they_come(tmp_path):
    result = run_chapter("18", "--scene", SCENES / "cornell_fog.scene", "--out",
                         tmp_path / "x.png")
    assert result.returncode == 3, result.stderr
    assert "renders no participating media" in result.stderr
    assert "media come in chapter 24" in result.stderr

