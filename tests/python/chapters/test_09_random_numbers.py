"""Chapter 09: random numbers on the GPU. The generator must be python_prototypes/rng.py
bit for bit (both seedings, also after several dispatches); its output must pass the
statistics that rng.py defines (and the naive seeding must fail the neighbour test);
a fixed seed must reproduce the image byte for byte however the dispatches are grouped;
and the anti-aliased teapot must agree with a supersampled numpy reference within its
Monte Carlo error, while a planted mistake (no jitter) is rejected."""

import numpy as np
import pytest

from python_prototypes import obj_io
from python_prototypes.reference import mesh_scene
from python_prototypes import rng
from conftest import ROOT, copy_shaders, read_pfm, render, run_chapter

TEAPOT = ROOT / "build" / "assets" / "meshes" / "teapot_552.obj"


def draw(tmp_path, seeding, seed, width, height, count, spp=1, *extra):
    """Runs --view noise for `spp` samples, then --dump-random `count` numbers: returns
    (the image's grey level, the dumped numbers as uint32 (count, height, width))."""
    out, dump = tmp_path / f"noise_{seeding}_{seed}.pfm", tmp_path / f"{seeding}_{seed}.bin"
    result = run_chapter("09", "--headless", "--out", out, "--view", "noise",
                         "--seeding", seeding, "--seed", seed, "--width", width,
                         "--height", height, "--spp", spp, "--dump-random", dump,
                         "--count", count, *extra)
    assert result.returncode == 0, result.stderr
    numbers = np.fromfile(dump, dtype="<u4").reshape(count, height, width)
    return read_pfm(out)[..., 0], numbers


# ---------------------------------------------------------------------------------------
# The GPU's numbers are rng.py's numbers
# ---------------------------------------------------------------------------------------

@pytest.mark.windows
@pytest.mark.parametrize("seeding", ["naive", "hashed"])
@pytest.mark.parametrize("seed", [1, 2024])
def test_streams_equal_the_numpy_model_bit_for_bit(tmp_path, seeding, seed):
    """--spp 1 shows number 0 of each pixel (as a float, exactly: 24 bits), the dump
    continues with numbers 1 .. 6 from the state the dispatch left in the buffer."""
    width, height = 19, 7  # not a multiple of the 8 x 8 tiles
    first, numbers = draw(tmp_path, seeding, seed, width, height, 6)
    expected = rng.pixel_streams(seeding, seed, width, height, 7)
    assert np.array_equal(first, rng.to_unit_float(expected[0]))
    assert np.array_equal(numbers, expected[1:])


def test_the_stream_continues_across_many_dispatches(tmp_path):
    """After 9 dispatches of the tracer (one number each in the noise view), the state
    in the buffer is the one rng.py reaches after 9 steps."""
    _, numbers = draw(tmp_path, "hashed", 7, 12, 10, 3, 9)
    assert np.array_equal(numbers, rng.pixel_streams("hashed", 7, 12, 10, 12)[9:])


@pytest.mark.windows
def test_accumulation_is_the_running_mean(tmp_path):
    """Two samples: mean = x0 + (x1 - x0) / 2, in float32 as the shader computes it;
    eight: the mean of the first eight numbers, up to float32 rounding."""
    x = rng.to_unit_float(rng.pixel_streams("hashed", 3, 16, 8, 8))
    two, _ = draw(tmp_path, "hashed", 3, 16, 8, 1, 2)
    assert np.array_equal(two, x[0] + (x[1] - x[0]) / np.float32(2))
    eight, _ = draw(tmp_path, "hashed", 3, 16, 8, 1, 8)
    assert np.max(np.abs(eight - x.astype(np.float64).mean(axis=0))) < 1e-6


# ---------------------------------------------------------------------------------------
# Statistics on the GPU's output: the same tests as rng.py's, the same verdicts
# ---------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def gpu_floats(tmp_path_factory):
    """64 numbers from each of 64 x 64 pixels, per seeding, as rng.py's floats."""
    folder = tmp_path_factory.mktemp("statistics")
    return {seeding: rng.to_unit_float(draw(folder, seeding, 1, 64, 64, 64)[1])
            .astype(np.float64) for seeding in ["naive", "hashed"]}


def test_each_pixels_stream_is_uniform_for_hashed_seeding(gpu_floats):
    result = rng.stream_uniformity_test(gpu_floats["hashed"])
    assert result.passed, str(result)


@pytest.mark.parametrize("direction", ["x", "y"])
def test_neighbour_correlation_fails_naive_and_passes_hashed(gpu_floats, direction):
    naive = rng.neighbour_correlation_test(gpu_floats["naive"], direction)
    hashed = rng.neighbour_correlation_test(gpu_floats["hashed"], direction)
    assert not naive.passed, f"naive seeding should fail: {naive}"
    assert hashed.passed, f"hashed seeding should pass: {hashed}"


# ---------------------------------------------------------------------------------------
# Reproducibility: the seed fixes every bit, however the dispatches are grouped
# ---------------------------------------------------------------------------------------

AO_SMALL = ["--view", "ao", "--width", "24", "--height", "18", "--spp", "8"]


def ao_bytes(tmp_path, name, *args):
    out = tmp_path / f"{name}.pfm"
    result = run_chapter("09", "--headless", "--out", out, *AO_SMALL, *args)
    assert result.returncode == 0, result.stderr
    return out.read_bytes()


def test_a_seed_reproduces_the_image_byte_for_byte(tmp_path):
    once = ao_bytes(tmp_path, "once", "--seed", 5)
    assert ao_bytes(tmp_path, "again", "--seed", 5) == once
    assert ao_bytes(tmp_path, "other", "--seed", 6) != once


def test_splitting_the_dispatches_gives_the_same_image(tmp_path):
    """8 samples in one go, or in 4 groups of 2 with the GPU idle in between: the state
    in the buffer carries each pixel's stream over, so every bit is the same."""
    assert ao_bytes(tmp_path, "one", "--seed", 5) == \
        ao_bytes(tmp_path, "four", "--seed", 5, "--batches", 4)


# ---------------------------------------------------------------------------------------
# Anti-aliasing against a supersampled numpy reference
# ---------------------------------------------------------------------------------------

WIDTH, HEIGHT, SPP, SUB = 32, 24, 16, 8


@pytest.fixture(scope="module")
def supersampled():
    """mesh_scene.py's smooth teapot traced at SUB x SUB points per pixel (a SUB times
    larger picture: its pixel centres are the stratified points (i + 0.5) / SUB of ours):
    per pixel, the mean over the points and the variance of one point."""
    positions, normals, triangles, normal_triangles = obj_io.read_obj(TEAPOT)
    fine = mesh_scene.trace_mesh(positions, triangles, normals, normal_triangles,
                                 WIDTH * SUB, HEIGHT * SUB, smooth=True).image
    blocks = fine.reshape(HEIGHT, SUB, WIDTH, SUB, 3)
    return blocks.mean(axis=(1, 3)), blocks.var(axis=(1, 3))


def z_scores(image, supersampled):
    """The GPU's error in units of its Monte Carlo standard error. The mean of SPP
    independent jittered samples has variance var / SPP, where var is the variance of
    one sample, estimated by the variance over the SUB x SUB points; the reference's own
    error (stratified: below var / SUB^2) and float32 rounding (1e-3 per channel, well
    below 1/255) are added. Where a pixel shows one surface var is ~0 and the bound is
    the rounding term; at an edge the error is about normal, so |z| > 4 is rare
    (6e-5 for a normal; var itself is estimated, hence the 1% margin). SUB = 4 is not
    enough: a horizon that crosses a pixel between two of its 4 rows of points looks
    like a pixel of one colour, and var comes out far too small there."""
    mean, var = supersampled
    sigma = np.sqrt(var / SPP + var / SUB**2 + 1e-3**2)
    return (image - mean) / sigma


def render_aa(tmp_path, *args):
    return render("09", tmp_path / "aa.pfm", "--width", WIDTH, "--height", HEIGHT,
                  "--spp", SPP, "--seed", 9, *args)


def assert_within_monte_carlo_error(image, supersampled):
    """Few pixels beyond 4 standard errors, and at the edges (where a pixel's points
    differ: std above 0.03) errors of the size Monte Carlo predicts: E[z^2] there is
    (1/SPP) / (1/SPP + 1/SUB^2) = 0.8, give or take 0.1 over ~140 pixels, so 2 is far
    out. Rays through the pixel centres measure 3.9: their edges are off by a whole
    sample's spread, not by its 1/sqrt(SPP); the GPU's jittered samples measure 0.77."""
    z = z_scores(image, supersampled)
    outliers = np.mean(np.any(np.abs(z) > 4.0, axis=-1))
    assert outliers <= 0.01, f"{outliers:.1%} of pixels beyond 4 standard errors"
    edges = supersampled[1].max(axis=-1) > 1e-3
    assert edges.sum() > 50
    edge_z2 = float(np.mean(z[edges] ** 2))
    assert edge_z2 < 2.0, f"mean z^2 at the edges {edge_z2:.2f}: errors too large"


def test_antialiased_teapot_agrees_with_the_supersampled_reference(tmp_path, supersampled):
    image = render_aa(tmp_path)
    assert_within_monte_carlo_error(image, supersampled)
    # The edges really are soft: some pixels lie strictly between their neighbours'
    # surfaces, which a single ray per pixel cannot produce.
    assert np.mean(supersampled[1].max(axis=-1) > 1e-3) > 0.05


def test_check_rejects_rays_through_the_pixel_centre(tmp_path, supersampled):
    """The planted mistake: no jitter, every sample through the centre: chapter 08's
    aliased picture, SPP times. The edges then miss the reference by many errors."""
    shaders = copy_shaders("09", tmp_path)
    source = shaders / "trace.comp"
    right = "vec2 pointInPixel = vec2(random01(random), random01(random));"
    assert right in source.read_text()
    source.write_text(source.read_text().replace(right, "vec2 pointInPixel = vec2(0.5);"))
    image = render_aa(tmp_path, "--shader-dir", shaders)
    with pytest.raises(AssertionError):
        assert_within_monte_carlo_error(image, supersampled)
