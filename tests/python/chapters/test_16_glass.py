"""Chapter 16: glass, checked with statistics (book/docs/maintainers.md).

- The GLSL of dielectric.glsl on the GPU (tests/cpp/bsdf_probe.cpp with
  tests/data/bsdf/dielectric_probe.comp) against python_prototypes/microfacet.py,
  query by query, from both sides, to float precision; then a chi-square test of the
  GPU's rough dielectric samples (reflection and transmission, the whole sphere) against
  the GPU's own pdf, which integrates to the share of samples that succeed.
- White furnaces: a smooth glass sphere in a glowing box vanishes (index 1.5 and 2.42).
- A lamp inside a glass ball looks dimmer by (1 - F) / eta^2: the radiance scale.
- Mitsuba 3, region by region: smooth and rough glass spheres, a glass box of quads and
  a prism of triangles, and the glass gems, all in the Cornell room; then each sphere
  and gem in a close-up, within 2% with a standard error of 0.3-1.0%.
- Planted bugs, each in a copy of the shaders, each failing the check that catches it.
- Bad glass (a negative roughness, an index <= 0): exit code 3 at its line.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import page_claims
import path_checks
import pytest
from conftest import ROOT, regions_agreeing, run_chapter
from path_checks import SIGMAS, mean_and_error

from python_prototypes import chi_square
from python_prototypes import microfacet as mf
from python_prototypes.scene_cast import sphere_t

pytestmark = pytest.mark.filterwarnings("ignore::RuntimeWarning")

PROBE_SHADER = ROOT / "tests" / "data" / "bsdf" / "dielectric_probe.comp"
SCENES = ROOT / "assets" / "scenes"
TEST_SCENES = ROOT / "tests" / "data" / "scenes"
MESH_FOLDERS = [ROOT / "build" / "assets"]  # where the build writes the gems

# The planted bugs: (file, the right line, the wrong one). Each must fail its check.
FRESNEL_INDICES_SWAPPED = ("dielectric.glsl", "fromOutside ? eta : 1.0 / eta",
                           "fromOutside ? 1.0 / eta : eta")
NO_RADIANCE_SCALE = ("dielectric.glsl", "float radianceScale = fresnel.etaTI * fresnel.etaTI;",
                     "float radianceScale = 1.0;")
# Without its own case, total internal reflection takes the square root of a negative
# number for cos(theta_t): NaN, which poisons the path.
NO_TOTAL_INTERNAL_REFLECTION = ("dielectric.glsl", "if (sinTSquared >= 1.0) return",
                                "if (false) return")
MISSING_TRANSMISSION_JACOBIAN = (
    "dielectric.glsl", ": transmissionJacobian(wi, wo, m, etaBeyond(wi, eta));", ": 1.0;")
BUGS = {"fresnel_indices_swapped": FRESNEL_INDICES_SWAPPED,
        "no_radiance_scale": NO_RADIANCE_SCALE,
        "no_total_internal_reflection": NO_TOTAL_INTERNAL_REFLECTION,
        "missing_transmission_jacobian": MISSING_TRANSMISSION_JACOBIAN}


def shaders_with(tmp_path, bug=None) -> Path:
    """A copy of the chapter's shaders (and the probe's), with one planted bug."""
    return path_checks.shaders_with_bug("16", tmp_path, bug, [PROBE_SHADER])


def path_trace(tmp_path, name, *args, shader_dir=None) -> np.ndarray:
    extra = ["--shader-dir", shader_dir] if shader_dir else []
    return path_checks.path_trace("16", tmp_path, name, *extra, *args)


# --- The GPU's dielectric against numpy -------------------------------------------------

def run_probe(shader_dir: Path, queries: np.ndarray, tmp_path: Path) -> np.ndarray:
    """Runs dielectric_probe.comp on (N, 20) float32 queries; returns the (N, 24) answers."""
    return path_checks.run_bsdf_probe(PROBE_SHADER.name, shader_dir, queries, tmp_path)


def make_queries(wi, alpha, eta, u, given) -> np.ndarray:
    q = np.zeros((len(wi), 20))
    q[:, 0:3], q[:, 3], q[:, 4] = wi, alpha, eta
    q[:, 12:15] = u
    q[:, 16:19] = given
    return q


def sphere_directions(rng, n):
    """Unit directions over the whole sphere: outside (z > 0) and inside (z < 0)."""
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


@pytest.fixture(scope="module")
def probe_queries():
    rng = np.random.default_rng(16)
    n = 4000
    return (sphere_directions(rng, n), rng.choice([0.05, 0.2, 0.5, 1.0], n),
            rng.choice([1.5, 1.57, 1.77, 2.42], n), rng.random((n, 3)),
            sphere_directions(rng, n))


def assert_matches_numpy(answers, wi, alpha, eta, u, given):
    """Every quantity within float32's precision of the numpy prototype's."""
    def close(ours, theirs, what):
        ours, theirs = np.asarray(ours), np.asarray(theirs)
        bad = ~np.isclose(ours, theirs, rtol=2e-3, atol=1e-5)
        assert not bad.any(), (what, int(bad.sum()), ours[bad][:5], theirs[bad][:5])

    F, cos_t, eta_it, eta_ti = mf.fresnel_dielectric(wi[:, 2], eta)
    close(answers[:, 12], F, "fresnelDielectric: reflectance")
    close(answers[:, 13], cos_t, "fresnelDielectric: cosT")
    close(answers[:, 14], eta_it, "fresnelDielectric: etaIT")
    close(answers[:, 15], eta_ti, "fresnelDielectric: etaTI")
    wo, weight = mf.smooth_dielectric_sample(wi, eta, u[:, 2])
    close(answers[:, 16:19], wo, "smoothDielectricSample: wo")
    close(answers[:, 5], weight, "smoothDielectricSample: weight")
    close(answers[:, 20:23], mf.generalized_half_vector(wi, given, eta)[0],
          "generalizedHalfVector")
    close(answers[:, 8], mf.rough_dielectric_eval(wi, given, alpha, eta), "roughDielectricEval")
    close(answers[:, 9], mf.rough_dielectric_pdf(wi, given, alpha, eta), "roughDielectricPdf")
    wo, weight, pdf = mf.rough_dielectric_sample(wi, alpha, eta, u[:, 2], u[:, 0], u[:, 1])
    close(answers[:, 0:3], wo, "roughDielectricSample: wo")
    close(answers[:, 3], pdf, "roughDielectricSample: pdf")
    close(answers[:, 4], weight, "roughDielectricSample: weight")


def test_gpu_dielectric_matches_the_numpy_prototype(tmp_path, probe_queries):
    answers = run_probe(shaders_with(tmp_path), make_queries(*probe_queries), tmp_path)
    assert_matches_numpy(answers, *probe_queries)
    wi = probe_queries[0]
    assert (answers[:, 12] == 1.0).sum() > 100  # total internal reflection was tried
    assert (wi[:, 2] < 0).sum() > 1500  # and so were both sides


def test_sample_weight_is_eval_over_pdf(tmp_path, probe_queries):
    # Ask eval and pdf about the very direction the sampler chose.
    wi, alpha, eta, u, _ = probe_queries
    folder = shaders_with(tmp_path)
    sampled = run_probe(folder, make_queries(*probe_queries), tmp_path)
    wo, pdf, weight = sampled[:, 0:3], sampled[:, 3], sampled[:, 4]
    again = run_probe(folder, make_queries(wi, alpha, eta, u, wo), tmp_path)
    valid = pdf > 0
    assert valid.mean() > 0.8
    assert 0.2 < np.mean(wo[valid, 2] * wi[valid, 2] < 0) < 0.9  # both lobes sampled
    np.testing.assert_allclose(again[valid, 9], pdf[valid], rtol=2e-3)
    np.testing.assert_allclose(again[valid, 8] / pdf[valid], weight[valid], rtol=2e-3,
                               atol=1e-6)


# (alpha, incidence in degrees, eta); a negative incidence: from inside the glass.
CHI_SQUARE_CASES = [(0.1, 30, 1.5), (0.3, -20, 1.5), (0.5, 70, 1.5), (0.3, -60, 1.5),
                    (0.2, 45, 2.42)]


def incident(angle):
    """wi at `angle` degrees from the normal; a negative angle: from inside (below)."""
    theta = math.radians(180.0 + angle if angle < 0 else angle)
    return np.array([math.sin(theta), 0.0, math.cos(theta)])


def vertical_microfacet_theta(wi, eta):
    """The theta_o where the microfacet joining wi to a refracted wo turns vertical: the
    pdf jumps there, so the chi-square quadrature splits its cells there."""
    eta_io = eta if wi[2] > 0 else 1.0 / eta
    cos_o = -wi[2] / eta_io
    return [float(np.arccos(cos_o))] if abs(cos_o) < 1.0 else []


def gpu_chi_square(folder, tmp_path, alpha, angle, eta, samples=200_000):
    """The GPU's sampled directions against the GPU's own pdf, over the whole sphere.
    Returns the test's result and the pdf's integral over the sphere."""
    wi = incident(angle)
    valid_share = []

    def sample_directions(rng, count):
        answers = run_probe(folder, make_queries(np.tile(wi, (count, 1)), alpha, eta,
                                                 rng.random((count, 3)),
                                                 np.tile(wi, (count, 1))), tmp_path)
        valid = answers[:, 3] > 0
        valid_share.append(valid.mean())
        return answers[:, 0:3], valid

    def pdf(directions):
        flat = directions.reshape(-1, 3)
        n = len(flat)
        answers = run_probe(folder, make_queries(np.tile(wi, (n, 1)), alpha, eta,
                                                 np.zeros((n, 3)), flat), tmp_path)
        return answers[:, 9].reshape(directions.shape[:-1])

    breaks = vertical_microfacet_theta(wi, eta)
    result = chi_square.chi_square_test(sample_directions, pdf, samples, seed=abs(angle),
                                        theta_breaks=breaks,
                                        test_count=len(CHI_SQUARE_CASES))
    integral = 1.0 - chi_square.cell_probabilities(pdf, 60, 120, 6, breaks)[-1]
    return result, integral, valid_share[0]


@pytest.mark.parametrize("alpha, angle, eta", CHI_SQUARE_CASES)
def test_gpu_samples_have_the_gpu_pdf(tmp_path, alpha, angle, eta):
    result, integral, valid = gpu_chi_square(shaders_with(tmp_path), tmp_path, alpha,
                                             angle, eta)
    print(f"alpha {alpha}, θi {angle}°, eta {eta}: {result}; ∫ pdf = {integral:.4f}, "
          f"valid samples {valid:.4f}")
    assert result.accepted, str(result)
    # The pdf integrates to 1 less the share of samples that fail: a microfacet that
    # reflects wi through the surface, or refracts it back to wi's side. From outside
    # a few per cent fail, from inside up to 9% at alpha 0.3 (single scattering).
    assert abs(integral - valid) < 2e-3 + SIGMAS * math.sqrt(valid * (1 - valid) / 200_000)
    assert integral > (0.95 if angle > 0 else 0.85)


# --- Furnace and the radiance scale -----------------------------------------------------

@pytest.mark.windows
@pytest.mark.parametrize("ior", [1.5, 2.42])
def test_glass_sphere_vanishes_in_the_furnace(tmp_path, ior):
    # Smooth glass in a box glowing with 1: every path leaves the glass again and ends
    # on the box, its weights 1, eta^-2 and eta^2 multiplying to 1: as bright as the box.
    text = (TEST_SCENES / "furnace_mirror.scene").read_text().replace(
        "material metal mirror", f"material metal dielectric ior {ior}")
    scene_file = tmp_path / "furnace_glass.scene"
    scene_file.write_text(text)
    image = path_trace(tmp_path, "glass", "--scene", scene_file, "--width", 64,
                       "--height", 64, "--spp", 64, "--depth", 40)
    mask, _ = path_checks.named_region(image, scene_file, "sphere")
    assert mask.sum() > 300
    mean, error = mean_and_error(image[mask])  # the background is the box's 1 itself
    print(f"ior {ior}: sphere {mean} ± {error}, the box 1")
    assert np.all(np.abs(mean - 1.0) < SIGMAS * error + 1e-3), (mean, error)


def lamp_expected(scene, width, height, ior=1.5):
    """The lamp in glass_lamp.scene through the ball, pixel by pixel (pixel centres):
    (1 - F) / ior^2 where the refracted ray reaches the lamp with room to spare, NaN
    elsewhere."""
    from python_prototypes import mitsuba_reference
    eye = np.asarray(scene.camera.eye, dtype=np.float64)
    directions = mitsuba_reference.ray_directions(scene.camera, width, height)
    ball, lamp = scene.spheres
    t = sphere_t(ball.center, ball.radius, eye, directions.reshape(-1, 3)).reshape(height,
                                                                              width)
    normals = (eye + t[..., None] * directions - ball.center) / ball.radius
    cos_i = np.clip(-np.sum(normals * directions, axis=-1), 0.0, 1.0)
    F, _, _, _ = mf.fresnel_dielectric(cos_i, ior)
    # The refracted ray passes the centre at ball.radius sin(theta_t): inside the lamp?
    sin_t = np.sqrt(1.0 - cos_i**2) / ior
    reaches = np.isfinite(t) & (ball.radius * sin_t < 0.9 * lamp.radius)
    return np.where(reaches, (1.0 - F) / ior**2, np.nan)


def test_lamp_in_glass_is_dimmed_by_the_radiance_scale(tmp_path):
    image = path_trace(tmp_path, "lamp", "--scene", TEST_SCENES / "glass_lamp.scene",
                       "--width", 48, "--height", 48, "--spp", 64)
    measured, expected = assert_lamp_dimmed(image)
    page_claims.record("16-lamp-in-glass", f"{measured:.4f}")
    page_claims.record("16-lamp-expected", f"{expected:.4f}")


def lamp_through_glass():
    """(the pixels that see the lamp through the ball, the radiance each should show)
    for glass_lamp.scene at 48 x 48."""
    from python_prototypes import scene_io
    scene = scene_io.load_scene(str(TEST_SCENES / "glass_lamp.scene"), [])
    expected = lamp_expected(scene, 48, 48)
    return np.isfinite(expected), expected


def assert_lamp_dimmed(image):
    mask, expected = lamp_through_glass()
    assert mask.sum() > 200
    residual = image[mask] - expected[mask][:, None]
    mean, error = mean_and_error(residual)
    unscaled = 1.5**2 * expected[mask].mean()
    print(f"lamp through glass: {image[mask].mean():.4f}, expected "
          f"{expected[mask].mean():.4f} (without the scale: {unscaled:.4f})")
    assert np.all(np.abs(mean) < SIGMAS * error + 2e-3), (mean, error)
    return image[mask].mean(), expected[mask].mean()


# --- Mitsuba 3 ----------------------------------------------------------------------------

def mitsuba_render(scene_file, spp, size=64):
    return path_checks.mitsuba_regions(scene_file, spp, size, MESH_FOLDERS)


@pytest.fixture(scope="module")
def mitsuba_glass():
    return mitsuba_render(SCENES / "cornell_glass.scene", 1024)


@pytest.fixture(scope="module")
def mitsuba_shapes():
    return mitsuba_render(TEST_SCENES / "glass_shapes.scene", 1024)


@pytest.fixture(scope="module")
def mitsuba_gems():
    return mitsuba_render(SCENES / "cornell_gem_glass.scene", 2048)


def assert_within_two_percent(ours, reference):
    return path_checks.assert_regions_within_two_percent(ours, reference, MESH_FOLDERS)


def test_glass_spheres_agree_with_mitsuba(tmp_path, mitsuba_glass):
    ours = path_trace(tmp_path, "ours", "--width", 64, "--height", 64, "--spp", 512)
    compared = assert_within_two_percent(ours, mitsuba_glass)
    assert {"glass_sphere", "rough_glass_sphere"} <= set(compared)
    assert len(compared) >= 6


def test_glass_quads_and_triangles_agree_with_mitsuba(tmp_path, mitsuba_shapes):
    # Rays enter and leave a box of quads and a prism of triangles as they do a sphere.
    ours = path_trace(tmp_path, "shapes", "--scene", TEST_SCENES / "glass_shapes.scene",
                      "--width", 64, "--height", 64, "--spp", 512)
    compared = assert_within_two_percent(ours, mitsuba_shapes)
    assert {"glass_box", "glass_prism"} <= set(compared)


def test_glass_gems_agree_with_mitsuba(tmp_path, mitsuba_gems):
    ours = path_trace(tmp_path, "gems", "--scene", SCENES / "cornell_gem_glass.scene",
                      "--width", 64, "--height", 64, "--spp", 512)
    compared = assert_within_two_percent(ours, mitsuba_gems)
    assert {"ruby", "diamond", "emerald", "sapphire"} <= set(compared)


# Issue #16: each glass object's brightness within 2% of Mitsuba 3's, measured closely
# enough to say so. The full views above cannot: at 64 x 64 a gem is a few hundred
# pixels and its standard error 2-4.5%. So each object is seen in a close-up from the
# same eye (path_checks.close_up: the same rays meet it, the picture shaped like it),
# the region the whole object. Our noise is most of the error (Russian roulette after a
# refraction into a gem: exercise 3), so we take more samples than Mitsuba's share.
# (object, its scene, our spp, Mitsuba's spp, fewest pixels, the largest standard error)
CLOSE_UPS = {
    "glass_sphere": ("cornell_glass.scene", 512, 1024, 2000, 0.006),
    "rough_glass_sphere": ("cornell_glass.scene", 256, 1024, 2000, 0.005),
    "ruby": ("cornell_gem_glass.scene", 1536, 2048, 650, 0.0125),
    "diamond": ("cornell_gem_glass.scene", 1536, 2048, 650, 0.0125),
    "emerald": ("cornell_gem_glass.scene", 1536, 2048, 650, 0.0125),
    "sapphire": ("cornell_gem_glass.scene", 1536, 2048, 650, 0.0125),
}


def close_up_within_two_percent(tmp_path, name, shader_dir=None):
    """The close-up's comparison; returns the relative difference and its error."""
    scene, spp, mitsuba_spp, fewest, largest_error = CLOSE_UPS[name]
    extra = ["--shader-dir", shader_dir] if shader_dir else []
    relative, error, pixels, ours, theirs, scene_file = path_checks.close_up_difference(
        "16", tmp_path, SCENES / scene, name, 64, spp, mitsuba_spp, MESH_FOLDERS, extra)
    assert pixels > fewest
    assert error < largest_error  # the measurement can tell 2% from 0
    assert abs(relative) < 0.02, (name, relative, error)
    regions_agreeing(ours, theirs, scene_file, SIGMAS, MESH_FOLDERS)  # colour by colour
    return relative, error


@pytest.mark.parametrize("name", CLOSE_UPS)
def test_each_glass_object_within_two_percent_of_mitsuba(tmp_path, name):
    close_up_within_two_percent(tmp_path, name)


# --- Planted bugs ---------------------------------------------------------------------------

@pytest.mark.parametrize("bug", BUGS.values(), ids=BUGS.keys())
def test_planted_bug_fails_the_comparison_with_numpy(tmp_path, probe_queries, bug):
    answers = run_probe(shaders_with(tmp_path, bug), make_queries(*probe_queries), tmp_path)
    with pytest.raises(AssertionError):
        assert_matches_numpy(answers, *probe_queries)


def test_missing_transmission_jacobian_fails_the_chi_square_test(tmp_path):
    folder = shaders_with(tmp_path, MISSING_TRANSMISSION_JACOBIAN)
    result, _, _ = gpu_chi_square(folder, tmp_path, 0.3, -20, 1.5)
    assert not result.accepted, str(result)


def test_no_radiance_scale_fails_the_lamp_in_glass(tmp_path):
    image = path_trace(tmp_path, "lamp", "--scene", TEST_SCENES / "glass_lamp.scene",
                       "--width", 48, "--height", 48, "--spp", 64,
                       shader_dir=shaders_with(tmp_path, NO_RADIANCE_SCALE))
    with pytest.raises(AssertionError):
        assert_lamp_dimmed(image)
    lamp, expected = lamp_through_glass()
    page_claims.check("16-no-radiance-scale", image[lamp].mean() / expected[lamp].mean())
    page_claims.record("16-lamp-unscaled", f"{image[lamp].mean():.3f}")


@pytest.mark.parametrize("bug, fixture", [(FRESNEL_INDICES_SWAPPED, "mitsuba_glass"),
                                          (NO_TOTAL_INTERNAL_REFLECTION, "mitsuba_gems")],
                         ids=["fresnel_indices_swapped", "no_total_internal_reflection"])
def test_planted_bug_fails_the_comparison_with_mitsuba(tmp_path, request, bug, fixture):
    reference = request.getfixturevalue(fixture)
    ours = path_trace(tmp_path, "bug", "--scene", reference[2], "--width", 64,
                      "--height", 64, "--spp", 128, shader_dir=shaders_with(tmp_path, bug))
    with pytest.raises(AssertionError):
        assert_within_two_percent(ours, reference)


# --- Bad input ------------------------------------------------------------------------------

@pytest.mark.parametrize("material", ["dielectric ior 1.5 roughness -0.1",
                                      "dielectric ior 0", "dielectric ior -1.5"],
                         ids=["negative_roughness", "zero_ior", "negative_ior"])
def test_bad_glass_is_refused_at_its_line(tmp_path, material):
    scene = tmp_path / "bad.scene"
    scene.write_text((SCENES / "cornell_glass.scene").read_text()
                     + f"material bad {material}\n")
    lines = scene.read_text().count("\n")
    result = run_chapter("16", "--headless", "--out", tmp_path / "x.png", "--scene", scene)
    assert result.returncode == 3, result.stderr
    assert f"{scene}:{lines}:" in result.stderr
    assert not (tmp_path / "x.png").exists()
