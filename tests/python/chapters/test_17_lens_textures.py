"""Chapter 17: a thin lens and textures (book/docs/maintainers.md).

- The lens, on the GPU: camera.glsl's primaryRay (tests/data/lens/lens_probe.comp
  through tests/cpp/bsdf_probe.cpp) against python_prototypes/thin_lens.py ray by ray;
  its points on the aperture fill the disk uniformly (a chi-square test over cells of
  equal area), which a square aperture or a polar map with r = u do not.
- A camera focused on a plane renders that plane as the pinhole does (block by block,
  within the noise); focused elsewhere, it does not.
- Textures, exactly: --view albedo looks through each pixel's centre, so every pixel
  is a known point of a known texture, compared with python_prototypes/textures.py
  (sRGB decoding, bilinear filtering, repeat, checkers; quads and OBJ meshes) to float
  precision. An image read upside down fails.
- Mitsuba 3, region by region: the chapter's scene (a lens; an image on a mesh and a
  checker on a quad) and a row of spheres in and out of focus.
- Bad scenes (a missing image, a file that is not one, a texture used before it is
  defined, a negative lens radius, a textured mesh without vt): exit code 3 at the line.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import path_checks
import pytest
from conftest import ROOT, read_pfm, regions_agreeing, run_chapter
from path_checks import SIGMAS

from python_prototypes import camera_rays
from python_prototypes import chi_square
from python_prototypes import scene_io
from python_prototypes import srgb
from python_prototypes import textures
from python_prototypes import thin_lens

PROBE_SHADER = ROOT / "tests" / "data" / "lens" / "lens_probe.comp"
SCENES = ROOT / "assets" / "scenes"
TEST_SCENES = ROOT / "tests" / "data" / "scenes"
ASSETS = ROOT / "build" / "assets"  # the build's generated meshes and images
MESH_FOLDERS = [ASSETS]

# The planted bugs: (file, the right text, the wrong one). Each must fail its check.
SQUARE_APERTURE = ("camera.glsl", "camera.lensRadius * concentricDisk(pointOnLens)",
                   "camera.lensRadius * (2.0 * pointOnLens - 1.0)")
# Polar coordinates with the radius uniform: inside the disk, crowded at its centre.
RADIUS_UNIFORM = ("camera.glsl", "camera.lensRadius * concentricDisk(pointOnLens)",
                  "camera.lensRadius * pointOnLens.x * vec2(cos(6.2831853 * pointOnLens.y),"
                  " sin(6.2831853 * pointOnLens.y))")
UPSIDE_DOWN = ("textures.glsl", "(1.0 - uv.y) * float(image.height)",
               "uv.y * float(image.height)")


def shaders_with(tmp_path, bug=None) -> Path:
    return path_checks.shaders_with_bug("17", tmp_path, bug, [PROBE_SHADER])


def path_trace(tmp_path, name, *args) -> np.ndarray:
    return path_checks.path_trace("17", tmp_path, name, *args)


# --- The lens on the GPU ------------------------------------------------------------------

FOCAL, SENSOR, RADIUS, FOCUS = 0.035, 0.036, 0.02, 2.5
EYE = (0.3, -0.2, 1.0)
WIDTH, HEIGHT = 64, 48


def lens_queries(rng, n, in_pixel=None) -> np.ndarray:
    """(N, 20) queries: random pixels, points in them and on the lens."""
    q = np.zeros((n, 20))
    q[:, 0], q[:, 1] = rng.integers(0, WIDTH, n), rng.integers(0, HEIGHT, n)
    q[:, 2], q[:, 3] = WIDTH, HEIGHT
    q[:, 4:6] = rng.random((n, 2)) if in_pixel is None else in_pixel
    q[:, 6:8] = rng.random((n, 2))
    q[:, 8:12] = FOCAL, SENSOR, RADIUS, FOCUS
    q[:, 12:15] = EYE
    return q


def gpu_rays(shader_dir, queries, tmp_path):
    answers = path_checks.run_bsdf_probe(PROBE_SHADER.name, shader_dir, queries, tmp_path)
    return answers[:, 0:3], answers[:, 4:7]


def test_gpu_lens_rays_match_the_numpy_prototype(tmp_path):
    queries = lens_queries(np.random.default_rng(1), 4000)
    origins, directions = gpu_rays(shaders_with(tmp_path), queries, tmp_path)
    camera = thin_lens.ThinLensCamera(eye=EYE, look_direction=(0, 0, -1), up=(0, 1, 0),
                                      focal_length=FOCAL, sensor_width=SENSOR,
                                      aperture_diameter=2 * RADIUS, focus_distance=FOCUS)
    expected_origins, expected_directions = thin_lens.thin_lens_rays(
        camera, WIDTH, HEIGHT, queries[:, 0] + queries[:, 4], queries[:, 1] + queries[:, 5],
        queries[:, 6], queries[:, 7])
    np.testing.assert_allclose(origins, expected_origins, atol=2e-6)
    np.testing.assert_allclose(directions, expected_directions, atol=2e-6)
    # Every ray of a pixel meets its pinhole ray on the focus plane.
    assert np.all(np.abs((origins - EYE) @ (0, 0, -1)) < 1e-7)  # they start on the lens


def aperture_points(shader_dir, tmp_path, n=40_000) -> np.ndarray:
    """Where n rays through one pixel's centre leave the lens, in lens radii (N, 2)."""
    queries = lens_queries(np.random.default_rng(2), n, in_pixel=0.5)
    origins, _ = gpu_rays(shader_dir, queries, tmp_path)
    return (origins - EYE)[:, :2] / RADIUS


def uniform_on_the_disk_p_value(points: np.ndarray) -> float:
    """Chi-square over 8 rings of equal area times 8 sectors: 64 cells, each holding
    1/64 of uniform points. A point outside the disk is a failure outright."""
    r2 = np.sum(points ** 2, axis=1)
    assert np.all(r2 <= 1.0 + 1e-5), f"{np.mean(r2 > 1):.1%} of the points are off the lens"
    ring = np.minimum((r2 * 8).astype(int), 7)
    sector = np.minimum(((np.arctan2(points[:, 1], points[:, 0]) + math.pi)
                         / (2 * math.pi) * 8).astype(int), 7)
    observed = np.bincount(ring * 8 + sector, minlength=64).astype(float)
    expected = len(points) / 64
    statistic = np.sum((observed - expected) ** 2 / expected)
    return chi_square.chi_square_p_value(statistic, 63)


def test_lens_samples_fill_the_aperture_uniformly(tmp_path):
    points = aperture_points(shaders_with(tmp_path), tmp_path)
    assert uniform_on_the_disk_p_value(points) > 1e-3
    assert np.sum(points ** 2, axis=1).max() > 0.99  # out to the rim


def test_a_square_aperture_is_caught(tmp_path):
    points = aperture_points(shaders_with(tmp_path, SQUARE_APERTURE), tmp_path)
    with pytest.raises(AssertionError, match="off the lens"):
        uniform_on_the_disk_p_value(points)


def test_radius_uniform_polar_samples_are_caught(tmp_path):
    points = aperture_points(shaders_with(tmp_path, RADIUS_UNIFORM), tmp_path)
    assert uniform_on_the_disk_p_value(points) < 1e-6
    # And they crowd the centre, as the page says: half of them inside half the radius,
    # where a uniform disk puts a quarter.
    inner = np.mean(np.sum(points ** 2, axis=1) < 0.25)
    assert inner > 0.4, inner


# --- In focus, the lens is the pinhole --------------------------------------------------------

# A checker wall 3 m in front of the camera, filling the view, lit by a lamp behind the
# camera. Squares of about 5 pixels: blur of a pixel or two changes most 4 x 4 blocks.
FOCUS_WALL = """camera eye 0 0 3 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.036{lens}
texture tiles checker 0.9 0.9 0.9 0.05 0.05 0.05 scale 6
material wall albedo texture tiles
material lamp albedo 0 0 0 emission 2 2 2
quad -2 -2 0   4 0 0   0 4 0   wall name wall
quad -3 -3 6   0 6 0   6 0 0   lamp
"""


def wall_image(tmp_path, name, lens="", seed=1) -> np.ndarray:
    scene = tmp_path / f"{name}.scene"
    scene.write_text(FOCUS_WALL.format(lens=lens))
    return path_trace(tmp_path, name, "--scene", scene, "--width", 64, "--height", 64,
                      "--spp", 64, "--depth", 1, "--seed", seed).mean(axis=2)


def blocks(image: np.ndarray, block: int = 4) -> np.ndarray:
    size = image.shape[0] // block
    return image.reshape(size, block, size, block).transpose(0, 2, 1, 3).reshape(
        size, size, -1)


@pytest.mark.windows
def test_the_focus_plane_is_as_sharp_as_through_a_pinhole(tmp_path):
    """Block means against the pinhole's, in standard errors of the noise, which two
    pinhole renders of different seeds measure block by block (their difference is
    noise alone; a render against one of them has the same spread)."""
    pinhole, again = wall_image(tmp_path, "pinhole"), wall_image(tmp_path, "again", seed=2)
    error = blocks(pinhole - again).std(axis=2, ddof=1) / 4 + 1e-9  # of a 16-pixel mean

    def z(image):
        return np.abs(blocks(image - pinhole).mean(axis=2) / error)
    focused = wall_image(tmp_path, "focused", " lens 0.05 focus 3", seed=3)
    assert z(focused).max() < SIGMAS + 1.0  # 256 blocks: the largest of 256 |z|
    defocused = wall_image(tmp_path, "defocused", " lens 0.05 focus 1.5", seed=3)
    # Blurred by about 2 pixels: the blocks astride the squares' edges move.
    assert np.mean(z(defocused) > SIGMAS) > 0.1 and z(defocused).max() > 5 * SIGMAS


# --- Textures, texel by texel ---------------------------------------------------------------

# The camera looks straight at the plane z = 0 from 1 m; the picture is 1 m wide.
FLAT_CAMERA = "camera eye 0 0 1 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.035\n"
LAMP = "material lamp albedo 0 0 0 emission 1 1 1\nsphere 0 0 5 0.1 lamp\n"
SIZE = 48


def plane_points(size=SIZE) -> np.ndarray:
    """Where each pixel centre's pinhole ray meets z = 0: (size, size, 2) x, y."""
    camera = camera_rays.Camera(eye=(0, 0, 1), look_direction=(0, 0, -1), up=(0, 1, 0),
                                focal_length=0.035, sensor_width=0.035)
    centres = camera_rays.pixel_centers(size, size, camera.eye, camera.look_direction,
                                        camera.up, camera.focal_length, camera.sensor_width)
    directions = centres - np.asarray(camera.eye)
    t = -1.0 / directions[..., 2]
    return (np.asarray(camera.eye) + directions * t[..., None])[..., :2]


def albedo_view(tmp_path, scene_text, name="albedo", shader_dir=None) -> np.ndarray:
    scene = tmp_path / f"{name}.scene"
    scene.write_text(scene_text)
    out = tmp_path / f"{name}.pfm"
    extra = ["--shader-dir", shader_dir] if shader_dir else []
    result = run_chapter("17", "--headless", "--scene", scene, "--view", "albedo",
                         "--width", str(SIZE), "--height", str(SIZE), "--out", out, *extra)
    assert result.returncode == 0, result.stderr
    return read_pfm(out)[..., :3]


def texture_of(scene_text, tmp_path, name="albedo"):
    scene = tmp_path / f"{name}_reread.scene"
    scene.write_text(scene_text)
    return scene_io.load_scene(scene, MESH_FOLDERS).textures


def quad_scene(texture_line: str, corner=(-0.6, -0.55), size=(1.2, 1.1)) -> str:
    """A quad over the whole view (1.2 m by 1.1 m), u to the right, v upwards."""
    return (FLAT_CAMERA + texture_line + "\nmaterial tex albedo texture t\n" + LAMP +
            f"quad {corner[0]} {corner[1]} 0   {size[0]} 0 0   0 {size[1]} 0   tex\n")


def quad_uv(points):
    return (points[..., 0] + 0.6) / 1.2, (points[..., 1] + 0.55) / 1.1


# Bilinear filtering in float32 on the GPU: a texture coordinate rounded by 1e-7 moves
# a 256-texel image's value by up to ~1e-4 where neighbouring texels differ most.
FLOAT_PRECISION = dict(atol=2e-4, rtol=1e-4)


@pytest.mark.parametrize("texture_line", [
    "texture t image textures/test_pattern.png",
    "texture t image textures/test_pattern.png linear",
    "texture t image textures/uv_grid.png"], ids=["srgb", "linear", "uv_grid"])
def test_an_image_on_a_quad_is_read_back_exactly(tmp_path, texture_line):
    text = quad_scene(texture_line)
    image = albedo_view(tmp_path, text)
    u, v = quad_uv(plane_points())
    expected = textures.lookup(texture_of(text, tmp_path)["t"], u, v)
    np.testing.assert_allclose(image, expected, **FLOAT_PRECISION)


def test_srgb_images_are_decoded_by_the_formula(tmp_path):
    """An 8 x 4 picture of the 8 x 4 test pattern, the quad exactly the view: each pixel
    centre is a texel centre, so the render shows the texels themselves, which must be
    the file's bytes / 255 read `linear`, and the sRGB curve of that otherwise."""
    from PIL import Image
    with Image.open(ASSETS / "textures" / "test_pattern.png") as png:
        raw = np.asarray(png.convert("RGB"), dtype=np.float64) / 255.0
    assert raw.shape == (4, 8, 3)

    def texels(words, name):
        scene = tmp_path / f"{name}.scene"
        scene.write_text(quad_scene(f"texture t image textures/test_pattern.png{words}",
                                    corner=(-0.5, -0.25), size=(1.0, 0.5)))
        out = tmp_path / f"{name}.pfm"
        result = run_chapter("17", "--headless", "--scene", scene, "--view", "albedo",
                             "--width", "8", "--height", "4", "--out", out)
        assert result.returncode == 0, result.stderr
        return read_pfm(out)[..., :3]
    np.testing.assert_allclose(texels(" linear", "linear"), raw, atol=1e-6)
    curve = srgb.decode(raw)
    np.testing.assert_allclose(texels("", "srgb"), curve, atol=1e-6)
    assert np.abs(curve - raw).max() > 0.1  # the two differ: the curve was applied


def test_an_image_read_upside_down_is_caught(tmp_path):
    text = quad_scene("texture t image textures/uv_grid.png")
    image = albedo_view(tmp_path, text, shader_dir=shaders_with(tmp_path, UPSIDE_DOWN))
    u, v = quad_uv(plane_points())
    expected = textures.lookup(texture_of(text, tmp_path)["t"], u, v)
    assert np.abs(image - expected).max() > 0.2


def test_a_checker_on_a_quad_is_read_back_exactly(tmp_path):
    text = quad_scene("texture t checker 0.9 0.1 0.2 0.1 0.3 0.8 scale 3.5")
    image = albedo_view(tmp_path, text)
    u, v = quad_uv(plane_points())
    expected = textures.lookup(texture_of(text, tmp_path)["t"], u, v)
    # Pixels whose centre lies within float rounding of a square's edge may go either way.
    s, t = 3.5 * u, 3.5 * v
    clear = (np.abs(s * 2 - np.round(s * 2)) > 1e-4) & (np.abs(t * 2 - np.round(t * 2)) > 1e-4)
    assert clear.mean() > 0.95
    np.testing.assert_allclose(image[clear], expected[clear], atol=1e-6)
    assert len(np.unique(image[clear].round(4), axis=0)) == 2


# A square of two triangles over the view whose vt run from -0.75 to 1.75 across and,
# turned a quarter, from 1.5 down to -1 (so the image repeats and is seen sideways).
SQUARE_OBJ = """v -0.6 -0.6 0
v 0.6 -0.6 0
v 0.6 0.6 0
v -0.6 0.6 0
vt -0.75 1.5
vt -0.75 -1
vt 1.75 -1
vt 1.75 1.5
f 1/1 2/2 3/3
f 1/1 3/3 4/4
"""


def test_an_image_on_a_mesh_repeats_through_its_vt(tmp_path):
    (tmp_path / "square.obj").write_text(SQUARE_OBJ)
    text = (FLAT_CAMERA + "texture t image textures/uv_grid.png\n"
            "material tex albedo texture t\n" + LAMP + "mesh square.obj tex\n")
    image = albedo_view(tmp_path, text)
    points = plane_points()
    s, t = (points[..., 0] + 0.6) / 1.2, (points[..., 1] + 0.6) / 1.2  # across, up
    u, v = -0.75 + 2.5 * t, 1.5 - 2.5 * s  # the vt, linear over the square
    inside = (np.abs(points[..., 0]) < 0.599) & (np.abs(points[..., 1]) < 0.599)
    expected = textures.lookup(texture_of(text, tmp_path)["t"], u, v)
    np.testing.assert_allclose(image[inside], expected[inside], **FLOAT_PRECISION)


# --- Mitsuba 3 -----------------------------------------------------------------------------

def mitsuba_render(scene_file, spp, size=64):
    return path_checks.mitsuba_regions(scene_file, spp, size, MESH_FOLDERS)


def assert_within_two_percent(ours, reference):
    return path_checks.assert_regions_within_two_percent(ours, reference, MESH_FOLDERS)


def test_the_chapter_scene_agrees_with_mitsuba(tmp_path):
    reference = mitsuba_render(SCENES / "lens_textures.scene", 1024)
    ours = path_trace(tmp_path, "ours", "--width", 64, "--height", 64, "--spp", 512)
    compared = assert_within_two_percent(ours, reference)
    assert {"teapot", "floor", "near_sphere"} <= set(compared)


def test_the_textured_teapot_within_two_percent_of_mitsuba(tmp_path):
    """The image texture on a mesh, measured closely enough to tell 2% from 0: the
    teapot of the chapter's scene in a close-up from the same eye (path_checks.close_up;
    through a pinhole: the lens is the other tests' business)."""
    relative, error, pixels, ours, theirs, scene_file = path_checks.close_up_difference(
        "17", tmp_path, SCENES / "lens_textures.scene", "teapot", 80, 512, 1024,
        MESH_FOLDERS)
    assert pixels > 1000
    assert error < 0.008
    assert abs(relative) < 0.02
    regions_agreeing(ours, theirs, scene_file, SIGMAS, MESH_FOLDERS)


def test_spheres_in_and_out_of_focus_agree_with_mitsuba(tmp_path):
    scene = SCENES / "depth_of_field.scene"
    reference = mitsuba_render(scene, 512)
    ours = path_trace(tmp_path, "dof", "--scene", scene, "--width", 64, "--height", 64,
                      "--spp", 256)
    compared = assert_within_two_percent(ours, reference)
    assert {"near", "in_focus", "far"} <= set(compared)


# --- Bad scenes ------------------------------------------------------------------------------

def refused(tmp_path, lines: str, line: int, message: str, files=()):
    for name, content in files:
        (tmp_path / name).write_bytes(content)
    scene = tmp_path / "bad.scene"
    scene.write_text(FLAT_CAMERA + LAMP + lines)
    result = run_chapter("17", "--headless", "--scene", scene, "--width", "8",
                         "--height", "8", "--out", tmp_path / "x.png")
    assert result.returncode == 3, result.stderr
    first = result.stderr.splitlines()[0]
    assert f"{scene}:{line}: " in first and message in first, result.stderr
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize("lines, line, message, files", [
    ("texture t image nowhere.png\n", 4, "image file 'nowhere.png' not found", ()),
    ("texture t image fake.png\n", 4, "is not a PNG or JPEG image",
     [("fake.png", b"GIF89a, or rather not\n")]),
    ("material m albedo texture t\ntexture t checker 0 0 0 1 1 1\n", 4,
     "texture 't' is not defined on an earlier line", ()),
    ("texture t checker 0 0 0 1 1 1\nmaterial m albedo texture t\nsphere 0 0 0 1 m\n", 6,
     "material 'm' is textured, and this shape has no texture coordinates", ()),
    ("texture t checker 0 0 0 1 1 1\nmaterial m albedo texture t\nmesh flat.obj m\n", 6,
     "material 'm' is textured, and flat.obj has no texture coordinates",
     [("flat.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")]),
], ids=["missing", "not_an_image", "texture_later", "sphere", "mesh_without_vt"])
def test_bad_textures_are_refused_at_their_line(tmp_path, lines, line, message, files):
    refused(tmp_path, lines, line, message, files)


def test_a_negative_lens_radius_is_refused(tmp_path):
    scene = tmp_path / "bad.scene"
    scene.write_text(FLAT_CAMERA.strip() + " lens -0.01 focus 2\n" + LAMP)
    result = run_chapter("17", "--headless", "--scene", scene, "--out", tmp_path / "x.png")
    assert result.returncode == 3
    assert f"{scene}:1: the lens radius '-0.01' must be 0 or more" in result.stderr


def test_chapter_16_refuses_a_lens_it_cannot_render(tmp_path):
    result = run_chapter("16", "--headless", "--scene", SCENES / "lens_textures.scene",
                         "--out", tmp_path / "x.png")
    assert result.returncode == 3
    assert "come in chapter 17" in result.stderr
