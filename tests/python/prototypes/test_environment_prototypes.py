"""The environment-light and thin-lens prototypes (python_prototypes/sky.py,
environment_sampling.py, thin_lens.py): the lat-long orientation is Mitsuba 3's envmap's
(probed through Mitsuba itself), the sky follows Preetham et al.'s closed forms and puts
its brightest pixel on the sun, the importance sampler's pdf integrates to 1 and its
samples pass a chi-square test that a sampler without sin θ fails, its irradiance
estimate is unbiased while the classic missing-Jacobian bug is caught, and the thin
lens blurs exactly as the circle-of-confusion formula says."""

import math
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[3]

from python_prototypes import camera_rays
from python_prototypes import chi_square
from python_prototypes import environment_sampling as env
from python_prototypes import sky
from python_prototypes import thin_lens

SAMPLES = 1_000_000


@pytest.fixture(scope="module")
def mi():
    mitsuba = pytest.importorskip("mitsuba", reason="pip install -r requirements.txt")
    mitsuba.set_variant("scalar_rgb")
    return mitsuba


def mitsuba_eval(mi, emitter, directions):
    """Mitsuba's envmap radiance seen along each direction: a ray going along d meets
    the environment with si.wi = -d."""
    values = []
    for d in np.asarray(directions, dtype=np.float64):
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(*(-d))
        values.append(np.array(emitter.eval(si), dtype=np.float64))
    return np.array(values)


def random_directions(rng, count):
    d = rng.normal(size=(count, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


@pytest.fixture(scope="module")
def spots_image():
    return sky.spots_map()


@pytest.fixture(scope="module")
def spots_sampler(spots_image):
    return env.EnvironmentSampler.from_image(spots_image)


# ---------------------------------------------------------------------------------------
# Orientation: ours and Mitsuba's
# ---------------------------------------------------------------------------------------

def test_direction_uv_round_trip():
    rng = np.random.default_rng(1)
    directions = random_directions(rng, 10_000)
    assert np.allclose(sky.uv_to_direction(*sky.direction_to_uv(directions)), directions,
                       atol=1e-12)
    u, v = rng.random(10_000), rng.uniform(1e-6, 1 - 1e-6, 10_000)
    u_back, v_back = sky.direction_to_uv(sky.uv_to_direction(u, v))
    assert np.allclose(u_back, u, atol=1e-12) and np.allclose(v_back, v, atol=1e-12)


@pytest.mark.parametrize("direction, uv", [
    ((0, 0, -1), (0.0, 0.5)), ((1, 0, 0), (0.25, 0.5)), ((0, 0, 1), (0.5, 0.5)),
    ((-1, 0, 0), (0.75, 0.5)), ((0, 1, 0), (None, 0.0)), ((0, -1, 0), (None, 1.0))])
def test_axes_land_where_the_convention_says(direction, uv):
    u, v = sky.direction_to_uv(np.array(direction, dtype=np.float64))
    if uv[0] is not None:
        assert u == pytest.approx(uv[0], abs=1e-12)
    assert v == pytest.approx(uv[1], abs=1e-12)


def test_pixel_centres_map_back_to_their_pixels():
    width, height = 64, 32
    rows, columns = sky.pixel_of_direction(sky.pixel_center_directions(width, height),
                                           width, height)
    expected_rows, expected_columns = np.mgrid[0:height, 0:width]
    assert np.array_equal(rows, expected_rows) and np.array_equal(columns, expected_columns)


def test_mitsuba_envmap_uses_our_uv(mi):
    """A map whose red is its column + 1 and green its row + 1: Mitsuba's bilinear
    lookup returns the continuous pixel position it read, which must be where our
    (u, v) says: column u W - 1/2 (texel centres), row v (H - 1) (rows on the poles)."""
    width, height = 16, 8
    rows, columns = np.mgrid[0:height, 0:width]
    image = np.stack([columns + 1.0, rows + 1.0, np.full_like(rows, 7.0, dtype=float)],
                     axis=-1).astype(np.float32)
    emitter = mi.load_dict({"type": "envmap", "bitmap": mi.Bitmap(image)})
    rng = np.random.default_rng(2)
    directions = random_directions(rng, 400)
    u, v = sky.direction_to_uv(directions)
    away_from_seam = (u * width > 0.55) & (u * width < width - 0.55)  # red wraps 16 -> 1
    got = mitsuba_eval(mi, emitter, directions[away_from_seam])
    assert np.allclose(got[:, 0], u[away_from_seam] * width - 0.5 + 1.0, atol=2e-4)
    assert np.allclose(got[:, 1], v[away_from_seam] * (height - 1) + 1.0, atol=2e-4)
    assert np.allclose(got[:, 2], 7.0, atol=1e-4)


def test_marked_pixels_through_a_pfm_file(mi, tmp_path):
    """Pixels marked in a PFM we write come back from Mitsuba along the directions our
    uv_to_direction gives for them (at Mitsuba's texel positions), the top row is +y,
    and the file's rows are not upside down."""
    width, height = 16, 8
    marks = {(1, 3): 5.0, (4, 12): 9.0, (6, 0): 3.0}
    image = np.zeros((height, width, 3), dtype=np.float32)
    for (row, column), value in marks.items():
        image[row, column] = (value, 2 * value, 3 * value)
    path = tmp_path / "marked.pfm"
    sky.write_pfm(path, image)
    emitter = mi.load_dict({"type": "envmap", "filename": str(path)})
    for (row, column), value in marks.items():
        at_mark = sky.uv_to_direction((column + 0.5) / width, row / (height - 1))
        mirrored = sky.uv_to_direction((column + 0.5) / width,
                                       (height - 1 - row) / (height - 1))
        assert np.allclose(mitsuba_eval(mi, emitter, [at_mark])[0],
                           [value, 2 * value, 3 * value], rtol=1e-5)
        assert np.allclose(mitsuba_eval(mi, emitter, [mirrored])[0], 0.0)
    top = np.zeros((height, width, 3), dtype=np.float32)
    top[0] = 1.0
    sky.write_pfm(path, top)
    emitter = mi.load_dict({"type": "envmap", "filename": str(path)})
    assert mitsuba_eval(mi, emitter, [(0.0, 1.0, 0.0)])[0] == pytest.approx([1, 1, 1])
    assert mitsuba_eval(mi, emitter, [(0.0, -1.0, 0.0)])[0] == pytest.approx([0, 0, 0])


def test_our_numpy_copy_of_mitsubas_lookup(mi):
    rng = np.random.default_rng(3)
    image = rng.uniform(0.0, 5.0, size=(6, 12, 3)).astype(np.float32)
    emitter = mi.load_dict({"type": "envmap", "bitmap": mi.Bitmap(image)})
    # Not exactly at a pole: there u is atan2(0, ±0), which the sign of a zero decides.
    directions = np.concatenate([random_directions(rng, 300), [[0, 0, -1], [1, 0, 0]]])
    assert np.allclose(sky.mitsuba_envmap_eval(image, directions),
                       mitsuba_eval(mi, emitter, directions), rtol=2e-5, atol=1e-5)


def test_mitsubas_irradiance_by_brute_force():
    """mitsuba_upward_irradiance (row weights) against brute-force quadrature of the
    bilinear lookup that the test above checks against Mitsuba itself."""
    rng = np.random.default_rng(16)
    image = rng.uniform(0.0, 5.0, size=(8, 16, 3))
    steps = 1024
    u, v = np.meshgrid((np.arange(steps) + 0.5) / steps, (np.arange(steps) + 0.5) / steps)
    directions = sky.uv_to_direction(u, v)
    weight = (2 * np.pi**2 * np.sin(np.pi * v) * np.maximum(directions[..., 1], 0.0)
              / steps**2)
    brute = np.einsum("ijc,ij->c", sky.mitsuba_envmap_eval(image, directions), weight)
    assert np.allclose(sky.mitsuba_upward_irradiance(image), brute, rtol=1e-4)


def test_mitsubas_reading_of_our_sky_differs_by_under_one_percent(sky_512):
    """Mitsuba puts row r at v = r / (H - 1), we at (r + 1/2) / H: the same file lights
    a scene a little differently (0.3 to 0.5% here for 512 x 256, halving with each
    doubling of the width). Comparisons with Mitsuba must allow for it."""
    ours, theirs = sky.upward_irradiance(sky_512), sky.mitsuba_upward_irradiance(sky_512)
    print(f"upward irradiance: ours {ours}, Mitsuba's reading {theirs}, "
          f"ratio {theirs / ours}")
    assert np.all(np.abs(theirs / ours - 1) < 0.01)


def test_mitsuba_renders_the_irradiance_of_its_reading(mi, sky_512, tmp_path):
    """End to end: Mitsuba loads our sky's PFM and renders a white diffuse floor facing
    +y (radiance E / π, direct lighting, its own envmap sampling). Its E agrees with
    mitsuba_upward_irradiance, and, at this width, measurably not with ours."""
    path = tmp_path / "sky.pfm"
    sky.write_pfm(path, sky_512)
    transform = mi.ScalarTransform4f
    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "direct", "emitter_samples": 4, "bsdf_samples": 0},
        "sky": {"type": "envmap", "filename": str(path)},
        "floor": {"type": "rectangle", "to_world": transform().rotate([1, 0, 0], -90),
                  "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": 1}}},
        "camera": {"type": "orthographic",
                   "to_world": transform().look_at(origin=[0, 1, 0], target=[0, 0, 0],
                                                   up=[0, 0, -1])
                   @ transform().scale([0.5, 0.5, 1]),
                   "film": {"type": "hdrfilm", "width": 8, "height": 8,
                            "rfilter": {"type": "box"}},
                   "sampler": {"type": "independent", "sample_count": 8192}}})
    pixels = np.array(mi.render(scene, seed=1), dtype=np.float64).reshape(-1, 3) * np.pi
    passes, estimate, error = passes_z_test(pixels, sky.mitsuba_upward_irradiance(sky_512))
    ours = sky.upward_irradiance(sky_512)
    print(f"Mitsuba renders E = {estimate} ± {error}; its reading "
          f"{sky.mitsuba_upward_irradiance(sky_512)}, ours {ours}")
    assert passes
    assert np.any(np.abs(estimate - ours) > 4 * error)


# ---------------------------------------------------------------------------------------
# The sky
# ---------------------------------------------------------------------------------------

def preetham_zenith(turbidity, sun_zenith):
    """Preetham et al. 1999, appendix A.2, typed in again: Y_z (kcd/m²), x_z, y_z."""
    t, s = turbidity, sun_zenith
    chi = (4 / 9 - t / 120) * (math.pi - 2 * s)
    big_y = (4.0453 * t - 4.9710) * math.tan(chi) - 0.2155 * t + 2.4192
    x = (t * t * (0.00166 * s**3 - 0.00375 * s**2 + 0.00209 * s)
         + t * (-0.02903 * s**3 + 0.06377 * s**2 - 0.03202 * s + 0.00394)
         + (0.11693 * s**3 - 0.21196 * s**2 + 0.06052 * s + 0.25886))
    y = (t * t * (0.00275 * s**3 - 0.00610 * s**2 + 0.00317 * s)
         + t * (-0.04214 * s**3 + 0.08970 * s**2 - 0.04153 * s + 0.00516)
         + (0.15346 * s**3 - 0.26756 * s**2 + 0.06670 * s + 0.26688))
    return big_y, x, y


CASES = [(2.0, 20.0), (3.0, 60.0), (6.0, 75.0), (9.0, 40.0)]  # (T, sun zenith degrees)


@pytest.mark.parametrize("turbidity, sun_zenith_degrees", CASES)
def test_zenith_values_follow_preetham(turbidity, sun_zenith_degrees):
    sun_zenith = math.radians(sun_zenith_degrees)
    big_y, x, y = preetham_zenith(turbidity, sun_zenith)
    assert sky.zenith_luminance(turbidity, sun_zenith) == pytest.approx(big_y, rel=1e-12)
    assert sky.zenith_chromaticity(turbidity, sun_zenith) == pytest.approx((x, y),
                                                                          rel=1e-12)
    # And the whole model gives exactly them straight up, F(0, θs) / F(0, θs) = 1.
    sun = sky.elevation_azimuth_to_direction(90.0 - sun_zenith_degrees, 33.0)
    model = sky.sky_xyY(np.array([0.0, 1.0, 0.0]), sun, turbidity)
    assert model == pytest.approx((x, y, big_y), rel=1e-12)
    # Daylight: a bluish white in a plausible range of kcd/m².
    assert 0.2 < x < 0.33 and 0.2 < y < 0.35 and 0.5 < big_y < 30


def test_perez_coefficients_are_the_papers():
    luminance, x, y = sky.perez_coefficients(4.0)
    assert luminance == pytest.approx([0.1787 * 4 - 1.4630, -0.3554 * 4 + 0.4275,
                                       -0.0227 * 4 + 5.3251, 0.1206 * 4 - 2.5771,
                                       -0.0670 * 4 + 0.3703])
    assert x[3] == pytest.approx(-0.0641 * 4 - 0.8989)
    assert y[2] == pytest.approx(-0.0079 * 4 + 0.2102)


@pytest.fixture(scope="module")
def sky_512():
    return sky.sky_map(512, sun_elevation=30.0, sun_azimuth=120.0, turbidity=3.0)


def test_sky_map_is_finite_non_negative_float32(sky_512):
    assert sky_512.shape == (256, 512, 3) and sky_512.dtype == np.float32
    assert np.all(np.isfinite(sky_512)) and np.all(sky_512 >= 0.0)


@pytest.mark.parametrize("elevation, azimuth, turbidity", [(30.0, 120.0, 3.0),
                                                           (62.0, 301.0, 2.2),
                                                           (4.0, 8.0, 6.0),
                                                           (85.0, 200.0, 9.0)])
def test_brightest_pixel_is_the_sun(elevation, azimuth, turbidity):
    width = 256
    image = sky.sky_map(width, elevation, azimuth, turbidity)
    lum = sky.luminance(image)
    row, column = np.unravel_index(np.argmax(lum), lum.shape)
    sun = sky.elevation_azimuth_to_direction(elevation, azimuth)
    brightest = sky.pixel_center_directions(width, width // 2)[row, column]
    pixel_reach = math.hypot(math.pi / width, 2 * math.pi / width)  # a pixel's diagonal
    assert math.acos(min(1.0, brightest @ sun)) <= pixel_reach + sky.SUN_HALF_ANGLE
    # Even a low sun through haze (4°, T = 6: air mass 12, blue all gone) stands out.
    assert lum[row, column] > 50 * np.median(lum)


def test_sky_is_brighter_near_the_sun_than_opposite():
    sun_elevation, sun_azimuth = 30.0, 120.0
    sun = sky.elevation_azimuth_to_direction(sun_elevation, sun_azimuth)
    for elevation, offset in [(30.0, 15.0), (45.0, 0.0), (10.0, 30.0), (60.0, 40.0)]:
        near = sky.elevation_azimuth_to_direction(elevation, sun_azimuth + offset)
        opposite = sky.elevation_azimuth_to_direction(elevation, sun_azimuth + 180 + offset)
        near_l, opposite_l = (sky.luminance(sky.sky_radiance(d, sun, 3.0))
                              for d in (near, opposite))
        assert near_l > 1.5 * opposite_l, (elevation, offset, near_l, opposite_l)


def test_sun_disk_carries_exactly_its_solid_angle():
    for width, elevation in [(512, 30.0), (256, 71.0), (1024, 12.0)]:
        image = np.zeros((width // 2, width, 3))
        sun = sky.elevation_azimuth_to_direction(elevation, 77.0)
        coverage = sky.add_disk(image, sun, sky.SUN_HALF_ANGLE, (1.0, 1.0, 1.0))
        total = coverage.sum(axis=1) @ sky.row_solid_angles(width, width // 2)
        assert total == pytest.approx(sky.SUN_SOLID_ANGLE, rel=1e-9)
        assert sky.SUN_SOLID_ANGLE == pytest.approx(6.72e-5, rel=0.01)


def test_sun_luminance_is_plausible():
    """The unattenuated black body gives the sun's known ~2e9 cd/m²; through the air at
    30° elevation and T = 3 it keeps roughly half; the matching functions' fit
    integrates to the CIE 1931 ȳ area, 106.86 nm."""
    wavelengths = np.arange(360.0, 831.0, 1.0)
    y_bar_area = sky.cie_1931_matching(wavelengths)[:, 1].sum()
    assert y_bar_area == pytest.approx(106.86, rel=0.01)
    outside = sky.luminance(sky.spectrum_to_linear_srgb(
        wavelengths, sky.planck_radiance(wavelengths, sky.SUN_TEMPERATURE_KELVIN)))
    assert 1.6e6 < outside < 2.2e6  # kcd/m²
    high_sun = sky.sun_radiance(math.radians(60.0), 3.0)
    assert 0.35 * outside < sky.luminance(high_sun) < 0.75 * outside
    low_sun = sky.sun_radiance(math.radians(80.0), 3.0)  # air mass 5.6: reddened
    assert low_sun[0] / low_sun[2] > 2 * high_sun[0] / high_sun[2]


def test_ground_is_albedo_times_irradiance_over_pi(sky_512):
    black_ground = sky.sky_map(512, 30.0, 120.0, 3.0, ground_albedo=0.0)
    assert np.all(black_ground[128:] == 0.0)
    irradiance = sky.upward_irradiance(black_ground)
    assert np.allclose(sky_512[200, 17], 0.2 * irradiance / math.pi, rtol=1e-5)
    assert np.allclose(sky_512[:128], black_ground[:128])


def test_spots_map_matches_its_closed_form_irradiance(spots_image):
    assert spots_image.shape == (32, 64, 3)
    assert np.allclose(sky.upward_irradiance(spots_image), sky.spots_irradiance(),
                       rtol=0.01)


def test_pfm_round_trip_and_conventions(tmp_path, spots_image):
    from python_prototypes import mitsuba_reference
    path = tmp_path / "spots.pfm"
    sky.write_pfm(path, spots_image)
    assert not (tmp_path / "spots.pfm.partial").exists()
    assert path.read_bytes().startswith(b"PF\n64 32\n-1.0\n")
    assert np.array_equal(sky.read_pfm(path), spots_image)
    assert np.array_equal(mitsuba_reference.read_pfm(path), spots_image)
    first_stored_row = np.frombuffer(path.read_bytes()[len(b"PF\n64 32\n-1.0\n"):],
                                     dtype="<f4", count=64 * 3).reshape(64, 3)
    assert np.array_equal(first_stored_row, spots_image[-1])  # the bottom row comes first


def test_bad_sky_arguments_are_refused():
    with pytest.raises(ValueError):
        sky.sky_map(512, sun_elevation=-5.0)
    with pytest.raises(ValueError):
        sky.sky_map(512, turbidity=20.0)
    with pytest.raises(ValueError):
        sky.sky_map(511)


# ---------------------------------------------------------------------------------------
# Chi-square p-values without scipy
# ---------------------------------------------------------------------------------------

def upper_gamma_by_recurrence(a, x):
    """Q(a, x) for a half-integer or integer a from Q(1/2, x) = erfc √x or
    Q(1, x) = e^-x and Q(s + 1, x) = Q(s, x) + x^s e^-x / Γ(s + 1)."""
    s, q = (0.5, math.erfc(math.sqrt(x))) if (2 * a) % 2 == 1 else (1.0, math.exp(-x))
    while s < a:
        q += math.exp(s * math.log(x) - x - math.lgamma(s + 1))
        s += 1.0
    return q


@pytest.mark.parametrize("a", [0.5, 1.0, 1.5, 3.0, 10.5, 50.0, 250.5, 1000.0])
@pytest.mark.parametrize("relative_x", [0.3, 0.9, 1.0, 1.1, 2.0])
def test_regularized_upper_gamma(a, relative_x):
    x = a * relative_x
    expected = upper_gamma_by_recurrence(a, x)
    assert chi_square.regularized_upper_gamma(a, x) == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("statistic, dof, p", [(3.841458820694124, 1, 0.05),
                                               (6.634896601021214, 1, 0.01),
                                               (18.307038053275146, 10, 0.05),
                                               (124.34211340400407, 100, 0.05),
                                               (10.0, 10, 0.44049328506521257)])
def test_chi_square_p_values_known(statistic, dof, p):
    assert chi_square.chi_square_p_value(statistic, dof) == pytest.approx(p, rel=1e-6)


def test_chi_square_pools_small_bins():
    observed = [100, 95, 3, 1, 1]
    expected = [98.0, 97.0, 2.0, 2.0, 1.0]
    statistic, dof, p = env.chi_square_test(observed, expected)
    # Bins: 100 vs 98, 95 vs 97, pooled 5 vs 5.
    assert dof == 2
    assert statistic == pytest.approx(4 / 98 + 4 / 97 + 0.0)
    assert p == pytest.approx(math.exp(-statistic / 2))  # 2 dof: Q(1, χ²/2)
    # Samples where nothing was expected: that bin joins the smallest, and is caught.
    statistic, dof, p = env.chi_square_test([10, 10, 30], [25.0, 25.0, 0.0])
    assert (statistic, dof) == (pytest.approx(18.0), 1)
    assert p == pytest.approx(math.erfc(3.0), rel=1e-9)


# ---------------------------------------------------------------------------------------
# Environment sampling
# ---------------------------------------------------------------------------------------

def test_tables_are_cdfs(spots_sampler):
    marginal, conditional = spots_sampler.marginal_cdf, spots_sampler.conditional_cdf
    assert marginal.shape == (33,) and conditional.shape == (32, 65)
    assert marginal[0] == 0.0 and marginal[-1] == 1.0 and np.all(np.diff(marginal) >= 0)
    assert np.all(conditional[:, 0] == 0.0) and np.all(conditional[:, -1] == 1.0)
    assert np.all(np.diff(conditional, axis=1) >= 0)


@pytest.mark.parametrize("which", ["spots", "sky"])
def test_pdf_integrates_to_one(which, spots_image):
    image = spots_image if which == "spots" else sky.sky_map(128, 30.0, 120.0, 3.0)
    sampler = env.EnvironmentSampler.from_image(image)
    height, width = image.shape[:2]
    centres = sky.pixel_center_directions(width, height)
    # The pdf at each pixel's centre times the pixel's solid angle: the midpoint rule.
    total = np.sum(sampler.pdf(centres) * sky.row_solid_angles(width, height)[:, None])
    assert total == pytest.approx(1.0, abs=2e-3)
    # Integrated properly over each pixel it is the pixel's probability, exactly.
    integrated = env.pixel_probabilities_from_pdf(sampler.pdf, width, height)
    assert integrated.sum() == pytest.approx(1.0, abs=1e-9)
    assert np.allclose(integrated, sampler.pixel_probability, rtol=1e-9, atol=1e-15)


def test_samples_fall_in_their_pixel_with_the_pdf_of_pdf(spots_sampler):
    rng = np.random.default_rng(4)
    directions, pdf, (rows, columns) = spots_sampler.sample(rng.random(100_000),
                                                            rng.random(100_000))
    again_rows, again_columns = sky.pixel_of_direction(directions, 64, 32)
    assert np.mean((again_rows == rows) & (again_columns == columns)) > 0.9999
    same = (again_rows == rows) & (again_columns == columns)
    assert np.allclose(pdf[same], spots_sampler.pdf(directions[same]), rtol=1e-9)
    assert np.all(pdf > 0)


def test_zero_rows_and_pixels_are_never_sampled():
    image = sky.spots_map()
    image[16:] = 0.0  # black below the horizon
    image[3, 10:20] = 0.0
    sampler = env.EnvironmentSampler.from_image(image)
    rng = np.random.default_rng(5)
    _, _, (rows, columns) = sampler.sample(rng.random(200_000), rng.random(200_000))
    assert rows.max() < 16
    assert not np.any((rows == 3) & (columns >= 10) & (columns < 20))
    edges = np.array([0.0, np.nextafter(1.0, 0.0)])
    _, pdf, (rows, _) = sampler.sample(edges, edges)  # the extreme numbers stay valid
    assert np.all(rows < 16) and np.all(np.isfinite(pdf))


@pytest.mark.parametrize("seed", [1, 2])
def test_chi_square_passes_the_sampler(spots_sampler, seed):
    statistic, dof, p = env.sampler_chi_square(spots_sampler, spots_sampler,
                                               np.random.default_rng(seed), SAMPLES)
    print(f"right sampler, seed {seed}: χ² {statistic:.1f}, {dof} dof, p {p:.4f}")
    assert p > 1e-3


def test_chi_square_passes_inside_the_pixels(spots_sampler):
    """Cells of a quarter pixel: the pdf's 1/sin θ inside each pixel must be right too."""
    statistic, dof, p = env.sampler_chi_square(spots_sampler, spots_sampler,
                                               np.random.default_rng(3), SAMPLES,
                                               subdivisions=2)
    print(f"right sampler, quarter pixels: χ² {statistic:.1f}, {dof} dof, p {p:.4f}")
    assert p > 1e-3


def test_chi_square_rejects_a_sampler_without_sin_theta(spots_image, spots_sampler):
    wrong = env.EnvironmentSampler.from_image(spots_image, sin_theta_weighting=False)
    statistic, dof, p = env.sampler_chi_square(wrong, spots_sampler,
                                               np.random.default_rng(1), SAMPLES)
    print(f"sampler without sin θ: χ² {statistic:.1f}, {dof} dof, p {p:.3g}")
    assert p < 1e-9
    # And its rows crowd the poles, as chapter 18's page says: the eighth of the rows
    # nearest each pole get more of its samples than of the right sampler's.
    u = np.random.default_rng(2).random((2, 100_000))
    polar = [np.mean(np.minimum(rows, s.height - 1 - rows) < s.height / 8)
             for s in (wrong, spots_sampler) for rows in [s.sample(*u)[2][0]]]
    print(f"samples in the polar rows: without sin θ {polar[0]:.3f}, right {polar[1]:.3f}")
    assert polar[0] > 1.2 * polar[1]


def passes_z_test(samples, exact, standard_errors=4.0):
    estimate, error = env.mean_and_standard_error(samples)
    return np.all(np.abs(estimate - exact) <= standard_errors * error), estimate, error


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_irradiance_estimate_agrees_with_the_direct_sum(spots_image, spots_sampler, seed):
    exact = sky.upward_irradiance(spots_image)
    samples = env.irradiance_samples(spots_sampler, np.random.default_rng(seed), SAMPLES)
    passes, estimate, error = passes_z_test(samples, exact)
    print(f"seed {seed}: estimate {estimate} ± {error}, exact {exact}")
    assert passes


def test_irradiance_with_the_pdf_missing_sin_theta_is_rejected(spots_image, spots_sampler):
    exact = sky.upward_irradiance(spots_image)
    samples = env.irradiance_samples(spots_sampler, np.random.default_rng(1), SAMPLES,
                                     pdf=env.pdf_forgot_sin_theta)
    passes, estimate, error = passes_z_test(samples, exact)
    print(f"pdf without 1/sin θ: estimate {estimate} ± {error}, exact {exact}")
    assert not passes
    assert np.all(np.abs(estimate - exact) > 20 * error)


def test_sampler_without_sin_theta_is_unbiased_with_its_own_pdf(spots_image):
    """Weights without sin θ sample worse, but divided by their own pdf stay right."""
    wrong_weights = env.EnvironmentSampler.from_image(spots_image,
                                                      sin_theta_weighting=False)
    samples = env.irradiance_samples(wrong_weights, np.random.default_rng(6), SAMPLES)
    assert passes_z_test(samples, sky.upward_irradiance(spots_image))[0]


def test_irradiance_under_the_sky(sky_512):
    """The sun holds half the light in a pixel: importance sampling still gets it."""
    sampler = env.EnvironmentSampler.from_image(sky_512)
    samples = env.irradiance_samples(sampler, np.random.default_rng(7), 400_000)
    passes, estimate, error = passes_z_test(samples, sky.upward_irradiance(sky_512))
    assert passes
    assert np.all(error / estimate < 0.003)


# ---------------------------------------------------------------------------------------
# The thin lens
# ---------------------------------------------------------------------------------------

WIDTH, HEIGHT = 256, 192


def lens_camera(aperture=0.035 / 2.0, focus=2.0):
    return thin_lens.ThinLensCamera(aperture_diameter=aperture, focus_distance=focus)


def test_concentric_disk_is_uniform_on_the_disk():
    rng = np.random.default_rng(8)
    points = thin_lens.concentric_disk(rng.random(200_000), rng.random(200_000))
    radius_squared = np.sum(points**2, axis=1)
    assert radius_squared.max() <= 1.0 + 1e-12
    assert radius_squared.mean() == pytest.approx(0.5, abs=0.005)  # uniform: E[r²] = 1/2
    assert np.abs(points.mean(axis=0)).max() < 0.005
    edge = np.linspace(0.0, 1.0, 101)
    on_square = np.concatenate([thin_lens.concentric_disk(edge, np.zeros(101)),
                                thin_lens.concentric_disk(np.ones(101), edge)])
    assert np.allclose(np.linalg.norm(on_square, axis=1), 1.0)  # square's edge -> circle
    assert np.allclose(thin_lens.concentric_disk([0.5], [0.5]), 0.0)


def test_aperture_zero_gives_the_pinhole_rays():
    camera = lens_camera(aperture=0.0)
    rows, columns = np.mgrid[0:HEIGHT, 0:WIDTH]
    rng = np.random.default_rng(9)
    origins, directions = thin_lens.thin_lens_rays(
        camera, WIDTH, HEIGHT, columns.ravel() + 0.5, rows.ravel() + 0.5,
        rng.random(rows.size), rng.random(rows.size))
    pinhole = camera_rays.camera_rays(camera, WIDTH, HEIGHT).reshape(-1, 3)
    assert np.allclose(origins, camera.eye, atol=0.0)
    assert np.allclose(directions, pinhole, atol=1e-12)


def test_rays_of_a_pixel_meet_on_the_focus_plane():
    camera = lens_camera()
    rng = np.random.default_rng(10)
    count = 5000
    forward, _, _ = thin_lens.basis(camera)
    for pixel in [(0.5, 0.5), (128.0, 96.0), (200.3, 17.9)]:
        x, y = np.full(count, pixel[0]), np.full(count, pixel[1])
        origins, directions = thin_lens.thin_lens_rays(camera, WIDTH, HEIGHT, x, y,
                                                       rng.random(count), rng.random(count))
        to_plane = camera.focus_distance - thin_lens.depth(camera, origins)
        t = to_plane / (directions @ forward)
        hits = origins + directions * t[:, None]
        assert np.ptp(hits, axis=0).max() < 1e-12
        assert np.ptp(origins, axis=0).max() > 0.5 * camera.aperture_diameter


def test_image_positions_invert_the_rays():
    camera = lens_camera()
    rng = np.random.default_rng(11)
    count = 2000
    x, y = rng.uniform(0, WIDTH, count), rng.uniform(0, HEIGHT, count)
    origins, directions = thin_lens.thin_lens_rays(camera, WIDTH, HEIGHT, x, y,
                                                   rng.random(count), rng.random(count))
    points = origins + directions * rng.uniform(0.3, 30.0, count)[:, None]
    back_x, back_y = thin_lens.image_positions(camera, WIDTH, HEIGHT, points, origins)
    assert np.allclose(back_x, x, atol=1e-9) and np.allclose(back_y, y, atol=1e-9)


def test_points_on_the_focus_plane_do_not_spread():
    camera = lens_camera()
    forward, right, true_up = thin_lens.basis(camera)
    rng = np.random.default_rng(12)
    for side, up in [(0.0, 0.0), (0.4, -0.3), (-0.9, 0.5)]:
        point = np.asarray(camera.eye) + camera.focus_distance * forward + side * right \
            + up * true_up
        assert thin_lens.measured_blur_diameter(camera, WIDTH, HEIGHT, point, 20_000,
                                                rng) < 1e-9


@pytest.mark.parametrize("aperture", [0.035 / 1.4, 0.035 / 4, 0.1])
@pytest.mark.parametrize("point_depth, side", [(0.5, 0.0), (1.2, 0.2), (3.5, -0.8),
                                               (20.0, 4.0)])
def test_blur_diameter_matches_the_circle_of_confusion(aperture, point_depth, side):
    camera = lens_camera(aperture=aperture)
    forward, right, _ = thin_lens.basis(camera)
    point = np.asarray(camera.eye) + point_depth * forward + side * right
    measured = thin_lens.measured_blur_diameter(camera, WIDTH, HEIGHT, point, 200_000,
                                                np.random.default_rng(13))
    formula = thin_lens.circle_of_confusion_pixels(camera, point_depth, WIDTH)
    print(f"A {aperture * 1000:.3g} mm, depth {point_depth} m: measured {measured:.5f} px, "
          f"formula {formula:.5f} px, ratio {measured / formula:.5f}")
    assert measured == pytest.approx(formula, rel=0.01)
    assert measured <= formula * (1 + 1e-9)  # no image falls outside the circle


def test_blur_fills_its_circle_uniformly():
    """Mean squared distance from the centre of a uniform disk of diameter c is c²/8."""
    camera = lens_camera(aperture=0.035 / 1.4)
    forward, _, _ = thin_lens.basis(camera)
    point = np.asarray(camera.eye) + 0.7 * forward
    rng = np.random.default_rng(14)
    lens = thin_lens.lens_points(camera, rng.random(200_000), rng.random(200_000))
    x, y = thin_lens.image_positions(camera, WIDTH, HEIGHT,
                                     np.broadcast_to(point, lens.shape), lens)
    diameter = thin_lens.circle_of_confusion_pixels(camera, 0.7, WIDTH)
    mean_square = np.mean((x - x.mean()) ** 2 + (y - y.mean()) ** 2)
    assert mean_square == pytest.approx(diameter**2 / 8, rel=0.01)
    assert np.ptp(x) == pytest.approx(diameter, rel=0.01)  # as wide as it is tall: round
    assert np.ptp(y) == pytest.approx(diameter, rel=0.01)


def test_our_circle_is_the_textbook_one_on_our_sensor():
    """The textbook blur, measured on a real lens's sensor at f f_d / (f_d - f), scaled
    to our sensor at f: the same in pixels when both sensors see the same view."""
    distances = np.array([0.3, 1.0, 2.5, 10.0, np.inf])
    for f, a, focus in [(0.035, 0.0125, 2.0), (0.05, 0.02, 0.8), (0.024, 0.006, 6.0)]:
        ours = thin_lens.circle_of_confusion(distances, a, f, focus)
        textbook = thin_lens.physical_circle_of_confusion(distances, a, f, focus)
        assert np.allclose(ours, textbook * (focus - f) / focus, rtol=1e-12)


def test_rays_match_mitsubas_thinlens(mi):
    camera = thin_lens.ThinLensCamera(eye=(0.3, 1.1, 4.0),
                                      look_direction=(0.1, -0.25, -1.0),
                                      aperture_diameter=0.05, focus_distance=2.5)
    sensor = mi.load_dict(thin_lens.mitsuba_thinlens_dict(camera, WIDTH, HEIGHT))
    forward, _, _ = thin_lens.basis(camera)
    rng = np.random.default_rng(15)
    count = 200
    x, y = rng.uniform(0, WIDTH, count), rng.uniform(0, HEIGHT, count)
    u1, u2 = rng.random(count), rng.random(count)
    origins, directions = thin_lens.thin_lens_rays(camera, WIDTH, HEIGHT, x, y, u1, u2)
    near_clip = sensor.near_clip()
    for i in range(count):
        ray, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f(x[i] / WIDTH, y[i] / HEIGHT),
                                   mi.Point2f(1.0 - u1[i], u2[i]))  # its lens x is our -x
        d = np.array(ray.d, dtype=np.float64)
        o = np.array(ray.o, dtype=np.float64) - d * near_clip / (d @ forward)
        assert np.allclose(d, directions[i], atol=2e-6), i
        assert np.allclose(o, origins[i], atol=2e-6), i
