"""Chapter 25: media whose density varies, checked with closed forms, a furnace, the
homogeneous medium it must reduce to, and Mitsuba 3's volumetric path tracer
(book/docs/maintainers.md).

- The build's cloud (build/assets/volumes/cloud.vol) is python_prototypes/volumes.py's,
  value for value, and a .vol file both readers agree on.
- Beer-Lambert through a grid: a cloud that only absorbs, in front of a glowing wall.
  Camera rays cross it by delta tracking, which keeps a ray with the chance of no real
  collision: each pixel's mean is the wall's radiance times exp(-optical depth), the
  integral of scale x the trilinear density along the pixel's rays (numpy, 4 x 4 rays a
  pixel, at the centres of its sixteenths). The trilinear lookup and the tracking are
  both in it; a majorant half the grid's densest point fails it.
- A grid of one density everywhere is the homogeneous medium of chapter 24 with the
  same coefficients: the same picture within the noise, lit through ratio-tracked
  shadow rays; a ratio tracking that keeps exp(-sigma_t / majorant) at each step fails.
- A white furnace: the cloud scattering everything it stops (albedo 1) vanishes in an
  environment of radiance 1.
- Mitsuba 3 `volpath` with its `heterogeneous` medium over the same .vol file (its
  `gridvolume`), region by region within 2%.
- Bad grids: too dense for the program's tracking steps, exit code 3 at the line.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import numpy as np
import path_checks
import pytest
from conftest import ROOT, run_chapter
from path_checks import SIGMAS, mean_and_error

from python_prototypes import mitsuba_reference as mr
from python_prototypes import scene_io, volumes
from python_prototypes.pfm import write_pfm

pytestmark = pytest.mark.filterwarnings("ignore::RuntimeWarning")

SCENES = ROOT / "assets" / "scenes"
ASSETS = ROOT / "build" / "assets"
MESH_FOLDERS = [ASSETS]

# The planted bugs: (file, the right text, the wrong one). Each must fail its check.
MAJORANT_TOO_SMALL = (  # half the densest sigma_t: denser points are taken as that dense
    "grid.glsl",
    "        t -= log(1.0 - random01(random)) / medium.majorant;\n"
    "        if (t >= far) return flight;\n"
    "        float sigmaT = medium.scale * densityAt(medium, ray.origin + t * ray.direction);\n"
    "        if (random01(random) * medium.majorant < sigmaT) {",
    "        t -= log(1.0 - random01(random)) / (0.5 * medium.majorant);\n"
    "        if (t >= far) return flight;\n"
    "        float sigmaT = medium.scale * densityAt(medium, ray.origin + t * ray.direction);\n"
    "        if (random01(random) * 0.5 * medium.majorant < sigmaT) {")
RATIO_AS_EXPONENTIAL = (  # a null collision's chance taken as a transmittance
    "grid.glsl", "kept *= 1.0 - sigmaT / medium.majorant;",
    "kept *= exp(-sigmaT / medium.majorant);")


def shaders_with(tmp_path, bug=None):
    return path_checks.shaders_with_bug("25", tmp_path, bug)


def path_trace(tmp_path, name, *args, shader_dir=None) -> np.ndarray:
    extra = ["--shader-dir", shader_dir] if shader_dir else []
    return path_checks.path_trace("25", tmp_path, name, *extra, *args)


# --- The cloud ------------------------------------------------------------------------------

def test_the_builds_cloud_is_the_prototypes():
    built = volumes.read_vol(ASSETS / "volumes" / "cloud.vol")
    made = volumes.cloud()
    assert np.array_equal(built.density, made.density)
    assert np.allclose(built.box_min, made.box_min) and np.allclose(built.box_max, made.box_max)
    assert built.density.max() == 1.0 and built.density.min() == 0.0
    # Its outermost cells are empty, so the grid is empty outside its box in both
    # readings (the course's, and Mitsuba's clamped one).
    d = built.density
    assert not (d[[0, -1]].any() or d[:, [0, -1]].any() or d[:, :, [0, -1]].any())


# --- Beer-Lambert through the cloud ---------------------------------------------------------

SCALE = 6.0
WALL = (2.0, 3.0, 4.0)


def absorbing_cloud_scene(folder):
    """The build's cloud, absorbing only, between the camera and a glowing wall."""
    (folder / "cloud.vol").write_bytes((ASSETS / "volumes" / "cloud.vol").read_bytes())
    path = folder / "cloud.scene"
    path.write_text(
        "camera eye 0 -0.2 3 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.012\n"
        f"medium ink grid cloud.vol albedo 0 0 0 scale {SCALE}\n"
        "material edge boundary\n"
        f"material wall albedo 0 0 0 emission {' '.join(map(str, WALL))}\n"
        "quad -3 -3 -1  6 0 0  0 6 0 wall name wall\n"
        "sphere 0 -0.2 0 0.7 edge interior ink name ball\n")
    return path


def expected_through_cloud(scene_file, size, subsamples=4):
    """Each pixel's mean: the wall's radiance times exp(-optical depth), averaged over
    subsamples x subsamples rays at the centres of as many equal parts of the pixel
    (the pixels of a picture `subsamples` times as wide): the pixel's mean, as the
    renderer's uniform points in it estimate it."""
    scene = scene_io.load_scene(scene_file)
    grid = volumes.read_vol(scene_file.parent / "cloud.vol")
    fine = size * subsamples
    directions = mr.ray_directions(scene.camera, fine, fine).reshape(-1, 3)
    eye = np.array(scene.camera.eye)
    depths = volumes.optical_depths(grid, SCALE, eye, directions, 3.6, steps=400)
    by_pixel = np.exp(-depths).reshape(size, subsamples, size, subsamples)
    # The 16 rays stand for the pixel within about their spread over 4 (a pixel
    # across the cloud's edge varies more than its 16 rays see exactly).
    spread = by_pixel.std(axis=(1, 3)) / subsamples
    return (by_pixel.mean(axis=(1, 3)), spread,
            depths.reshape(size, subsamples, size, subsamples).mean(axis=(1, 3)))


def assert_follows_optical_depth(image, expected):
    """Pixel by pixel within SIGMAS standard errors: the render's, of a Bernoulli mean
    (a ray is kept or not: sqrt(T (1 - T) / spp), where T (1 - T) is at least 4 / spp:
    a pixel the cloud barely touches loses a ray or two to it in 1024 more often than
    the normal curve says), and the expectation's own; and the mean of the pixels the
    cloud covers thickly within 1%."""
    kept, spread, depth = expected
    spp = 1024
    bernoulli = np.maximum(kept * (1 - kept), 4.0 / spp)
    error = np.sqrt(bernoulli / spp + spread ** 2)[..., None] * np.array(WALL)
    wall = kept[..., None] * np.array(WALL)
    assert np.all(np.abs(image - wall) < SIGMAS * error + 1e-4), \
        (np.abs(image - wall) / (error + 1e-9)).max()
    thick = depth > 1.0
    assert thick.sum() > 50
    assert np.allclose(image[thick].mean(axis=0), wall[thick].mean(axis=0), rtol=0.01)


@pytest.mark.windows
def test_camera_rays_through_an_absorbing_grid_follow_its_optical_depth(tmp_path):
    scene_file = absorbing_cloud_scene(tmp_path)
    image = path_trace(tmp_path, "cloud", "--scene", scene_file, "--width", 32,
                       "--height", 32, "--spp", 1024, "--depth", 1)
    assert_follows_optical_depth(image, expected_through_cloud(scene_file, 32))


def test_majorant_too_small_fails_the_optical_depth(tmp_path):
    scene_file = absorbing_cloud_scene(tmp_path)
    image = path_trace(tmp_path, "cloud", "--scene", scene_file, "--width", 32,
                       "--height", 32, "--spp", 1024, "--depth", 1,
                       shader_dir=shaders_with(tmp_path, MAJORANT_TOO_SMALL))
    with pytest.raises(AssertionError):
        assert_follows_optical_depth(image, expected_through_cloud(scene_file, 32))


# --- A grid of one density is a homogeneous medium ------------------------------------------

def constant_grid(path, density=0.5):
    """A 4 x 4 x 4 grid of one density over a box the ball of cornell_smoke fits in."""
    volumes.write_vol(path, volumes.Grid(np.full((4, 4, 4), density, np.float32),
                                         np.array([-0.6, -1.0, -0.6]),
                                         np.array([0.6, 0.2, 0.6])))


def smoke_room(folder, name, medium_line):
    text = (SCENES / "cornell_smoke.scene").read_text()
    lines = [medium_line if line.startswith("medium smoke") else line
             for line in text.splitlines()]
    assert medium_line in lines
    path = folder / f"{name}.scene"
    path.write_text("\n".join(lines) + "\n")
    return path


def render_both(tmp_path, shader_dir=None):
    """The smoke room twice: its ball a grid of density 0.5 times scale 6 with albedo
    (0.2, 0.5, 0.8), and chapter 24's homogeneous medium of the same coefficients."""
    constant_grid(tmp_path / "constant.vol")
    grid = smoke_room(tmp_path, "grid",
                      "medium smoke grid constant.vol albedo 0.2 0.5 0.8 scale 6 g 0.5")
    homogeneous = smoke_room(tmp_path, "homogeneous", "medium smoke homogeneous "
                             "sigma_a 2.4 1.5 0.6 sigma_s 0.6 1.5 2.4 g 0.5")
    args = ("--width", 32, "--height", 32, "--spp", 256)
    return (path_trace(tmp_path, "grid", "--scene", grid, *args, shader_dir=shader_dir),
            path_trace(tmp_path, "homogeneous", "--scene", homogeneous, *args,
                       shader_dir=shader_dir))


def assert_same_within_noise(first, second):
    """Over the picture and in every 8 x 8 block: the mean difference within SIGMAS of
    its standard error (from the pixels' own spread), plus 2e-4 for float rounding."""
    difference = (first - second).reshape(4, 8, 4, 8, 3).transpose(0, 2, 1, 3, 4)
    for pixels in [difference.reshape(-1, 3)] + list(difference.reshape(16, 64, 3)):
        mean, error = mean_and_error(pixels)
        assert np.all(np.abs(mean) < SIGMAS * error + 2e-4), (mean, error)


@pytest.mark.windows
def test_a_grid_of_one_density_is_the_homogeneous_medium(tmp_path):
    grid, homogeneous = render_both(tmp_path)
    assert_same_within_noise(grid, homogeneous)


def test_ratio_tracking_as_an_exponential_fails(tmp_path):
    grid, homogeneous = render_both(tmp_path, shaders_with(tmp_path, RATIO_AS_EXPONENTIAL))
    with pytest.raises(AssertionError):
        assert_same_within_noise(grid, homogeneous)


# --- The white furnace ----------------------------------------------------------------------

def test_a_scattering_cloud_vanishes_in_the_furnace(tmp_path):
    sky = tmp_path / "white.pfm"
    write_pfm(sky, np.ones((8, 16, 3), dtype=np.float32))
    (tmp_path / "cloud.vol").write_bytes((ASSETS / "volumes" / "cloud.vol").read_bytes())
    scene = tmp_path / "furnace.scene"
    scene.write_text(
        "camera eye 0 -0.2 2.5 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.025\n"
        "medium cloud grid cloud.vol albedo 1 1 1 scale 8 g 0.5\n"
        "material edge boundary\n"
        "sphere 0 -0.2 0 0.7 edge interior cloud name cloud\n"
        f"environment {sky.name}\n")
    image = path_trace(tmp_path, "furnace", "--scene", scene, "--width", 32, "--height", 32,
                       "--spp", 256, "--depth", 40)
    path_checks.assert_mean_everywhere(image, 1.0, margin=2e-3)  # as chapter 24's furnace


# --- Mitsuba 3's volumetric path tracer -----------------------------------------------------

def test_the_cloud_agrees_with_mitsuba_volpath(tmp_path):
    scene_file = SCENES / "cornell_cloud.scene"
    reference = path_checks.mitsuba_regions(scene_file, 512, 64, MESH_FOLDERS)
    ours = path_trace(tmp_path, "cloud", "--scene", scene_file, "--width", 64,
                      "--height", 64, "--spp", 512)
    compared = path_checks.assert_regions_within_two_percent(ours, reference, MESH_FOLDERS)
    assert {"cloud", "back", "floor"} <= set(compared), compared


# --- Bad grids ------------------------------------------------------------------------------

def test_a_grid_too_dense_to_track_is_exit_3_at_its_line(tmp_path):
    constant_grid(tmp_path / "dense.vol", density=1.0)
    scene = smoke_room(tmp_path, "dense",
                       "medium smoke grid dense.vol albedo 1 1 1 scale 40")
    result = run_chapter("25", "--scene", scene, "--out", tmp_path / "x.png")
    assert result.returncode == 3, result.stderr
    line = next(i for i, text in enumerate(scene.read_text().splitlines(), 1)
                if text.startswith("medium smoke"))
    assert f"{scene}:{line}: " in result.stderr, result.stderr
    assert "tracking steps, more than this program's 32: a smaller scale fits" \
        in result.stderr, result.stderr
    assert not (tmp_path / "x.png").exists()
