"""Chapter 27: motion, checked against a closed form, against stills and against
Mitsuba 3 (book/docs/maintainers.md).

- The closed form: a ball moving across a dark wall, seen through each pixel's centre
  (--view albedo), covers the pixel for the fraction of the shutter's interval that
  python_prototypes/instances.moving_sphere_coverage works out; the blurred picture's
  8 x 8 blocks agree with it within the noise of that many samples. A correct way of
  drawing the instants differently (stratified over the samples) passes; planted
  mistakes fail: no instant at all (every path at the shutter's opening), the object's
  space moved the wrong way, an instant beyond the interval.
- Stills: --instant S draws what the same scene draws with each moving instance moved
  by S of its motion and still (the top level built again around it): the same
  distance, normal and albedo at every pixel but a few on silhouettes.
- Mitsuba 3 has no motion blur: the blurred picture is the mean over the shutter of
  stills, so the chapter's scene is compared block by block, within 2%, with the mean
  of Mitsuba's stills at 8 instants (the middles of 8 equal parts of the interval).
- The window's animation plays the instants back and forth, the top level built again
  each frame; its last frame is the still at its instant.
- Refitting: the twisted teapot's refitted tree draws what the twisted triangles written
  out (numpy) draw; its SAH cost is the fresh tree's when untwisted and grows with the
  twist, never below a rebuild's.
- Bad input: --instant outside 0..1, --twist on a blurred picture and --animate without
  a window are exit code 2; chapter 26 refuses moving instances (test_26_instances.py).

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import json
import subprocess

import numpy as np
import path_checks
import pytest
from conftest import (ROOT, WINDOW_SAFETY_TIMEOUT, run_chapter, window_command,
                      xvfb_available)
from path_checks import SIGMAS

from course_tools.program_output import last_json_line
from python_prototypes import instances, mitsuba_reference, obj_io, scene_io, teapot
from python_prototypes.pfm import read_pfm

SCENES = ROOT / "assets" / "scenes"
MESH_FOLDERS = [ROOT / "build" / "assets"]
TEAPOT = ROOT / "build" / "assets" / "meshes" / "teapot_6320.obj"
SIZE = 48

# A ball (radius 0.25: the unit ball scaled, then turned, which the motion must not
# mind) crossing a dark wall while the shutter is open, up and to the right; a lamp
# behind the eye (every scene has one).
WALL, BALL = 0.1, 0.9
SMEAR = f"""camera eye 0 0 3 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.025 shutter 0 1
material wall albedo {WALL} {WALL} {WALL}
material ball albedo {BALL} {BALL} {BALL}
material lamp albedo 0 0 0 emission 1 1 1
quad -3 -3 -1   6 0 0   0 6 0   wall name wall
quad -0.1 0 3.5   0.2 0 0   0 0.2 0   lamp name lamp
object ball begin
  sphere 0 0 0 1 ball
end
instance ball scale 0.25 rotate 0 0 1 30 translate -0.5 -0.1 0 moving 0.9 0.3 0 name ball
"""
CENTRE, RADIUS, MOTION = (-0.5, -0.1, 0.0), 0.25, (0.9, 0.3, 0.0)

# The planted bugs: (file, the right text, the wrong one). Each must fail its check.
NO_INSTANT = ("path.comp", "    pathTime = random01(random);\n", "    random01(random);\n")
MOVED_THE_WRONG_WAY = ("instances.glsl", "    offset -= pathTime * placed.objectMotion.xyz;\n",
                       "    offset += pathTime * placed.objectMotion.xyz;\n")
BEYOND_THE_INTERVAL = ("path.comp", "    pathTime = random01(random);\n",
                       "    pathTime = 1.5 * random01(random);\n")
# A correct way of drawing them differently: stratified, each 16 samples one instant in
# each sixteenth of the interval (the chapter draws each independently).
STRATIFIED = ("path.comp", "    pathTime = random01(random);\n",
              "    pathTime = (float(sampleIndex % 16u) + random01(random)) / 16.0;\n")


def expected_smear(size: int) -> np.ndarray:
    """The albedo each pixel's centre sees, averaged over the shutter: the ball's for
    the fraction of the interval it covers the pixel, the wall's for the rest."""
    scene = scene_io.parse_scene(SMEAR, ROOT / "smear.scene")
    directions = mitsuba_reference.ray_directions(scene.camera, size, size)
    eye = np.asarray(scene.camera.eye, dtype=np.float64)
    coverage = np.array([[instances.moving_sphere_coverage(eye, d, CENTRE, MOTION, RADIUS)
                          for d in row] for row in directions])
    return WALL + coverage * (BALL - WALL)


def smear(tmp_path, label, spp, shader_dir=None):
    scene = tmp_path / "smear.scene"
    scene.write_text(SMEAR)
    extra = ["--shader-dir", shader_dir] if shader_dir else []
    return path_checks.path_trace("27", tmp_path, label, "--scene", scene, "--view", "albedo",
                                  "--width", SIZE, "--height", SIZE, "--spp", spp, *extra)


def assert_smear_as_the_closed_form(image: np.ndarray, spp: int):
    """Each 8 x 8 block's mean within SIGMAS standard errors of the closed form's, the
    error that of `spp` instants a pixel (each sees the ball or the wall: a coin)."""
    expected = expected_smear(SIZE)
    fraction = (expected - WALL) / (BALL - WALL)
    variance = fraction * (1 - fraction) * (BALL - WALL) ** 2 / spp
    blocks = lambda a: a.reshape(SIZE // 8, 8, SIZE // 8, 8).sum(axis=(1, 3)) / 64  # noqa: E731
    error = np.sqrt(blocks(variance) / 64)
    difference = np.abs(blocks(image[..., 0]) - blocks(expected))
    assert (fraction > 0.05).sum() > 100 and (fraction < 0.95).sum() > 100
    assert np.all(difference < SIGMAS * error + 2e-3), np.max(difference - SIGMAS * error)


@pytest.mark.windows
def test_a_moving_ball_smears_as_the_closed_form(tmp_path):
    assert_smear_as_the_closed_form(smear(tmp_path, "smear", 256), 256)


def test_instants_drawn_another_way_smear_the_same(tmp_path):
    shader_dir = path_checks.shaders_with_bug("27", tmp_path, STRATIFIED)
    assert_smear_as_the_closed_form(smear(tmp_path, "stratified", 256, shader_dir), 256)


@pytest.mark.parametrize("bug", [NO_INSTANT, MOVED_THE_WRONG_WAY, BEYOND_THE_INTERVAL],
                         ids=["no_instant", "moved_the_wrong_way", "beyond_the_interval"])
def test_planted_bug_fails_the_closed_form(tmp_path, bug):
    shader_dir = path_checks.shaders_with_bug("27", tmp_path, bug)
    with pytest.raises(AssertionError):
        assert_smear_as_the_closed_form(smear(tmp_path, "bug", 256, shader_dir), 256)


# --- Stills ------------------------------------------------------------------------------

def still_views(tmp_path, scene, label, *args):
    return {view: path_checks.path_trace("27", tmp_path, f"{label}_{view}", "--scene", scene,
                                         "--view", view, "--width", SIZE, "--height", SIZE,
                                         "--spp", 1, *args)
            for view in ("distance", "normals", "albedo")}


def assert_same_views(ours, theirs, silhouettes=4):
    agree = np.isclose(ours["distance"][..., 0], theirs["distance"][..., 0], rtol=1e-4)
    agree &= np.all(np.abs(ours["normals"] - theirs["normals"]) < 2e-3, axis=-1)
    agree &= np.all(np.abs(ours["albedo"] - theirs["albedo"]) < 1e-6, axis=-1)
    assert np.sum(~agree) <= silhouettes, np.argwhere(~agree)[:8]


def moved_text(text: str, instant: float) -> str:
    """The scene file with each `moving X Y Z` written as a last step `translate` by
    that share of it, and no shutter: the still, spelled without motion."""
    lines = []
    for line in text.splitlines():
        if line.lstrip().startswith("#"):
            continue
        words = line.split("#")[0].split()
        if words[:1] == ["instance"] and "moving" in words:
            at = words.index("moving")
            motion = [float(w) for w in words[at + 1:at + 4]]
            words[at:at + 4] = ["translate"] + [f"{instant * m:.9g}" for m in motion]
            line = " ".join(words)
        elif words[:1] == ["camera"] and "shutter" in words:
            at = words.index("shutter")
            line = " ".join(words[:at] + words[at + 3:])
        lines.append(line)
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("instant", [0.0, 0.4, 1.0])
def test_a_still_is_the_scene_with_its_instances_moved_that_far(tmp_path, instant):
    moved = tmp_path / "moved.scene"
    moved.write_text(moved_text((SCENES / "cornell_motion.scene").read_text(), instant))
    still = scene_io.load_scene(str(moved), [str(f) for f in MESH_FOLDERS])
    assert not still.moves() and still.camera.shutter_close == 0
    ours = still_views(tmp_path, SCENES / "cornell_motion.scene", "still", "--instant",
                       instant)
    theirs = still_views(tmp_path, moved, "moved")
    assert_same_views(ours, theirs)
    if instant > 0:  # and the still at the shutter's opening is not it
        opening = still_views(tmp_path, SCENES / "cornell_motion.scene", "opening",
                              "--instant", 0)
        with pytest.raises(AssertionError):
            assert_same_views(opening, theirs)


# --- Mitsuba 3: the mean of stills -------------------------------------------------------

INSTANTS = 8


def blocks_of(image: np.ndarray, block: int) -> np.ndarray:
    """An image's block x block squares, one a row of their pixels."""
    rows, columns = image.shape[0] // block, image.shape[1] // block
    return image.reshape(rows, block, columns, block).transpose(0, 2, 1, 3).reshape(
        rows * columns, block * block)


def test_the_blur_is_the_mean_of_mitsubas_stills(tmp_path):
    pytest.importorskip("mitsuba")
    size, spp = 64, 512
    scene = scene_io.load_scene(str(SCENES / "cornell_motion.scene"),
                                [str(f) for f in MESH_FOLDERS])
    stills = [path_checks.kept_mitsuba(scene.at_instant((k + 0.5) / INSTANTS), size, size,
                                       1024 // INSTANTS, 6, seed=k)
              for k in range(INSTANTS)]
    theirs = np.mean(stills, axis=0)
    ours = path_checks.path_trace("27", tmp_path, "blurred", "--width", size, "--height",
                                  size, "--spp", spp)
    a, b = blocks_of(ours.mean(axis=-1), 8), blocks_of(theirs.mean(axis=-1), 8)
    relative = a.mean(axis=1) / b.mean(axis=1) - 1
    error = np.std(a - (a.mean(axis=1) / b.mean(axis=1))[:, None] * b, axis=1,
                   ddof=1) / np.sqrt(a.shape[1]) / b.mean(axis=1)
    print("largest block difference", np.max(np.abs(relative)))
    assert np.all(np.abs(relative) < np.maximum(0.02, SIGMAS * error)), \
        (np.abs(relative).max(), relative)


# --- The window's animation ---------------------------------------------------------------

@pytest.mark.skipif(not xvfb_available(), reason="Xvfb is not installed")
def test_the_window_plays_the_instants_and_builds_the_top_level_each_frame(tmp_path,
                                                                          window_env):
    out = tmp_path / "window.pfm"
    # 4 frames a way: frames 0..6 show instants 0, 1/4, 1/2, 3/4, 1, 3/4, 1/2.
    result = subprocess.run(window_command("27", out, "--frames", 7, "--animate", 4,
                                           "--view", "albedo"),
                            capture_output=True, text=True, timeout=WINDOW_SAFETY_TIMEOUT,
                            env=window_env)
    assert result.returncode == 0, result.stderr
    stats = json.loads(result.stdout.strip().splitlines()[-1])
    assert stats["frames_shown"] == 8 and stats["instant"] == 0.5  # and the first still
    assert stats["samples_per_pixel"] == 1  # each frame starts over
    still = tmp_path / "still.pfm"
    run = run_chapter("27", "--headless", "--instant", 0.5, "--view", "albedo", "--width", 32,
                      "--height", 32, "--spp", 1, "--out", still)
    assert run.returncode == 0, run.stderr
    assert np.array_equal(read_pfm(out)[..., :3], read_pfm(still)[..., :3])


# --- Refitting the twisting teapot ------------------------------------------------------------

def twisted_obj(path, degrees: float):
    """The teapot twisted as the chapter twists it (instances.twisted_about_middle),
    written out (its OBJ has one normal a corner, which turns with it)."""
    positions, normals, corners, corner_normals = obj_io.read_obj(TEAPOT)
    assert np.array_equal(corners, corner_normals)
    teapot.write_obj(path, *instances.twisted_about_middle(positions, normals, degrees),
                     corners)


def test_the_refitted_teapot_draws_the_twisted_triangles(tmp_path):
    twisted = tmp_path / "twisted.obj"
    twisted_obj(twisted, 90)
    written = tmp_path / "written.scene"
    written.write_text((SCENES / "cornell_twist.scene").read_text().replace(
        "meshes/teapot_6320.obj", str(twisted)))
    ours = still_views(tmp_path, SCENES / "cornell_twist.scene", "refitted", "--instant", 1,
                       "--twist", 90)
    assert_same_views(ours, still_views(tmp_path, written, "written"))


def sah_costs(instant: float) -> tuple[float, float]:
    result = run_chapter("27", "--headless", "--scene", "cornell_twist", "--instant", instant,
                         "--twist", 90, "--width", 8, "--height", 8, "--spp", 1, "--json")
    assert result.returncode == 0, result.stderr
    stats = last_json_line(result.stdout, "27")
    return stats["object_sah_cost"], stats["rebuilt_sah_cost"]


def test_a_refitted_tree_costs_more_as_the_twist_grows():
    costs = [sah_costs(instant) for instant in (0.0, 0.25, 0.5, 1.0)]
    refitted, rebuilt = zip(*costs)
    assert refitted[0] == pytest.approx(rebuilt[0], rel=1e-6)  # untwisted: the same tree
    assert all(a < b for a, b in zip(refitted, refitted[1:])), refitted
    assert all(r >= f * (1 - 1e-6) for r, f in zip(refitted, rebuilt)), costs
    assert refitted[-1] > 1.1 * rebuilt[-1], costs  # a quarter turn: well worth a rebuild


# --- Bad input -------------------------------------------------------------------------------

@pytest.mark.parametrize("arguments, words", [
    (["--instant", "1.5"], "a fraction of the shutter's interval"),
    (["--twist", "30"], "--twist deforms the objects at an instant"),
    (["--animate", "4"], "--animate plays the motion in the window"),
])
def test_options_that_do_not_go_together_are_exit_2(tmp_path, arguments, words):
    result = run_chapter("27", "--headless", *arguments, "--out", tmp_path / "x.png")
    assert result.returncode == 2 and words in result.stderr, result.stderr
    assert not (tmp_path / "x.png").exists()
