"""Chapter 02: the test pattern must equal an independent numpy computation of it,
for both dispatch shapes, both headless backends and the window."""

import subprocess

import numpy as np
import pytest

from conftest import (BACKENDS, BIN, WINDOW_SAFETY_TIMEOUT, copy_shaders, read_image, render,
                      run_chapter, srgb_encode_8bit, xvfb_available)
from python_prototypes.reference.first_pixels import first_pixels_pattern

# Sizes that are not multiples of 64 (1D groups) or 8 (2D tiles) on purpose.
WIDTH, HEIGHT = 203, 157


@pytest.mark.windows
@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("dispatch", ["1d", "2d"])
def test_pattern_equals_numpy(tmp_path, backend, dispatch):
    args = ["--width", WIDTH, "--height", HEIGHT, "--backend", backend, "--dispatch", dispatch]
    linear = render("02", tmp_path / "pattern.pfm", *args)
    reference = first_pixels_pattern(WIDTH, HEIGHT)
    assert np.max(np.abs(linear - reference)) < 1e-6

    png = render("02", tmp_path / "pattern.png", *args)
    assert np.max(np.abs(png - srgb_encode_8bit(reference))) <= 1.0


def test_check_rejects_a_wrong_pattern(tmp_path):
    """The comparison must fail for a plausible mistake: rows and columns swapped."""
    shaders = copy_shaders("02", tmp_path)
    source = shaders / "pattern_1d.comp"
    text = source.read_text()
    wrong = "uvec2(index / imageSize.x, index % imageSize.x)"
    source.write_text(text.replace("uvec2(index % imageSize.x, index / imageSize.x)", wrong))
    linear = render("02", tmp_path / "wrong.pfm", "--width", 64, "--height", 48,
                    "--shader-dir", shaders)
    assert np.max(np.abs(linear - first_pixels_pattern(64, 48))) > 0.1


@pytest.mark.skipif(not xvfb_available(), reason="Xvfb is not installed")
def test_window_renders_frames_and_exits(tmp_path, window_env):
    out = tmp_path / "window.png"
    result = subprocess.run(
        [str(BIN / "02_first_pixels"), "--window", "--frames", "20", "--width", "160",
         "--height", "120", "--out", str(out)],
        capture_output=True, text=True, timeout=WINDOW_SAFETY_TIMEOUT, env=window_env)
    assert result.returncode == 0, result.stderr
    image = read_image(out)
    assert np.max(np.abs(image - srgb_encode_8bit(first_pixels_pattern(160, 120)))) <= 1.0


def test_default_output_name_in_working_folder(tmp_path):
    result = run_chapter("02", "--headless", "--width", 32, "--height", 32)
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "02_first_pixels.png").exists()
    assert str(tmp_path / "02_first_pixels.png") in result.stdout


def test_shader_error_in_included_file_names_file_and_line(tmp_path):
    shaders = copy_shaders("02", tmp_path)
    included = shaders / "pattern.glsl"
    lines = included.read_text().splitlines()
    broken_line = next(i for i, l in enumerate(lines) if "vec2 centre" in l) + 1
    lines[broken_line - 1] = "    vec2 centre = this is not glsl;"
    included.write_text("\n".join(lines) + "\n")
    result = run_chapter("02", "--headless", "--out", tmp_path / "x.png", "--shader-dir", shaders)
    assert result.returncode == 4
    assert f"shaders/02_first_pixels/pattern.glsl:{broken_line}:" in result.stderr
    assert not (tmp_path / "x.png").exists()
