"""Chapter 15: mirrors and metals, checked with statistics (book/docs/maintainers.md).

- The GLSL of microfacet.glsl on the GPU (tests/cpp/bsdf_probe.cpp) against
  python_prototypes/microfacet.py, query by query, to float precision; then a
  chi-square test of the GPU's samples against the GPU's own pdf.
- White furnaces: a mirror sphere in a glowing box vanishes; a rough metal reflecting
  everything (Fresnel ~1) keeps the albedo microfacet.furnace_albedo predicts.
- Mitsuba 3, region by region: each material on a sphere in the Cornell room, and the
  glossy plates.
- Planted bugs, each in a copy of the shaders, each failing the check that catches it.
- A dielectric is refused: exit code 3 at its line.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import page_claims
import path_checks
import pytest
from conftest import ROOT, regions_agreeing, run_chapter
from path_checks import SIGMAS, assert_agrees_with_mitsuba, mean_and_error

from python_prototypes import chi_square
from python_prototypes import microfacet as mf
from python_prototypes.scene_cast import sphere_t

pytestmark = pytest.mark.filterwarnings("ignore::RuntimeWarning")

PROBE_SHADER = ROOT / "tests" / "data" / "bsdf" / "bsdf_probe.comp"
SCENES = ROOT / "assets" / "scenes"
TEST_SCENES = ROOT / "tests" / "data" / "scenes"

# Measured RGB indices (Mitsuba 3.9.1's, as in assets/scenes/cornell_metals.scene).
GOLD = (np.array([0.143036, 0.375307, 1.44205]), np.array([3.983, 2.38556, 1.60336]))
COPPER = (np.array([0.201005, 0.92375, 1.10222]), np.array([3.91326, 2.45305, 2.14209]))

# The planted bugs: (file, the right line, the wrong one). Each must fail its check.
MISSING_JACOBIAN = ("microfacet.glsl", "return visibleNormalPdf(wi, m, alpha) / (4.0 * dot(wo, m));",
                    "return visibleNormalPdf(wi, m, alpha);")
HALF_VECTOR_NOT_NORMALISED = ("microfacet.glsl", """    vec3 m = normalize(wi + wo);
    float value""", """    vec3 m = wi + wo;
    float value""")
ETA_K_SWAPPED = ("microfacet.glsl", "vec2 n = vec2(eta, k)", "vec2 n = vec2(k, eta)")
# A delta vertex treated as if next-event estimation had looked after its light: the
# light it reflects is then MIS-weighted against a density of 0, so it is lost.
DELTA_GIVEN_TO_NEE = ("path.comp", "afterDelta = isDelta(material);", "afterDelta = false;")


def shaders_with(tmp_path, bug=None) -> Path:
    """A copy of the chapter's shaders (and the probe's), with one planted bug."""
    return path_checks.shaders_with_bug("15", tmp_path, bug, [PROBE_SHADER])


def path_trace(tmp_path, name, *args, shader_dir=None) -> np.ndarray:
    extra = ["--shader-dir", shader_dir] if shader_dir else []
    return path_checks.path_trace("15", tmp_path, name, *extra, *args)


# --- The GPU's microfacets against numpy ------------------------------------------------

def run_probe(shader_dir: Path, queries: np.ndarray, tmp_path: Path) -> np.ndarray:
    """Runs bsdf_probe.comp on (N, 20) float32 queries; returns the (N, 24) answers."""
    return path_checks.run_bsdf_probe(PROBE_SHADER.name, shader_dir, queries, tmp_path)


def make_queries(wi, alpha, eta, k, u, given) -> np.ndarray:
    n = len(wi)
    q = np.zeros((n, 20))
    q[:, 0:3], q[:, 3] = wi, alpha
    q[:, 4:7], q[:, 8:11] = eta, k
    q[:, 12:14] = u
    q[:, 16:19] = given
    return q


def random_directions(rng, n, min_cos=0.02):
    """Unit directions above the surface, not too close to the horizon."""
    z = rng.uniform(min_cos, 1.0, n)
    phi = rng.uniform(0, 2 * np.pi, n)
    r = np.sqrt(1 - z * z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)


@pytest.fixture(scope="module")
def probe_queries():
    rng = np.random.default_rng(15)
    n = 4000
    wi = random_directions(rng, n)
    alpha = rng.choice([0.05, 0.2, 0.5, 1.0], n)
    metal = rng.integers(0, 2, n)
    eta = np.where(metal[:, None] == 0, GOLD[0], COPPER[0])
    k = np.where(metal[:, None] == 0, GOLD[1], COPPER[1])
    u = rng.random((n, 2))
    given = random_directions(rng, n)
    return wi, alpha, eta, k, u, given


def assert_matches_numpy(answers, wi, alpha, eta, k, u, given):
    """Every quantity within float32's precision of the numpy prototype's (relative 1e-3
    where sums of squares cancel near the horizon, absolutely tiny elsewhere)."""
    def close(ours, theirs, what):
        ours, theirs = np.asarray(ours), np.asarray(theirs)
        bad = ~np.isclose(ours, theirs, rtol=2e-3, atol=1e-5)
        assert not bad.any(), (what, int(bad.sum()), ours[bad][:5], theirs[bad][:5])

    a = alpha
    fresnel, evals = np.zeros_like(eta), np.zeros_like(eta)
    for metal_eta, metal_k in (GOLD, COPPER):  # the prototype takes one RGB eta and k
        rows = np.all(eta == metal_eta, axis=-1)
        fresnel[rows] = mf.fresnel_conductor(wi[rows, 2], metal_eta, metal_k)
        evals[rows] = mf.rough_conductor_eval(wi[rows], given[rows], a[rows], metal_eta,
                                              metal_k)
    close(answers[:, 12:15], fresnel, "fresnelConductor")
    close(answers[:, 15], mf.ggx_d(given, a), "ggxD")
    close(answers[:, 16], mf.ggx_g1(wi, given, a), "ggxG1")
    close(answers[:, 17], mf.visible_normal_pdf(wi, given, a), "visibleNormalPdf")
    close(answers[:, 20:23], mf.sample_visible_normal(wi, a, u[:, 0], u[:, 1]),
          "sampleVisibleNormal")
    close(answers[:, 8:11], evals, "roughConductorEval")
    close(answers[:, 11], mf.rough_conductor_pdf(wi, given, a), "roughConductorPdf")
    wo, _, pdf = mf.rough_conductor_sample(wi, a, 1.0, 1.0, u[:, 0], u[:, 1])
    close(answers[:, 0:3], wo, "roughConductorSample: wo")
    close(answers[:, 3], pdf, "roughConductorSample: pdf")


def test_gpu_microfacets_match_the_numpy_prototype(tmp_path, probe_queries):
    answers = run_probe(shaders_with(tmp_path), make_queries(*probe_queries), tmp_path)
    assert_matches_numpy(answers, *probe_queries)


def reciprocity_error(forward, backward, wi, given):
    """The largest relative difference between f(wi, given) and f(given, wi), from evals
    that carry the cosine of their second direction; both directions above the surface."""
    up = (wi[:, 2] > 0.05) & (given[:, 2] > 0.05)
    f_forward = forward[up] / given[up, 2:3]
    f_backward = backward[up] / wi[up, 2:3]
    scale = np.maximum(np.abs(f_forward), 1e-6)
    return float(np.max(np.abs(f_forward - f_backward) / scale))


def test_rough_conductor_is_reciprocal(tmp_path, probe_queries):
    """f(wi, wo) = f(wo, wi): light runs both ways (Helmholtz). The GPU's eval with the
    two directions swapped; and, to show the check can fail, the prototype with the
    masking of one direction squared instead of multiplied by the other's."""
    wi, alpha, eta, k, u, given = probe_queries
    folder = shaders_with(tmp_path)
    forward = run_probe(folder, make_queries(wi, alpha, eta, k, u, given), tmp_path)[:, 8:11]
    backward = run_probe(folder, make_queries(given, alpha, eta, k, u, wi), tmp_path)[:, 8:11]
    assert reciprocity_error(forward, backward, wi, given) < 5e-3

    def one_sided(a, b, m, alpha):  # G1(a)^2: not symmetric in a and b
        return mf.ggx_g1(a, m, alpha) ** 2
    wrong_forward = mf.rough_conductor_eval(wi, given, alpha, GOLD[0], GOLD[1], g2=one_sided)
    wrong_backward = mf.rough_conductor_eval(given, wi, alpha, GOLD[0], GOLD[1], g2=one_sided)
    assert reciprocity_error(wrong_forward, wrong_backward, wi, given) > 0.05


def test_sample_weight_is_eval_over_pdf(tmp_path, probe_queries):
    # Ask eval and pdf about the very direction the sampler chose.
    wi, alpha, eta, k, u, _ = probe_queries
    folder = shaders_with(tmp_path)
    sampled = run_probe(folder, make_queries(*probe_queries), tmp_path)
    wo, pdf, weight = sampled[:, 0:3], sampled[:, 3], sampled[:, 4:7]
    again = run_probe(folder, make_queries(wi, alpha, eta, k, u, wo), tmp_path)
    valid = pdf > 0
    assert valid.mean() > 0.8
    np.testing.assert_allclose(again[valid, 11], pdf[valid], rtol=1e-3)
    np.testing.assert_allclose(again[valid, 8:11] / pdf[valid, None], weight[valid],
                               rtol=1e-3, atol=1e-6)


CHI_SQUARE_CASES = [(angle, alpha) for alpha in (0.1, 0.5) for angle in (10, 50, 80)]


def gpu_chi_square(folder, tmp_path, angle, alpha, samples=200_000):
    """The GPU's sampled directions against the GPU's own pdf, over the sphere."""
    theta = math.radians(angle)
    wi = np.array([math.sin(theta), 0.0, math.cos(theta)])
    eta, k = COPPER

    def sample_directions(rng, count):
        u = rng.random((count, 2))
        answers = run_probe(folder, make_queries(np.tile(wi, (count, 1)), alpha, eta, k,
                                                 u, np.tile(wi, (count, 1))), tmp_path)
        return answers[:, 0:3], answers[:, 3] > 0

    def pdf(directions):
        flat = directions.reshape(-1, 3)
        n = len(flat)
        answers = run_probe(folder, make_queries(np.tile(wi, (n, 1)), alpha, eta, k,
                                                 np.zeros((n, 2)), flat), tmp_path)
        return answers[:, 11].reshape(directions.shape[:-1])

    return chi_square.chi_square_test(sample_directions, pdf, samples, seed=angle,
                                      test_count=len(CHI_SQUARE_CASES))


@pytest.mark.parametrize("angle, alpha", CHI_SQUARE_CASES)
def test_gpu_samples_have_the_gpu_pdf(tmp_path, angle, alpha):
    result = gpu_chi_square(shaders_with(tmp_path), tmp_path, angle, alpha)
    print(f"θi {angle}°, alpha {alpha}: {result}")
    assert result.accepted, str(result)


# --- White furnaces ---------------------------------------------------------------------

@pytest.mark.windows
@pytest.mark.parametrize("estimator", ["nee", "mis"])
def test_mirror_sphere_vanishes_in_the_furnace(tmp_path, estimator):
    # A perfect mirror in a box glowing with 1 reflects the box: as bright as the box.
    # (Without the special case at a delta vertex, MIS would weigh its light to 0.)
    image = path_trace(tmp_path, "mirror", "--scene", TEST_SCENES / "furnace_mirror.scene",
                       "--width", 48, "--height", 48, "--spp", 8, "--estimator", estimator)
    mask, _ = path_checks.named_region(image, TEST_SCENES / "furnace_mirror.scene", "sphere")
    assert mask.sum() > 100
    np.testing.assert_allclose(image[mask], 1.0, atol=1e-4)


def albedo_table(alpha, angles=np.arange(0.0, 90.0, 2.0)):
    return angles, np.array([mf.furnace_albedo(a, alpha, count=60_000, seed=1)[0]
                             for a in angles])


@pytest.mark.parametrize("alpha", [0.3, 1.0])
def test_rough_metal_in_the_furnace_keeps_the_predicted_albedo(tmp_path, alpha):
    # A rough metal with k = 1000 reflects 99.9996% at every angle (Fresnel ~1): in a box
    # glowing with 1, each pixel shows the share of light single scattering keeps at its
    # angle of incidence, microfacet.furnace_albedo (1 for a mirror, less the rougher).
    text = (TEST_SCENES / "furnace_mirror.scene").read_text().replace(
        "material metal mirror", f"material metal conductor eta 1 1 1 k 1000 1000 1000 "
        f"roughness {alpha}")
    scene_file = tmp_path / "furnace_rough.scene"
    scene_file.write_text(text)
    image = path_trace(tmp_path, "rough", "--scene", scene_file, "--width", 48,
                       "--height", 48, "--spp", 64)
    mask, scene = path_checks.named_region(image, scene_file, "sphere")
    from python_prototypes import mitsuba_reference
    eye = np.asarray(scene.camera.eye)
    directions = mitsuba_reference.ray_directions(scene.camera, 48, 48)[mask]
    sphere = scene.spheres[0]
    t = sphere_t(sphere.center, sphere.radius, eye, directions)
    normals = (eye + t[:, None] * directions - sphere.center) / sphere.radius
    angles = np.degrees(np.arccos(np.clip(-np.sum(normals * directions, axis=-1), 0, 1)))
    table_angles, table = albedo_table(alpha)
    expected = np.interp(angles, table_angles, table).mean()
    mean, error = mean_and_error(image[mask])
    print(f"alpha {alpha}: sphere {mean}, predicted {expected:.4f}")
    page_claims.record(f"15-furnace-measured-{alpha}", f"{mean.mean():.3f}")
    page_claims.record(f"15-furnace-predicted-{alpha}", f"{expected:.3f}")
    assert np.all(np.abs(mean - expected) < SIGMAS * error + 0.004), (mean, expected)
    if alpha == 1.0:
        assert expected < 0.95  # single scattering loses light: the test can tell


# --- Mitsuba 3 ----------------------------------------------------------------------------

@pytest.fixture(scope="module")
def mitsuba_metals():
    """Mitsuba 3's render of cornell_metals at 64 x 64, 1024 spp."""
    from python_prototypes import scene_io
    scene = scene_io.load_scene(str(SCENES / "cornell_metals.scene"), [])
    return path_checks.kept_mitsuba(scene, 64, 64, 1024, 6, seed=0)


def assert_agrees_in_every_region(ours, mitsuba_metals):
    """Every region (walls and spheres) within 4.5 standard errors of Mitsuba's
    (conftest.regions_agreeing: an error bar a region only too dark cannot widen)."""
    return regions_agreeing(ours, mitsuba_metals, SCENES / "cornell_metals.scene", SIGMAS)


def test_cornell_metals_agrees_with_mitsuba(tmp_path, mitsuba_metals):
    # A mirror, smooth copper and rough gold (alpha 0.2) in the Cornell room.
    ours = path_trace(tmp_path, "ours", "--width", 64, "--height", 64, "--spp", 512)
    compared = assert_agrees_in_every_region(ours, mitsuba_metals)
    assert {"mirror_sphere", "copper_sphere", "gold_sphere"} <= set(compared)
    assert len(compared) >= 8


@pytest.mark.parametrize("sphere", ["mirror_sphere", "copper_sphere", "gold_sphere"])
def test_each_metal_within_two_percent_of_mitsuba(tmp_path, sphere):
    # Issue #16: each metal's brightness within 2% of Mitsuba 3's, measured closely
    # enough to say so: the sphere in a close-up from the same eye (path_checks.close_up,
    # 1,500-2,400 pixels) at 256 spp against Mitsuba's 1024, a standard error of
    # 0.25-0.75% (the lamp in the copper and the mirror is most of their noise).
    relative, error, pixels, ours, theirs, scene_file = path_checks.close_up_difference(
        "15", tmp_path, SCENES / "cornell_metals.scene", sphere, 64, 256, 1024)
    assert pixels > 1200
    assert error < 0.01  # the measurement can tell 2% from 0
    assert abs(relative) < 0.02, (sphere, relative, error)
    regions_agreeing(ours, theirs, scene_file, SIGMAS)  # and colour by colour


def test_glossy_plates_agree_with_mitsuba(tmp_path):
    # Rough aluminium from alpha 0.01 to 0.3 under lamps of four sizes.
    ours = path_trace(tmp_path, "plates", "--scene", SCENES / "glossy_plates.scene",
                      "--width", 96, "--height", 72, "--spp", 128)
    compared = assert_agrees_with_mitsuba(ours, spp=512,
                                          scene_file=SCENES / "glossy_plates.scene")
    assert {"plate1", "plate2", "plate3", "plate4"} <= set(compared)


@pytest.fixture(scope="module")
def plate_images(tmp_path_factory):
    folder = tmp_path_factory.mktemp("plates")
    return {estimator: path_trace(folder, estimator, "--scene",
                                  SCENES / "glossy_plates.scene", "--width", 96,
                                  "--height", 72, "--spp", 128, "--seed", seed,
                                  "--estimator", estimator)
            for seed, estimator in enumerate(["nee", "bsdf", "mis"], start=1)}


@pytest.mark.parametrize("pair", [("nee", "mis"), ("bsdf", "mis")])
def test_estimators_agree_on_the_glossy_plates(plate_images, pair):
    a, b = (plate_images[name] for name in pair)
    compared = regions_agreeing(a, b, SCENES / "glossy_plates.scene", SIGMAS)
    assert len(compared) >= 5


def test_each_estimator_wins_where_the_page_says(plate_images):
    # The page's map (Veach's thesis, section 9.2): light sampling wins on the rough back
    # plate where it reflects the small lamps (its left half), BSDF sampling on the
    # polished front plate where it reflects the large ones (its right half). Each one's
    # error against Mitsuba there, at the same samples, is under a third of the other's.
    pytest.importorskip("mitsuba")
    from python_prototypes import scene_io
    scene_file = SCENES / "glossy_plates.scene"
    scene = scene_io.load_scene(str(scene_file), [])
    reference = path_checks.kept_mitsuba(scene, 96, 72, 512, 6, seed=0, variant="scalar_rgb")

    def error(estimator, plate, half):
        mask, _ = path_checks.named_region(reference, scene_file, plate)
        columns = np.flatnonzero(mask.any(axis=0))
        middle = (columns.min() + columns.max() + 1) // 2
        mask = mask.copy()
        if half == "left":
            mask[:, middle:] = False
        else:
            mask[:, :middle] = False
        assert mask.sum() >= 20, (plate, half, mask.sum())
        difference = plate_images[estimator][mask] - reference[mask]
        return float(np.sqrt(np.mean(difference ** 2)))

    rough = {e: error(e, "plate4", "left") for e in ("nee", "bsdf")}
    polished = {e: error(e, "plate1", "right") for e in ("nee", "bsdf")}
    print(f"RMSE, rough plate and small lamps: {rough}; polished plate and large lamps: "
          f"{polished}")
    assert rough["nee"] < rough["bsdf"] / 3
    assert polished["bsdf"] < polished["nee"] / 3


# --- Planted bugs ---------------------------------------------------------------------------

@pytest.mark.parametrize("bug", [MISSING_JACOBIAN, HALF_VECTOR_NOT_NORMALISED, ETA_K_SWAPPED],
                         ids=["missing_jacobian", "half_vector_not_normalised",
                              "eta_k_swapped"])
def test_planted_bug_fails_the_comparison_with_numpy(tmp_path, probe_queries, bug):
    answers = run_probe(shaders_with(tmp_path, bug), make_queries(*probe_queries), tmp_path)
    with pytest.raises(AssertionError):
        assert_matches_numpy(answers, *probe_queries)


def test_missing_jacobian_fails_the_chi_square_test(tmp_path):
    result = gpu_chi_square(shaders_with(tmp_path, MISSING_JACOBIAN), tmp_path, 50, 0.5)
    assert not result.accepted, str(result)


@pytest.mark.parametrize("bug", [MISSING_JACOBIAN, HALF_VECTOR_NOT_NORMALISED, ETA_K_SWAPPED],
                         ids=["missing_jacobian", "half_vector_not_normalised",
                              "eta_k_swapped"])
def test_planted_bug_fails_the_comparison_with_mitsuba(tmp_path, bug, mitsuba_metals):
    ours = path_trace(tmp_path, "bug", "--width", 64, "--height", 64, "--spp", 256,
                      shader_dir=shaders_with(tmp_path, bug))
    with pytest.raises(AssertionError):
        assert_agrees_in_every_region(ours, mitsuba_metals)


def test_missing_jacobian_darkens_the_rough_gold_as_the_page_says(tmp_path, mitsuba_metals):
    # The pdf 4 (wo . m) times too large shrinks each sample's weight: the rough gold
    # darker than Mitsuba's, and by more than its noise (the page's sentence is checked
    # against this ratio, page_claims).
    ours = path_trace(tmp_path, "bug", "--width", 64, "--height", 64, "--spp", 256,
                      shader_dir=shaders_with(tmp_path, MISSING_JACOBIAN))
    mask, _ = path_checks.named_region(ours, SCENES / "cornell_metals.scene", "gold_sphere")
    ratio = ours[mask].mean() / mitsuba_metals[mask].mean()
    brightness_difference = (ours[mask] - mitsuba_metals[mask]).mean(axis=-1, keepdims=True)
    mean, error = mean_and_error(brightness_difference)
    print(f"gold with the Jacobian left out / Mitsuba: {ratio:.3f}")
    assert abs(mean) > SIGMAS * error, (mean, error)
    page_claims.check("15-missing-jacobian", ratio)


def test_delta_bsdf_given_to_nee_fails_the_mirror_furnace(tmp_path):
    image = path_trace(tmp_path, "bug", "--scene", TEST_SCENES / "furnace_mirror.scene",
                       "--width", 48, "--height", 48, "--spp", 8,
                       shader_dir=shaders_with(tmp_path, DELTA_GIVEN_TO_NEE))
    mask, _ = path_checks.named_region(image, TEST_SCENES / "furnace_mirror.scene", "sphere")
    assert not np.allclose(image[mask], 1.0, atol=1e-4)
    assert image[mask].mean() < 0.5  # the mirror shows black


# --- Bad input ------------------------------------------------------------------------------

def test_glass_is_refused_at_its_line(tmp_path):
    scene = tmp_path / "glass.scene"
    scene.write_text((SCENES / "cornell_metals.scene").read_text()
                     + "material glass dielectric ior 1.5\n")
    lines = scene.read_text().count("\n")
    result = run_chapter("15", "--headless", "--out", tmp_path / "x.png", "--scene", scene)
    assert result.returncode == 3, result.stderr
    assert f"{scene}:{lines}:" in result.stderr
    assert "dielectric" in result.stderr and "chapter 16" in result.stderr
