"""Chapter 03: every ray the shader makes must be the ray of the Python prototype
(python_prototypes/camera_rays.py), for the default camera and another one, at a size
that is not a multiple of the 8x8 tiles; and a wrong camera must be noticed."""

import numpy as np
import pytest

from python_prototypes import camera_rays
from conftest import (BACKENDS, assert_images_agree, copy_shaders, render, run_chapter,
                      srgb_encode_8bit)

WIDTH, HEIGHT = 161, 121  # odd on purpose: tiles overhang, and the centre is a pixel

# A camera unlike the default in every respect: elsewhere, looking sideways and down,
# tilted (up is not +y), a wider lens on a smaller sensor.
OTHER_CAMERA = dict(eye=(2.0, 3.0, -1.0), look_direction=(-1.0, -0.5, 0.3),
                    up=(0.2, 1.0, 0.1), focal_length=0.024, sensor_width=0.0235)


def camera_arguments(camera: dict) -> list:
    vector = lambda v: ",".join(f"{x:g}" for x in v)  # noqa: E731
    return ["--camera-eye", vector(camera["eye"]),
            "--camera-look", vector(camera["look_direction"]),
            "--camera-up", vector(camera["up"]),
            "--focal-length", camera["focal_length"],
            "--sensor-width", camera["sensor_width"]]


def reference_colors(width, height, camera: dict | None = None) -> np.ndarray:
    rays = camera_rays.camera_rays(camera_rays.Camera(**(camera or {})), width, height)
    return camera_rays.ray_colors(rays)


@pytest.mark.windows
@pytest.mark.parametrize("backend", BACKENDS)
def test_every_ray_equals_the_prototype(tmp_path, backend):
    args = ["--width", WIDTH, "--height", HEIGHT, "--backend", backend]
    linear = render("03", tmp_path / "rays.pfm", *args)
    reference = reference_colors(WIDTH, HEIGHT)
    assert np.max(np.abs(linear - reference)) < 1e-5

    png = render("03", tmp_path / "rays.png", *args)
    assert_images_agree(png, srgb_encode_8bit(reference), label=backend)
    assert np.max(np.abs(png - srgb_encode_8bit(reference))) <= 1.0


@pytest.mark.parametrize("backend", BACKENDS)
def test_another_camera_equals_the_prototype_command_line(tmp_path, backend):
    """Both programs get the same camera on their command lines."""
    npy = tmp_path / "rays.npy"
    camera_rays.main(["--width", str(WIDTH), "--height", str(HEIGHT), "--out-npy", str(npy),
                      "--eye", *map(str, OTHER_CAMERA["eye"]),
                      "--look-direction", *map(str, OTHER_CAMERA["look_direction"]),
                      "--up", *map(str, OTHER_CAMERA["up"]),
                      "--focal-length", str(OTHER_CAMERA["focal_length"]),
                      "--sensor-width", str(OTHER_CAMERA["sensor_width"])])
    reference = camera_rays.ray_colors(np.load(npy).astype(np.float64))
    linear = render("03", tmp_path / "rays.pfm", "--width", WIDTH, "--height", HEIGHT,
                    "--backend", backend, *camera_arguments(OTHER_CAMERA))
    assert np.max(np.abs(linear - reference)) < 1e-5
    # The other camera really is another picture.
    assert np.max(np.abs(linear - reference_colors(WIDTH, HEIGHT))) > 0.1


# The two classic camera mistakes, planted in a copy of the shader.
MISTAKES = {
    # Row 0 is the top of the image but +up is the top of the sensor: forget to turn
    # one into the other and the picture is upside down.
    "upside_down": ("float upwards = 0.5 - centre.y;", "float upwards = centre.y - 0.5;"),
    # A square sensor for a 4:3 image: the picture is squashed vertically.
    "square_sensor": ("* float(imageSize.y) / float(imageSize.x);", ";"),
}


@pytest.mark.parametrize("mistake", MISTAKES)
def test_check_rejects_a_wrong_camera(tmp_path, mistake):
    shaders = copy_shaders("03", tmp_path)
    source = shaders / "camera.glsl"
    right, wrong = MISTAKES[mistake]
    assert right in source.read_text()
    source.write_text(source.read_text().replace(right, wrong))
    png = render("03", tmp_path / "wrong.png", "--width", WIDTH, "--height", HEIGHT,
                 "--shader-dir", shaders)
    with pytest.raises(AssertionError):
        assert_images_agree(png, srgb_encode_8bit(reference_colors(WIDTH, HEIGHT)))


BAD_CAMERAS = [
    (["--camera-eye", "nan,0,0"], "--camera-eye expects a finite number"),
    (["--camera-eye", "1,2"], "--camera-eye expects three numbers"),
    (["--camera-look", "0,0,0"], "camera: the look direction must not be zero"),
    (["--camera-up", "0,0,0"], "camera: the up direction must not be zero"),
    (["--camera-look", "0,-2,0"], "camera: up must not be parallel to the look direction"),
    (["--focal-length", "0"], "must be positive"),
    (["--sensor-width", "inf"], "--sensor-width expects a finite number"),
]


@pytest.mark.parametrize("args,message", BAD_CAMERAS, ids=[" ".join(a) for a, _ in BAD_CAMERAS])
def test_bad_camera_is_exit_2(tmp_path, args, message):
    result = run_chapter("03", "--headless", "--out", tmp_path / "x.png", *args)
    assert result.returncode == 2, result.stderr
    assert message in result.stderr
    assert list(tmp_path.iterdir()) == []
