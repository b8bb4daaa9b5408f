"""Chapter 18: the environment light's importance sampling, and the light it gives
(book/docs/maintainers.md).

- The sampler on the GPU: environment.glsl's sampleEnvironment (its direction, pdf and
  the radiance of the pixel it drew), environmentPdf and
  environmentRadiance (tests/data/environment/environment_probe.comp through
  tests/cpp/bsdf_probe.cpp, the map's texels and tables bound as the chapter binds
  them) against python_prototypes/environment_sampling.py for the same uniform
  numbers and the same tables, built from the map as environment.cpp builds them; the
  GPU's pdf integrates to 1 over the sphere; the GPU's samples have the GPU's pdf (a
  chi-square test over cells of a world latitude-longitude grid, the map turned or
  not). Planted bugs: a pdf without sin(theta), a map read upside down.
- Mitsuba 3, region by region: the sky alone lighting a diffuse and a rough metal
  sphere on a diffuse ground; the spots map with a small area light and a diffuse
  sphere.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import path_checks
import pytest
from conftest import ROOT

from python_prototypes import environment_map
from python_prototypes import environment_sampling
from python_prototypes import pfm
from python_prototypes import sky

PROBE_SHADER = ROOT / "tests" / "data" / "environment" / "environment_probe.comp"
TEST_SCENES = ROOT / "tests" / "data" / "scenes"
ASSETS = ROOT / "build" / "assets"
MESH_FOLDERS = [ASSETS]
MAPS = {"sky": ASSETS / "environments" / "sky.pfm",
        "spots": ASSETS / "environments" / "spots.pfm"}

# shared.h's bindings, which the probe's buffers take.
TEXELS_BINDING, ENVIRONMENT_CDF_BINDING = 14, 16
# The map's texels start after a few others, as they follow the images' in the chapter:
# a lookup that ignores environmentFirstTexel reads these.
FIRST_TEXEL = 7
JUNK = 1.0e6
PROBE_BATCH = 1_000_000

# The planted bugs: (file, the right text, the wrong one).
# (Parts of lines: a starter ships this file, and no whole line of a solution.)
NO_SIN_THETA = ("environment.glsl", "(2.0 * PI * PI * sinTheta)", "(2.0 * PI * PI)")
UPSIDE_DOWN = ("environment.glsl", "u < 0.0 ? u + 1.0 : u, acos(clamp(d.y, -1.0, 1.0)) / PI",
               "u < 0.0 ? u + 1.0 : u, 1.0 - acos(clamp(d.y, -1.0, 1.0)) / PI")

# (map, scale, rotate_y degrees): the sky as the showcase has it, the spots map turned
# by a fraction of a pixel's width too (6.6 of its 64 columns).
CASES = {"sky": ("sky", 0.02, -60.0), "spots": ("spots", 1.0, 0.0),
         "spots_turned": ("spots", 2.5, 37.0)}


def shaders_with(tmp_path, bug=None) -> Path:
    return path_checks.shaders_with_bug("18", tmp_path, bug, [PROBE_SHADER])


# --- The tables, as environment.cpp builds them --------------------------------------------

def host_tables(image: np.ndarray, scale: float):
    """environment.cpp's loadEnvironment in numpy, float32 where it computes in float:
    the scaled radiance (H, W, 3), and the tables (H + 1 + H (W + 1),): the marginal CDF
    over rows of sum(luminance x sin theta at the pixel's centre), then each row's
    conditional CDF, each a running sum in double divided by its total, as float."""
    radiance = np.float32(scale) * np.asarray(image, dtype=np.float32)
    height, width = radiance.shape[:2]
    angle = (np.float32(3.14159265358979) * (np.arange(height, dtype=np.float32)
                                             + np.float32(0.5)) / np.float32(height))
    sin_theta = np.sin(angle.astype(np.float64)).astype(np.float32)  # sinf, rounded
    r, g, b = radiance[..., 0], radiance[..., 1], radiance[..., 2]
    luminance = np.float32(0.2126) * r + np.float32(0.7152) * g + np.float32(0.0722) * b
    weights = luminance * sin_theta[:, None]
    row_weights = np.cumsum(weights, axis=1, dtype=np.float32)[:, -1]  # float, in order

    def cdf(w):  # appendCdf: count + 1 numbers, exactly 0 first and 1 last
        sums = np.cumsum(np.asarray(w, dtype=np.float64))
        total = sums[-1]
        inner = sums[:-1] / total if total > 0 else np.arange(1, len(w)) / len(w)
        return np.concatenate([[0.0], inner.astype(np.float32), [1.0]]).astype(np.float32)
    tables = [cdf(row_weights)] + [cdf(weights[row]) for row in range(height)]
    return radiance, np.concatenate(tables)


def prototype_sampler(radiance: np.ndarray, tables: np.ndarray):
    """environment_sampling.EnvironmentSampler holding the host's tables: P(r, c) the
    product of the two steps, as pixelPdf takes it (the float32 CDF's own steps, which
    are what the sampler draws with)."""
    height, width = radiance.shape[:2]
    marginal = tables[:height + 1].astype(np.float64)
    conditional = tables[height + 1:].reshape(height, width + 1).astype(np.float64)
    probability = np.diff(marginal)[:, None] * np.diff(conditional, axis=1)
    return environment_sampling.EnvironmentSampler(radiance.astype(np.float64), marginal,
                                                   conditional, probability)


# --- The probe -----------------------------------------------------------------------------

class Probe:
    """One map (a CASES entry) on the GPU: its texels and tables written once, queried
    through the probe shader of a shader folder (the chapter's, or one with a bug)."""

    def __init__(self, case: str, shader_dir: Path, tmp_path: Path):
        name, self.scale, self.degrees = CASES[case]
        self.image = environment_map.read_map(MAPS[name])
        self.radiance, self.tables = host_tables(self.image, self.scale)
        self.height, self.width = self.radiance.shape[:2]
        self.sampler = prototype_sampler(self.radiance, self.tables)
        self.world_from_map = environment_map.map_from_world(self.degrees).T
        self.shader_dir, self.folder = shader_dir, tmp_path
        texels = np.full((FIRST_TEXEL + self.width * self.height, 4), JUNK, np.float32)
        texels[FIRST_TEXEL:, :3] = self.radiance.reshape(-1, 3)
        texels[FIRST_TEXEL:, 3] = 0.0
        self.texels_file = tmp_path / f"{case}_texels.f32"
        self.tables_file = tmp_path / f"{case}_tables.f32"
        texels.tofile(self.texels_file)
        self.tables.tofile(self.tables_file)

    def run(self, u: np.ndarray, directions: np.ndarray) -> np.ndarray:
        """(N, 24) answers for uniform pairs u (N, 2) and unit directions (N, 3), a
        million queries a run (the answers' buffer within GL's 128 MB of a block)."""
        if len(u) > PROBE_BATCH:
            return np.concatenate([self.run(u[i:i + PROBE_BATCH], directions[i:i + PROBE_BATCH])
                                   for i in range(0, len(u), PROBE_BATCH)])
        queries = np.zeros((len(u), 20), np.float32)
        queries[:, 0:2] = u
        queries[:, 4:7] = directions
        queries[:, 8:12] = (self.width, self.height, FIRST_TEXEL,
                            np.float32(math.radians(self.degrees)))
        return path_checks.run_bsdf_probe(
            PROBE_SHADER.name, self.shader_dir, queries, self.folder,
            {TEXELS_BINDING: self.texels_file, ENVIRONMENT_CDF_BINDING: self.tables_file})

    def sample(self, u: np.ndarray):
        """The GPU's sampled directions (N, 3) and pdfs (N,)."""
        answers = self.run(u, np.tile([0.0, 1.0, 0.0], (len(u), 1)))
        return answers[:, 0:3], answers[:, 3]

    def at(self, directions: np.ndarray):
        """The GPU's environmentRadiance (N, 3) and environmentPdf (N,) along directions."""
        answers = self.run(np.full((len(directions), 2), 0.5), directions)
        return answers[:, 4:7], answers[:, 7]

    def in_map(self, directions: np.ndarray) -> np.ndarray:
        return directions @ self.world_from_map  # the inverse turn: map from world

    def expected_at(self, directions: np.ndarray):
        """numpy's radiance and pdf along world directions (environment_map's lookup,
        environment_sampling's pdf in the map's frame)."""
        radiance = environment_map.lookup_nearest(self.image, directions, self.scale,
                                                  self.degrees)
        return radiance, self.sampler.pdf(self.in_map(directions))


def uniform_numbers(rng, count) -> np.ndarray:
    """Pairs in [0, 1) that float32 holds exactly, so both sides see the same numbers."""
    return (rng.integers(0, 1 << 24, (count, 2)) / float(1 << 24)).astype(np.float32)


def uniform_directions(rng, count) -> np.ndarray:
    d = rng.standard_normal((count, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def clear_of_pixel_edges(probe: Probe, directions: np.ndarray, margin=0.02) -> np.ndarray:
    """The directions at least `margin` of a pixel from their pixel's edges and from the
    poles: the GPU's acos and atan are approximations (Mesa's lowering errs by up to
    ~1e-5 radians), which may put a direction near an edge into either pixel."""
    u, v = sky.direction_to_uv(probe.in_map(directions))
    x, y = u * probe.width, v * probe.height
    return ((np.abs(x - np.round(x)) > margin) & (np.abs(y - np.round(y)) > margin)
            & (np.abs(directions[:, 1]) < 0.9999))


# --- The GPU against numpy ---------------------------------------------------------------

def test_the_host_tables_are_the_prototypes():
    """host_tables (environment.cpp in numpy) and environment_sampling's from_image
    build the same CDFs, to float32 rounding (a few units in the last place of 1)."""
    for case in ("sky", "spots"):
        name, scale, _ = CASES[case]
        image = environment_map.read_map(MAPS[name])
        ours = prototype_sampler(*host_tables(image, scale))
        theirs = environment_sampling.EnvironmentSampler.from_image(image.astype(np.float64))
        np.testing.assert_allclose(ours.marginal_cdf, theirs.marginal_cdf, atol=3e-7)
        np.testing.assert_allclose(ours.conditional_cdf, theirs.conditional_cdf, atol=3e-7)


@pytest.mark.parametrize("case", list(CASES))
def test_gpu_samples_match_the_numpy_prototype(tmp_path, case):
    """The same u, the same tables: the same pixel, the same point in it (to float32's
    precision) and the same pdf; and the pdf at the sampled direction is the pdf the
    sampler gave."""
    probe = Probe(case, shaders_with(tmp_path), tmp_path)
    u = uniform_numbers(np.random.default_rng(1), 50_000)
    directions, pdf = probe.sample(u)
    expected, expected_pdf, _ = probe.sampler.sample(u[:, 0].astype(np.float64),
                                                     u[:, 1].astype(np.float64))
    expected = expected @ probe.world_from_map.T
    np.testing.assert_allclose(directions, expected, atol=2e-5)
    usable = expected_pdf > 0
    assert usable.mean() > 0.999
    np.testing.assert_allclose(pdf[usable], expected_pdf[usable], rtol=2e-3)
    answers = probe.run(u, directions)
    clear = clear_of_pixel_edges(probe, directions)
    assert clear.mean() > 0.9
    np.testing.assert_allclose(answers[clear, 11], pdf[clear], rtol=2e-3)
    np.testing.assert_allclose(answers[clear, 8:11], probe.sampler.radiance(
        probe.in_map(directions[clear])), rtol=1e-6)


@pytest.mark.parametrize("case", list(CASES))
def test_each_sample_brings_its_own_pixels_radiance(tmp_path, case):
    """sampleEnvironment hands back the radiance of the pixel it drew, not a lookup of
    the direction again (which near an edge may find the neighbour: a firefly next to
    the sun). Drawn in proportion to luminance x sin(theta) at the pixel's centre,
    every sample's luminance over its pdf, times sin(theta) there over sin(theta)
    where the sample is, is one number: 2 pi^2 / (W H) x the sum of the weights, the
    sun's samples and the sky's alike."""
    probe = Probe(case, shaders_with(tmp_path), tmp_path)
    u = uniform_numbers(np.random.default_rng(4), 200_000)
    answers = probe.run(u, np.tile([0.0, 1.0, 0.0], (len(u), 1)))
    in_map, _, (row, column) = probe.sampler.sample(u[:, 0].astype(np.float64),
                                                    u[:, 1].astype(np.float64))
    np.testing.assert_array_equal(answers[:, 12:15], probe.radiance[row, column])
    weights = (probe.radiance.astype(np.float64) @ [0.2126, 0.7152, 0.0722]
               * np.sin(np.pi * (np.arange(probe.height) + 0.5) / probe.height)[:, None])
    constant = 2 * np.pi ** 2 / (probe.width * probe.height) * weights.sum()
    sin_theta = np.hypot(in_map[:, 0], in_map[:, 2])
    centre = np.sin(np.pi * (row + 0.5) / probe.height)
    usable = (answers[:, 3] > 0) & (sin_theta > 0.01)
    assert usable.mean() > 0.99
    value = (answers[:, 12:15] @ [0.2126, 0.7152, 0.0722]) / answers[:, 3] * centre / sin_theta
    # Float32 steps of the CDF round a dim pixel's chance by up to ~0.5% where the
    # sun's row climbs near 1; a neighbour's radiance would be off by 1000 times.
    np.testing.assert_allclose(value[usable], constant, rtol=1e-2)


@pytest.mark.parametrize("case", list(CASES))
def test_gpu_pdf_and_radiance_along_any_direction_match_numpy(tmp_path, case):
    probe = Probe(case, shaders_with(tmp_path), tmp_path)
    directions = uniform_directions(np.random.default_rng(2), 50_000)
    radiance, pdf = probe.at(directions)
    expected_radiance, expected_pdf = probe.expected_at(directions)
    clear = clear_of_pixel_edges(probe, directions)
    assert clear.mean() > 0.9
    np.testing.assert_allclose(radiance[clear], expected_radiance[clear], rtol=1e-6)
    np.testing.assert_allclose(pdf[clear], expected_pdf[clear], rtol=2e-3)
    assert radiance.max() < JUNK  # the map's texels, not those before them


def test_a_map_read_upside_down_is_caught(tmp_path):
    probe = Probe("sky", shaders_with(tmp_path, UPSIDE_DOWN), tmp_path)
    directions = uniform_directions(np.random.default_rng(2), 20_000)
    radiance, pdf = probe.at(directions)
    expected_radiance, expected_pdf = probe.expected_at(directions)
    wrong = np.abs(radiance - expected_radiance).max(axis=1) > 0.01 * expected_radiance.max(axis=1)
    print(f"radiance off by over 1% along {wrong.mean():.0%} of the directions, the pdf "
          f"along {np.mean(np.abs(pdf / expected_pdf - 1) > 0.01):.0%}")
    assert wrong.mean() > 0.5
    assert np.mean(np.abs(pdf / expected_pdf - 1) > 0.01) > 0.5


# --- The pdf over the sphere ----------------------------------------------------------------

def cell_probabilities(probe: Probe, columns: int, rows: int) -> np.ndarray:
    """The GPU's environmentPdf integrated over each cell of a world latitude-longitude
    grid (rows, columns), rows a whole number of the map's. The pdf x sin(theta) is
    constant over each of the map's pixels, which a turn about y shifts in u only: the
    cells are cut where the map's columns start, and each piece's midpoint gives its
    integral exactly, pdf x 2 pi^2 sin(theta) du dv."""
    assert probe.height % rows == 0
    shift = sky.direction_to_uv(np.array([0.0, 0.0, -1.0]) @ probe.world_from_map.T)[0]
    map_edges = (np.arange(probe.width) / probe.width + shift) % 1.0
    edges = np.unique(np.concatenate([np.arange(columns + 1) / columns, map_edges]))
    u_middle, du = (edges[1:] + edges[:-1]) / 2, np.diff(edges)
    keep = du > 1e-9  # an edge of both, rounded apart
    u_middle, du = u_middle[keep], du[keep]
    v_middle = (np.arange(probe.height) + 0.5) / probe.height
    grid_u, grid_v = np.meshgrid(u_middle, v_middle)
    _, pdf = probe.at(sky.uv_to_direction(grid_u, grid_v).reshape(-1, 3))
    mass = (pdf.reshape(grid_u.shape) * 2 * np.pi ** 2 * np.sin(np.pi * grid_v)
            * du[None, :] / probe.height)
    column = np.minimum((u_middle * columns).astype(int), columns - 1)
    per_column = np.zeros((probe.height, columns))
    np.add.at(per_column, (slice(None), column), mass)
    return per_column.reshape(rows, probe.height // rows, columns).sum(axis=1)


@pytest.mark.parametrize("case", list(CASES))
def test_the_gpu_pdf_integrates_to_one(tmp_path, case):
    probe = Probe(case, shaders_with(tmp_path), tmp_path)
    total = cell_probabilities(probe, 64, probe.height // 4 if case == "sky" else 32).sum()
    assert abs(total - 1.0) < 1e-4, total


def test_a_pdf_without_sin_theta_is_caught(tmp_path):
    probe = Probe("sky", shaders_with(tmp_path, NO_SIN_THETA), tmp_path)
    total = cell_probabilities(probe, 64, 64).sum()
    assert abs(total - 1.0) > 0.05, total
    u = uniform_numbers(np.random.default_rng(1), 20_000)
    _, pdf = probe.sample(u)
    _, expected_pdf, _ = probe.sampler.sample(u[:, 0].astype(np.float64),
                                              u[:, 1].astype(np.float64))
    assert np.mean(np.abs(pdf / expected_pdf - 1) > 0.01) > 0.5
    assert gpu_chi_square(probe, 500_000).p_value < 1e-6


# --- Chi-square -----------------------------------------------------------------------------

CHI_SQUARE = {"sky": (128, 64, 2_000_000), "spots": (64, 32, 1_000_000),
              "spots_turned": (64, 32, 1_000_000)}  # cells across, down; samples
LEVEL = 0.01 / len(CHI_SQUARE)  # Bonferroni: a correct sampler fails one in a hundred


class ChiSquare:
    def __init__(self, statistic, dof, p_value):
        self.statistic, self.dof, self.p_value = statistic, dof, p_value

    def __str__(self):
        return f"X² = {self.statistic:.1f}, {self.dof} degrees of freedom, p = {self.p_value:.3g}"


def gpu_chi_square(probe: Probe, samples: int, columns=None, rows=None) -> ChiSquare:
    """The GPU's samples counted in the cells of a world latitude-longitude grid against
    the counts its environmentPdf expects there (environment_sampling.chi_square_test:
    cells expecting few pooled, samples where none are expected a failure)."""
    columns = columns or CHI_SQUARE["sky"][0]
    rows = rows or CHI_SQUARE["sky"][1]
    rng = np.random.default_rng(3)
    directions, _ = probe.sample(uniform_numbers(rng, samples))
    row, column = sky.pixel_of_direction(directions, columns, rows)
    observed = environment_sampling.sample_counts(row, column, columns, rows)
    expected = samples * cell_probabilities(probe, columns, rows)
    return ChiSquare(*environment_sampling.chi_square_test(observed, expected))


@pytest.mark.parametrize("case", list(CHI_SQUARE))
def test_gpu_samples_have_the_gpu_pdf(tmp_path, case):
    columns, rows, samples = CHI_SQUARE[case]
    probe = Probe(case, shaders_with(tmp_path), tmp_path)
    result = gpu_chi_square(probe, samples, columns, rows)
    print(f"{case}: {result}")
    assert result.dof > 500  # cells enough to see the map's structure
    assert result.p_value > LEVEL, str(result)


# --- A floor under the sky --------------------------------------------------------------------

FLOOR = """camera eye 0 1 0 look 0 -1 0 up 0 0 -1 focal 0.035 sensor 0.036
material floor albedo {albedo} {albedo} {albedo}
quad -100 0 100   200 0 0   0 0 -200   floor name floor
environment {map} scale 0.02 rotate_y 20
"""


def floor_under_the_sky(tmp_path, estimator, shader_dir=None):
    """A white floor seen from straight above, lit by the sky alone (direct light):
    each pixel's radiance is albedo / pi x the upward irradiance of the map, exactly as
    its pixels are read (sky.upward_irradiance). Returns (image, that radiance)."""
    scene = tmp_path / "floor.scene"
    scene.write_text(FLOOR.format(albedo=0.8, map=MAPS["sky"]))
    extra = ["--shader-dir", shader_dir] if shader_dir else []
    image = path_checks.path_trace("18", tmp_path, "floor", "--scene", scene, "--width", 64,
                                   "--height", 64, "--spp", 1024, "--depth", 1, "--estimator",
                                   estimator, *extra)
    exact = 0.8 / math.pi * 0.02 * sky.upward_irradiance(environment_map.read_map(MAPS["sky"]))
    return image, exact


@pytest.mark.parametrize("estimator", ["nee", "mis"])
def test_a_floor_under_the_sky_gets_its_irradiance_without_fireflies(tmp_path, estimator):
    """Light sampling draws each pixel of the map in proportion to its luminance, so
    L cos / pdf hardly varies from sample to sample: no pixel far brighter than the
    rest (4 million samples: the brightest pixel 1.07 x the mean). A sample that takes
    its radiance from another pixel of the map than the one it was drawn in is a
    firefly, ~1000 times the mean next to the sun, and the many that lose the sun to its
    neighbour leave the mean short: looking the sampled direction up again through the
    GPU's approximate acos and atan does that to ~0.5% of the samples."""
    image, exact = floor_under_the_sky(tmp_path, estimator)
    mean, error = path_checks.mean_and_error(image)
    print(f"{estimator}: {mean} against {exact} (error {error}); brightest pixel "
          f"{image.mean(axis=2).max() / image.mean():.2f} x the mean")
    assert np.all(np.abs(mean - exact) < path_checks.SIGMAS * error + 1e-4 * exact)
    assert image.mean(axis=2).max() < 1.5 * image.mean()  # 1.07 when right


# --- Mitsuba 3, region by region ------------------------------------------------------------

def mitsuba_render(scene_file: Path, spp: int, folder: Path, finer: int, size=64):
    """Mitsuba 3's render of the scene and its regions (path_checks.mitsuba_regions),
    its map made `finer` times finer each way, each pixel repeated: Mitsuba reads a map
    bilinearly with row r at v = r / (H - 1) (sky.py's docstring), our chapter reads the
    nearest pixel, which moves the light by a few tenths of a percent on the sky's
    ground, several percent on the coarse spots map: more than the noise the regions
    are compared within. Repeated pixels make the two readings differ only within a
    fine pixel of the coarse ones' edges."""
    from python_prototypes import scene_io
    scene = scene_io.load_scene(str(scene_file), [str(f) for f in MESH_FOLDERS])
    image = environment_map.read_map(scene.environment.path)
    fine = np.repeat(np.repeat(image, finer, axis=0), finer, axis=1)
    fine_map = folder / f"fine_{scene.environment.path.name}"
    pfm.write_pfm(fine_map, fine.astype(np.float32))
    lines = []
    for line in scene_file.read_text().splitlines():
        words = line.split()
        if words[:1] == ["environment"]:
            line = " ".join(["environment", str(fine_map), *words[2:]])
        lines.append(line)
    copy = folder / f"fine_{scene_file.name}"
    copy.write_text("\n".join(lines) + "\n")
    return path_checks.mitsuba_regions(copy, spp, size, MESH_FOLDERS)


def test_the_sky_alone_agrees_with_mitsuba(tmp_path):
    """The environment the only light: what it sends straight to each surface (NEE from
    its tables, MIS against the BSDF) and after bounces."""
    scene = TEST_SCENES / "sky_spheres.scene"
    reference = mitsuba_render(scene, 1024, tmp_path, finer=4)
    ours = path_checks.path_trace("18", tmp_path, "sky", "--scene", scene, "--width", 64,
                                  "--height", 64, "--spp", 512)
    compared = path_checks.assert_regions_within_two_percent(ours, reference, MESH_FOLDERS)
    assert {"ground", "diffuse_sphere", "glossy_sphere"} <= set(compared)


def test_spots_and_a_lamp_agree_with_mitsuba(tmp_path):
    """An environment and an emitting shape together: next-event estimation picks one
    of the two (environmentChance), and MIS weighs each against BSDF sampling."""
    scene = TEST_SCENES / "spots_lamp.scene"
    reference = mitsuba_render(scene, 1024, tmp_path, finer=32)
    ours = path_checks.path_trace("18", tmp_path, "spots", "--scene", scene, "--width", 64,
                                  "--height", 64, "--spp", 512)
    compared = path_checks.assert_regions_within_two_percent(ours, reference, MESH_FOLDERS)
    assert {"ground", "sphere"} <= set(compared)
