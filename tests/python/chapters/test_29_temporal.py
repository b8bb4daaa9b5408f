"""Chapter 29: temporal accumulation, checked against Mitsuba 3 frame by frame, against
the frames drawn alone and against the numpy prototype's geometry
(python_prototypes/temporal.py).

- A still camera: four frames of one sample are the plain mean of four samples, the
  picture `--spp 4` draws (within float rounding), raw and denoised.
- A moving camera (the Cornell box, 1 sample a frame, 5 cm a frame, 2 seeds), against
  Mitsuba's render of each frame at 2 048 samples (relative MSE, as chapter 28's): from
  frame 4 on, every frame is closer than 4 samples in place without reprojection (the
  issue's measure), and, away from the lamp's rim (whose pixels one sample a frame shows
  whole or not at all), at most MOST_AGAINST_ALONE of the frame denoised alone
  (`--blend 1`; measured 0.44 to 0.54). With the history looked up where the pixel is
  now instead of where it was (the camera's motion left out: 0.80 at frame 4), the
  check fails.
- No ghosts: the boxes painted blue, the camera stepping 10 cm right and up a frame; on
  the pixels each step uncovers (the prototype finds them exactly: their surface was
  hidden from the last frame), the chapter's picture is Mitsuba's within the noise.
  Without the plane test the boxes' history is taken for the wall behind them, and the
  check fails.
- --frames-out writes every frame, the last the picture --out writes; the window draws
  the frames headless mode draws; bad options are exit code 2.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import dataclasses
import subprocess

import numpy as np
import path_checks
import pytest
from conftest import (ROOT, WINDOW_SAFETY_TIMEOUT, read_pfm, run_chapter, window_command,
                      xvfb_available)

from python_prototypes import scene_io, temporal
from python_prototypes.denoise import relative_mse

SCENE = ROOT / "assets" / "scenes" / "cornell_box.scene"
SIZE = 96
STEP = (0.05, 0.0, 0.0)
FRAMES = 10
CHECKED = (4, 7, 10)
SEEDS = (1, 2)
REFERENCE_SPP = 2048
MOST_AGAINST_ALONE = 0.63
# The ghost check: the painted boxes, stepping right and up; the frames whose uncovered
# pixels are compared (each with the frame before).
GHOST_STEP = (0.1, 0.1, 0.0)
GHOST_FRAMES = (2, 3)
GHOST_SEEDS = (1, 2, 3, 4, 5, 6)

# The planted bugs: (file, the right text, the wrong one). Each must fail its check.
NOT_MOVED = ("temporal.comp", "found = inPicture(before, position, point) &&",
             "found = inPicture(camera, position, point) &&")
NO_PLANE_TEST = ("temporal.comp", "    if (offPlane > allowed) return false;\n", "")


def frames(tmp_path, label, *args, scene=SCENE, count=FRAMES, step=STEP, seed=1):
    """Every frame's picture (denoised unless args say otherwise), 1 sample a frame."""
    prefix = tmp_path / f"{label}_{seed}"
    result = run_chapter("29", "--headless", "--scene", scene, "--width", SIZE, "--height",
                         SIZE, "--spp", 1, "--move-frames", count, "--move",
                         ",".join(map(str, step)), "--seed", seed, "--frames-out", prefix,
                         "--out", f"{prefix}.pfm", *args)
    assert result.returncode == 0, result.stderr
    return [read_pfm(f"{prefix}_{number:02d}.pfm") for number in range(1, count + 1)]


def moved_scene(scene, frame: int, step=STEP):
    """The scene seen from where the camera is at `frame` (1: where the file puts it)."""
    return dataclasses.replace(scene, camera=temporal.moved(
        scene.camera, np.multiply(step, frame - 1)))


def reference(scene, frame: int, step=STEP):
    return path_checks.kept_mitsuba(moved_scene(scene, frame, step), SIZE, SIZE,
                                    REFERENCE_SPP, 6, seed=0, variant="llvm_ad_rgb")


def away_from_the_lamp(image: np.ndarray) -> np.ndarray:
    """The pixels two or more away from any that shows the lamp (brighter than 1)."""
    near = image.mean(axis=-1) > 1.0
    for _ in range(2):
        grown = near.copy()
        grown[1:] |= near[:-1]
        grown[:-1] |= near[1:]
        grown[:, 1:] |= near[:, :-1]
        grown[:, :-1] |= near[:, 1:]
        near = grown
    return ~near


def test_a_still_camera_is_the_plain_mean(tmp_path):
    """Four frames of one sample, the camera still, are `--spp 4`: raw within float
    rounding; denoised, the variance read from s instead of the sample count, 99% of the
    pixels within 5e-4 of each other (measured 1.6e-4: the filter's weights turn the
    means' last bits into larger differences)."""
    for denoise, within in (("none", 1e-5), ("atrous", 5e-4)):
        blended = frames(tmp_path, f"still_{denoise}", "--denoise", denoise, count=4,
                         step=(0, 0, 0))[-1]
        four = path_checks.path_trace("29", tmp_path, f"four_{denoise}", "--scene", SCENE,
                                      "--width", SIZE, "--height", SIZE, "--spp", 4,
                                      "--seed", 1, "--denoise", denoise)
        apart = np.abs(blended - four) / (np.abs(four) + 1e-2)
        print(f"{denoise}: 99% within {np.quantile(apart, 0.99):.1e}, most {apart.max():.1e}")
        assert np.quantile(apart, 0.99) < within


@pytest.fixture(scope="module")
def alone(tmp_path_factory):
    """Each seed's frames drawn alone (--blend 1: no history), denoised."""
    folder = tmp_path_factory.mktemp("alone")
    return [frames(folder, "alone", "--blend", 1, seed=seed) for seed in SEEDS]


def assert_moving_frames_clean(tmp_path, alone, shader_dir=None, checked=CHECKED):
    extra = ["--shader-dir", shader_dir] if shader_dir else []
    scene = scene_io.load_scene(SCENE)
    blended = [frames(tmp_path, "blended", *extra, count=max(checked), seed=seed)
               for seed in SEEDS]
    for frame in checked:
        truth = reference(scene, frame)
        away = away_from_the_lamp(truth)
        # 4 samples where the camera is at this frame, no history (--blend 1), raw.
        in_place = [path_checks.path_trace("29", tmp_path, f"in_place_{frame}_{seed}",
                                           "--scene", SCENE, "--width", SIZE, "--height",
                                           SIZE, "--spp", 4, "--move-frames", frame,
                                           "--move", ",".join(map(str, STEP)), "--blend", 1,
                                           "--seed", seed, "--denoise", "none")
                    for seed in SEEDS]
        ours = np.mean([relative_mse(run[frame - 1], truth) for run in blended])
        ours_away = np.mean([relative_mse(run[frame - 1][away], truth[away])
                             for run in blended])
        alone_away = np.mean([relative_mse(run[frame - 1][away], truth[away])
                              for run in alone])
        four = np.mean([relative_mse(image, truth) for image in in_place])
        print(f"frame {frame}: blended {ours:.4f} (away from the lamp {ours_away:.4f}), "
              f"alone {alone_away:.4f} away, 4 samples in place raw {four:.4f}")
        assert ours < four
        assert ours_away < MOST_AGAINST_ALONE * alone_away


def test_moving_frames_beat_four_samples_and_the_frame_alone(tmp_path, alone):
    assert_moving_frames_clean(tmp_path, alone)


def test_history_looked_up_where_the_pixel_is_now_fails(tmp_path, alone):
    shader_dir = path_checks.shaders_with_bug("29", tmp_path, NOT_MOVED)
    with pytest.raises(AssertionError):
        assert_moving_frames_clean(tmp_path, alone, shader_dir, checked=(4,))


def assert_no_ghosts(tmp_path, shader_dir=None):
    """On the pixels each step uncovers, the picture's mean (over seeds) against
    Mitsuba's, per colour: within 12%, or 4 standard errors of the mean (measured -3% to
    -8%; without the plane test -21%)."""
    painted = tmp_path / "painted.scene"
    painted.write_text(temporal.painted_blue(SCENE.read_text()))
    scene = scene_io.load_scene(painted)
    extra = ["--shader-dir", shader_dir] if shader_dir else []
    runs = [frames(tmp_path, "ghost", *extra, scene=painted, count=max(GHOST_FRAMES),
                   step=GHOST_STEP, seed=seed) for seed in GHOST_SEEDS]
    for frame in GHOST_FRAMES:
        before = moved_scene(scene, frame - 1, GHOST_STEP).camera
        now = moved_scene(scene, frame, GHOST_STEP).camera
        uncovered = temporal.disoccluded(scene, before, now, SIZE)
        truth = reference(scene, frame, GHOST_STEP)[uncovered].mean(axis=0)
        values = np.array([run[frame - 1][uncovered].mean(axis=0) for run in runs])
        ours = values.mean(axis=0)
        error = values.std(axis=0, ddof=1) / np.sqrt(len(values))
        relative = ours / truth - 1
        print(f"frame {frame}, {uncovered.sum()} pixels uncovered: {np.round(relative, 3)} "
              f"of Mitsuba (standard error {np.round(error / truth, 3)})")
        assert uncovered.sum() >= 30
        assert np.all(np.abs(relative) < np.maximum(0.12, 4 * error / truth))


def test_no_ghosts_where_the_camera_uncovers_the_wall(tmp_path):
    assert_no_ghosts(tmp_path)


def test_without_the_plane_test_the_boxes_leave_ghosts(tmp_path):
    shader_dir = path_checks.shaders_with_bug("29", tmp_path, NO_PLANE_TEST)
    with pytest.raises(AssertionError):
        assert_no_ghosts(tmp_path, shader_dir)


@pytest.mark.windows
def test_frames_out_writes_every_frame_and_out_is_the_last(tmp_path):
    written = frames(tmp_path, "every", count=3)
    assert len(written) == 3 and not np.array_equal(written[0], written[2])
    assert np.array_equal(written[-1], read_pfm(tmp_path / "every_1.pfm"))


@pytest.mark.skipif(not xvfb_available(), reason="Xvfb is not installed")
def test_the_window_draws_the_frames_headless_draws(tmp_path, window_env):
    """The window draws a first frame, then one a frame shown (5), the camera stepping
    --move before each: headless mode's 6 frames, the same picture."""
    out = tmp_path / "window.pfm"
    result = subprocess.run(window_command("29", out, "--frames", 5, "--move", "0.05,0,0",
                                           "--scene", "cornell_box", "--seed", 3),
                            capture_output=True, text=True, timeout=WINDOW_SAFETY_TIMEOUT,
                            env=window_env)
    assert result.returncode == 0, result.stderr
    headless = tmp_path / "headless.pfm"
    run = run_chapter("29", "--headless", "--scene", "cornell_box", "--width", 32, "--height",
                      32, "--spp", 1, "--move-frames", 6, "--move", "0.05,0,0",
                      "--seed", 3, "--out", headless)
    assert run.returncode == 0, run.stderr
    assert np.allclose(read_pfm(out), read_pfm(headless), rtol=1e-5, atol=1e-6)


@pytest.mark.parametrize("arguments,words", [
    (["--blend", "1.5"], "--blend"),
    (["--blend", "-0.1"], "--blend"),
    (["--move", "1,2"], "--move"),
    (["--move-frames", "0"], "--move-frames"),
    (["--frames-out", "no/such/folder/frame"], "no/such/folder"),
])
def test_bad_options_are_exit_2(tmp_path, arguments, words):
    result = run_chapter("29", "--headless", "--out", tmp_path / "out.png", "--width", 16,
                         "--height", 16, "--spp", 1, *arguments)
    assert result.returncode == 2 and words in result.stderr, result.stderr
