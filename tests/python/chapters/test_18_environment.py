"""Chapter 18: an environment light, and exposure and tone mapping (book/docs/maintainers.md).

- A furnace: under a constant environment of radiance L, a white Lambertian sphere is
  L everywhere (a convex shape never sees itself: one bounce suffices), and one of
  albedo a is a L; the background is L exactly.
- Orientation: a map with a few bright spots, looked at straight through the camera
  (the background), pixel for pixel against python_prototypes/environment_map.py,
  turned by rotate_y too.
- The display: the PNG is the tone-mapped radiance (each operator against its formula
  in numpy, through the sRGB curve), the PFM the radiance itself whatever --tone-map and
  --exposure say.
- Bad maps: a NaN, an infinity or a negative texel is exit code 3 at the environment's
  line; chapter 17 refuses an environment.
- OpenEXR: the .exr output is the PFM's radiance, read back by Mitsuba's reader (not
  ours); a map written as EXR by Mitsuba (float, or grey half floats) lights the scene as
  its PFM does; a file that is neither, or a cut EXR, is exit code 3 at its line.
  (Odd EXR layouts, read through OpenEXR: tests/cpp/test_exr_file.cpp.)

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import path_checks
import pytest
from conftest import ROOT, read_pfm, run_chapter
from path_checks import SIGMAS, mean_and_error

from python_prototypes import camera_rays
from python_prototypes import environment_map
from python_prototypes import pfm
from python_prototypes import scene_io
from python_prototypes import srgb

SCENES = ROOT / "assets" / "scenes"
ASSETS = ROOT / "build" / "assets"
MESH_FOLDERS = [ASSETS]

CAMERA = "camera eye 0 0 3 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.036\n"


def write_map(path: Path, image: np.ndarray) -> Path:
    pfm.write_pfm(path, np.asarray(image, dtype=np.float32))
    return path


def render(tmp_path, name, scene_text, *args) -> np.ndarray:
    scene = tmp_path / f"{name}.scene"
    scene.write_text(scene_text)
    return path_checks.path_trace("18", tmp_path, name, "--scene", scene, *args)


# --- The furnace ---------------------------------------------------------------------------

@pytest.mark.windows
@pytest.mark.parametrize("albedo", [1.0, 0.5])
def test_a_sphere_in_a_constant_environment(tmp_path, albedo):
    write_map(tmp_path / "grey.pfm", np.full((8, 16, 3), 0.75))
    image = render(tmp_path, "furnace", CAMERA +
                   f"material m albedo {albedo} {albedo} {albedo}\nsphere 0 0 0 1 m\n"
                   "environment grey.pfm\n", "--width", 48, "--height", 48, "--spp", 64)
    scene = scene_io.load_scene(tmp_path / "furnace.scene", MESH_FOLDERS)
    centres = camera_rays.pixel_centers(48, 48, scene.camera.eye, scene.camera.look,
                                        scene.camera.up, scene.camera.focal_length,
                                        scene.camera.sensor_width)
    rays = centres - np.asarray(scene.camera.eye)
    rays /= np.linalg.norm(rays, axis=-1, keepdims=True)
    along = -(rays @ np.asarray(scene.camera.eye))  # closest approach to the centre
    miss = np.linalg.norm(np.asarray(scene.camera.eye) + rays * along[..., None], axis=-1)
    sphere, background = miss < 0.9, miss > 1.1  # a pixel is 6 cm across there
    np.testing.assert_allclose(image[background], 0.75, atol=1e-6)
    mean, error = (float(x[0]) for x in mean_and_error(image[sphere].mean(axis=1)[:, None]))
    assert abs(mean - 0.75 * albedo) < SIGMAS * error + 1e-3, (mean, error)
    assert error < 0.01 * 0.75 * albedo  # the measurement can tell 1% from 0


# --- Orientation ------------------------------------------------------------------------------

@pytest.mark.windows
@pytest.mark.parametrize("degrees", [0, 75])
def test_the_background_is_the_map_the_right_way_round(tmp_path, degrees):
    """A wide camera looking up and sideways at the spots map: each pixel that looks into
    one map pixel only shows that map pixel's radiance, wherever its samples go."""
    spots = ASSETS / "environments" / "spots.pfm"
    camera = "camera eye 0 0 0 look 1 0.6 -0.4 up 0 1 0 focal 0.01 sensor 0.036\n"
    text = (camera + "material lamp albedo 0 0 0 emission 1 1 1\n"
            "sphere 0 -100 0 0.001 lamp\n"  # a scene file needs an object; out of view
            f"environment {spots} rotate_y {degrees}\n")
    width, height = 64, 48
    image = render(tmp_path, "background", text, "--width", width, "--height", height,
                   "--spp", 4)
    scene_file = tmp_path / "background.scene"
    scene = scene_io.load_scene(scene_file, MESH_FOLDERS)
    c = scene.camera
    # Directions through a 5 x 5 grid of points over each pixel, corners included: a
    # pixel counts where all 25 look into one map pixel (a footprint that straddles the
    # seam at u = 0, a pole or a spot's edge does not).
    k = 4
    grid = camera_rays.pixel_centers(k * width + 1, k * height + 1, c.eye, c.look, c.up,
                                     c.focal_length * k * width / (k * width + 1),
                                     c.sensor_width)
    seen = environment_map.environment_radiance(scene.environment, grid - np.asarray(c.eye))
    middle = seen[k // 2::k, k // 2::k][:height, :width]
    same = np.all([np.all(middle == seen[i:i + k * height:k, j:j + k * width:k], axis=-1)
                   for i in range(k + 1) for j in range(k + 1)], axis=0)
    assert same.mean() > 0.5
    expected = middle
    assert expected[same].max() > 5 * expected[same].min()  # spots in view
    np.testing.assert_allclose(image[same], expected[same], rtol=1e-5, atol=1e-6)


# --- The display ------------------------------------------------------------------------------

def luminance(c):
    return c @ np.array([0.2126, 0.7152, 0.0722])


def tone_map(radiance, exposure, operator):
    """tone_mapping.glsl in numpy, written from the formulas."""
    x = radiance * 2.0 ** exposure
    if operator == "clamp":
        return np.clip(x, 0, 1)
    if operator == "reinhard":
        l = luminance(x)[..., None]
        mapped = l * (1 + l / 64.0) / (1 + l)
        return np.minimum(x * mapped / np.maximum(l, 1e-30), 1.0)
    y = 0.6 * x
    return np.clip(y * (2.51 * y + 0.03) / (y * (2.43 * y + 0.59) + 0.14), 0, 1)


@pytest.mark.parametrize("operator", ["clamp", "reinhard", "aces"])
@pytest.mark.parametrize("exposure", [0.0, -1.5])
def test_the_png_is_the_tone_mapped_radiance(tmp_path, operator, exposure):
    """Nothing but a map of known radiance (up to 20) in view, one sample a pixel: the
    same seed gives the same samples, so each PNG pixel is sRGB(tone map(2^EV L)) of the
    PFM's L, to 8-bit rounding."""
    rng = np.random.default_rng(4)
    write_map(tmp_path / "map.pfm", rng.uniform(0.0, 20.0, (8, 16, 3)))
    text = (CAMERA + "material lamp albedo 0 0 0 emission 1 1 1\nsphere 0 -100 0 0.001 lamp\n"
            "environment map.pfm\n")
    scene = tmp_path / "map.scene"
    scene.write_text(text)
    common = ["--headless", "--scene", scene, "--width", "32", "--height", "24", "--spp",
              "1", "--tone-map", operator, "--exposure", str(exposure)]
    png, linear = tmp_path / "out.png", tmp_path / "out.pfm"
    for out in (png, linear):
        result = run_chapter("18", *common, "--out", out)
        assert result.returncode == 0, result.stderr
    from PIL import Image
    with Image.open(png) as image:
        shown = np.asarray(image.convert("RGB"), dtype=np.float64) / 255.0
    radiance_seen = read_pfm(linear)[..., :3]
    expected = srgb.encode(tone_map(radiance_seen, exposure, operator))
    assert np.abs(shown - expected).max() <= 1.0 / 255.0 + 1e-6
    assert radiance_seen.max() > 10  # the PFM is radiance, not tone mapped


def test_the_pfm_is_radiance_whatever_the_display(tmp_path):
    outs = []
    for operator, exposure in [("clamp", "0"), ("aces", "2"), ("false-colour", "-3")]:
        out = tmp_path / f"{operator}.pfm"
        result = run_chapter("18", "--headless", "--width", "24", "--height", "16", "--spp",
                             "4", "--tone-map", operator, "--exposure", exposure,
                             "--out", out)
        assert result.returncode == 0, result.stderr
        outs.append(read_pfm(out))
    assert np.array_equal(outs[0], outs[1]) and np.array_equal(outs[0], outs[2])


# --- Bad maps ---------------------------------------------------------------------------------

def run_with_map(tmp_path, chapter, map_name, out_name):
    """The chapter on a sphere lit by `map_name` (line 4 of the scene): the scene's path
    and the finished process."""
    scene = tmp_path / "map.scene"
    scene.write_text(CAMERA + "material m albedo 0.5 0.5 0.5\nsphere 0 0 0 1 m\n"
                     f"environment {map_name}\n")
    return scene, run_chapter(chapter, "--headless", "--scene", scene, "--out",
                              tmp_path / out_name)


@pytest.mark.parametrize("value, word", [(math.nan, "nan"), (math.inf, "inf"),
                                         (-0.5, "negative")])
def test_a_bad_texel_is_refused_at_the_environment_line(tmp_path, value, word):
    image = np.ones((4, 8, 3))
    image[1, 5, 2] = value
    write_map(tmp_path / "bad.pfm", image)
    scene, result = run_with_map(tmp_path, "18", "bad.pfm", "x.png")
    assert result.returncode == 3
    assert (f"{scene}:4: environment 'bad.pfm': texel (row 1, column 5) is {word}"
            in result.stderr), result.stderr
    assert not (tmp_path / "x.png").exists()


def test_chapter_17_refuses_an_environment(tmp_path):
    write_map(tmp_path / "grey.pfm", np.ones((4, 8, 3)))
    scene, result = run_with_map(tmp_path, "17", "grey.pfm", "x.png")
    assert result.returncode == 3
    assert f"{scene}:4: this program has no environment light; it comes in chapter 18" \
        in result.stderr


# --- OpenEXR ----------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def mi():
    import mitsuba
    mitsuba.set_variant("scalar_rgb")
    return mitsuba


def test_the_exr_is_the_pfm_read_by_mitsuba(tmp_path, mi):
    outs = {}
    for kind in ("pfm", "exr"):
        out = tmp_path / f"sky.{kind}"
        result = run_chapter("18", "--headless", "--width", "40", "--height", "24", "--spp",
                             "2", "--seed", "5", "--tone-map", "aces", "--out", out)
        assert result.returncode == 0, result.stderr
        outs[kind] = out
    bitmap = mi.Bitmap(str(outs["exr"]))
    assert bitmap.pixel_format() == mi.Bitmap.PixelFormat.RGB
    assert bitmap.component_format() == mi.Struct.Type.Float32
    exr = np.array(bitmap)
    assert exr.shape == (24, 40, 3)
    assert exr.max() > 1.0  # radiance, not tone mapped
    assert np.array_equal(exr, read_pfm(outs["pfm"])[..., :3])


def test_an_exr_map_lights_the_scene_as_its_pfm(tmp_path, mi):
    spots = ASSETS / "environments" / "spots.pfm"
    colour = pfm.decode_pfm(spots.read_bytes())[..., :3].astype(np.float32)
    mi.Bitmap(colour).write(str(tmp_path / "spots.exr"))
    # Grey half floats: values a half holds exactly, so the two maps are the same.
    grey = np.round(colour.mean(axis=-1, keepdims=True) * 4) / 4
    write_map(tmp_path / "grey.pfm", np.repeat(grey, 3, axis=-1))
    mi.Bitmap(grey.astype(np.float16)).write(str(tmp_path / "grey.exr"))
    scene = CAMERA + "material m albedo 0.6 0.6 0.6\nsphere 0 0 0 1 m\n"
    for pfm_name, exr_name in [(spots, "spots.exr"), ("grey.pfm", "grey.exr")]:
        images = [render(tmp_path, f"map{i}", scene + f"environment {name} rotate_y 30\n",
                         "--width", 32, "--height", 24, "--spp", 4, "--seed", 2)
                  for i, name in enumerate((pfm_name, exr_name))]
        assert images[0].max() > 0.1
        assert np.array_equal(images[0], images[1]), exr_name


@pytest.mark.parametrize("content, reason", [
    (b"#?RADIANCE\n", "is not a PFM or OpenEXR image (it starts with neither PF, Pf nor "
                      "the EXR magic number)"),
    ("cut", "is not a readable OpenEXR image (")])
def test_a_bad_exr_is_refused_at_the_environment_line(tmp_path, mi, content, reason):
    if content == "cut":  # the first 400 bytes of a good EXR
        mi.Bitmap(np.ones((32, 64, 3), np.float32)).write(str(tmp_path / "good.exr"))
        content = (tmp_path / "good.exr").read_bytes()[:400]
    (tmp_path / "bad.exr").write_bytes(content)
    scene, result = run_with_map(tmp_path, "18", "bad.exr", "x.exr")
    assert result.returncode == 3
    assert f"{scene}:4: environment 'bad.exr' ({tmp_path / 'bad.exr'}) {reason}" \
        in result.stderr, result.stderr
    assert not (tmp_path / "x.exr").exists()
