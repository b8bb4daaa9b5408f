"""What the path tracers' checks (chapters 11 and 12) share: rendering to linear PFM,
the standard error of a mean over pixels, a closed-form form factor, and the region by
region comparison with Mitsuba 3.

Every expected value is compared with the statistical error of the estimate: the
standard error of a mean of N independent pixels is the spread of the pixels over
sqrt(N). Limits of 4.5 standard errors fail a correct renderer about once in 150,000
comparisons; the seeds are fixed, so the results do not change from run to run."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT, read_pfm, regions_agreeing, run_chapter

SCENES = ROOT / "tests" / "data" / "scenes"
SIGMAS = 4.5


def path_trace(chapter: str, tmp_path, name: str, *args) -> np.ndarray:
    """Renders with the chapter to a PFM (linear) and returns it (height, width, 3)."""
    out = tmp_path / f"{name}.pfm"
    result = run_chapter(chapter, "--headless", "--out", out, *map(str, args))
    assert result.returncode == 0, result.stderr
    return read_pfm(out)[..., :3]


def mean_and_error(values: np.ndarray):
    """Mean and standard error of the mean over the first axis (pixels)."""
    values = values.reshape(-1, values.shape[-1])
    return values.mean(axis=0), values.std(axis=0, ddof=1) / math.sqrt(len(values))


def assert_mean_everywhere(image: np.ndarray, expected: float, block: int = 8):
    """The image's mean is `expected` within SIGMAS standard errors (plus 1e-4 for float
    rounding), and so is each block x block square's: everywhere, not just on average.
    (Single pixels are no test at a few dozen samples: Russian roulette makes their
    distribution heavy-tailed.)"""
    mean, error = mean_and_error(image)
    assert np.all(np.abs(mean - expected) < SIGMAS * error + 1e-4), (mean, error)
    rows, columns = image.shape[0] // block, image.shape[1] // block
    squares = image[:rows * block, :columns * block].reshape(rows, block, columns, block, 3)
    for square in squares.swapaxes(1, 2).reshape(rows * columns, block * block, 3):
        square_mean, square_error = mean_and_error(square)
        assert np.all(np.abs(square_mean - expected) < SIGMAS * square_error + 1e-4), \
            square_mean


def rectangle_form_factor(a: float, b: float, h: float) -> float:
    """Form factor from a small patch to a parallel a x b rectangle h above it, one
    corner straight above the patch (the standard closed form)."""
    x, y = a / h, b / h
    return (x / math.sqrt(1 + x * x) * math.atan(y / math.sqrt(1 + x * x))
            + y / math.sqrt(1 + y * y) * math.atan(x / math.sqrt(1 + y * y))) / (2 * math.pi)


def square_light_expected() -> float:
    """tests/data/scenes/square_light.scene: the floor (albedo 0.5) under the centre of a
    0.5 m square light (radiance 10) 1 m up, made of four 0.25 m squares each with a
    corner above the point. Radiance = albedo / pi * irradiance = albedo * L_e * F."""
    return 0.5 * 10.0 * 4 * rectangle_form_factor(0.25, 0.25, 1.0)


def assert_agrees_with_mitsuba(ours: np.ndarray, spp: int = 512,
                               scene_file: Path = ROOT / "assets" / "scenes" /
                               "cornell_spheres.scene", mesh_folders=(),
                               most_relative: float | None = None) -> list[str]:
    """Every region of the scene (the pixels that see one wall, sphere, mesh or the
    light, at least 20) within SIGMAS standard errors of Mitsuba 3's render at `spp`,
    and within most_relative of its brightness if given. Returns the regions compared."""
    pytest.importorskip("mitsuba")
    import mitsuba_reference
    import scene_io
    scene = scene_io.load_scene(str(scene_file), [str(f) for f in mesh_folders])
    height, width = ours.shape[:2]
    theirs, _ = mitsuba_reference.render_mitsuba(scene, width, height, spp, 6, seed=0,
                                                 variant="scalar_rgb")
    return regions_agreeing(ours, np.asarray(theirs)[..., :3], scene_file, SIGMAS,
                            mesh_folders, most_relative)
