"""Appendix A2: chapter 12's path tracer as an OpenGL 3.3 fragment shader.

It runs on contexts that really are 3.3 (Mesa with its version forced down, on EGL and
on OSMesa), refuses 3.2, and calls no GL function newer than 3.3. Its pictures are
chapter 12's: on llvmpipe the same seed gives the same bits (the random streams, the
arithmetic and the order of the samples are the same), for spheres and for triangles
(faceted gems, smooth teapots, a lone glowing triangle), and with another seed the
regions of the Cornell box agree within their statistical error
(book/docs/maintainers.md)."""

from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

import gl_registry
from path_checks import render_with_stats as render
from conftest import (ROOT, WINDOW_SAFETY_TIMEOUT, check_hot_reload, copy_shaders,
                      loop_limit, read_pfm, regions_agreeing, run_chapter, window_command,
                      xvfb_available)

GL33 = {"MESA_GL_VERSION_OVERRIDE": "3.3", "MESA_GLSL_VERSION_OVERRIDE": "330"}
SCENES = ROOT / "assets" / "scenes"
SIGMAS = 4.5  # as chapter 12's checks: a correct renderer fails 1 in ~150,000
SIZE = ("--width", "48", "--height", "48")
pytestmark = pytest.mark.filterwarnings("ignore::RuntimeWarning")


# --- The same pictures as chapter 12 --------------------------------------------------

@pytest.fixture(scope="module")
def pictures(tmp_path_factory):
    """Chapter 12 (GL 4.5) and the appendix on forced 3.3 contexts, global and direct."""
    folder = tmp_path_factory.mktemp("pictures")
    runs = {}
    for light in ("global", "direct"):
        options = [*SIZE, "--spp", 64] + (["--direct"] if light == "direct" else [])
        runs["12", light, 1] = render("12", folder, f"c12_{light}", *options, "--seed", 1)
        runs["egl", light, 1] = render("A2", folder, f"egl_{light}", *options, "--seed", 1,
                                       "--backend", "egl", env=GL33)
        runs["egl", light, 2] = render("A2", folder, f"egl_{light}_2", *options, "--seed", 2,
                                       "--backend", "egl", env=GL33)
    runs["osmesa", "global", 1] = render("A2", folder, "osmesa", *SIZE, "--spp", 64,
                                         "--seed", 1, "--backend", "osmesa", env=GL33)
    return runs


def test_runs_on_gl33_contexts_egl_and_osmesa(pictures):
    for backend in ("egl", "osmesa"):
        _, stats = pictures[backend, "global", 1]
        assert stats["gl_version"].startswith("3.3 (Core Profile)"), stats
        assert stats["backend"].startswith(backend), stats
    _, stats = pictures["12", "global", 1]
    assert not stats["gl_version"].startswith("3.3")  # chapter 12 needs 4.3
    a, b = pictures["egl", "global", 1][0], pictures["osmesa", "global", 1][0]
    assert np.array_equal(a, b)  # the same Mesa behind both


@pytest.mark.parametrize("light", ["global", "direct"])
def test_same_seed_same_samples_as_chapter_12(pictures, light):
    # The same random streams, rays and arithmetic, one sample per pass as chapter 12 has
    # one per dispatch: on llvmpipe (one compiler for compute and fragment shaders) the
    # images are the same bits, and every pixel traced the same number of rays. Another
    # GL may compile the two shaders differently; then only the statistics below hold.
    ours, our_stats = pictures["egl", light, 1]
    theirs, their_stats = pictures["12", light, 1]
    assert our_stats["rays"] == their_stats["rays"]
    if "llvmpipe" in our_stats["renderer"]:
        assert np.array_equal(ours, theirs)
    else:
        assert np.abs(ours - theirs).mean() < 0.01 * theirs.mean()


@pytest.mark.parametrize("light", ["global", "direct"])
def test_regions_agree_with_chapter_12_statistically(pictures, light):
    # Independent streams (seed 2 against chapter 12's seed 1): each wall and sphere's
    # mean within 4.5 standard errors of the difference.
    ours, theirs = pictures["egl", light, 2][0], pictures["12", light, 1][0]
    assert not np.array_equal(ours, theirs)
    # The light has too few pixels wholly inside it at 48 x 48 to be compared.
    compared = regions_agreeing(ours, theirs,
                                SCENES / "cornell_spheres.scene", SIGMAS)
    assert len(compared) >= 7  # five walls, two spheres


# --- Triangles: chapter 12's meshes and normals, the same bits ------------------------

# The empty room with a lone glowing triangle on the back wall (flat: its corners share
# its own normal; NEE samples it, MIS weighs the paths that run into it) and the
# 552-triangle teapot from a file without normals (chapter 08's area-weighted ones).
LAMP_AND_TEAPOT = (SCENES / "cornell_room.scene").read_text() + """
material lamp albedo 0.5 0.5 0.5 emission 4 6 12
triangle -0.7 0.3 -0.99  -0.3 0.3 -0.99  -0.5 0.7 -0.99  lamp
mesh meshes/teapot_552_no_normals.obj white scale 0.3 rotate_y 30 translate 0 -1 0
"""
# Small and few samples, and every scene's shapes x 2 (--depth + 1) under the 65 535 loop
# iterations of Mesa 22's llvmpipe, or both programs would refuse it (exit code 4).
TRIANGLE_SCENES = {
    # 218 shapes: faceted gems, each facet with its normal from the file.
    "gems": ["--scene", "cornell_gems", "--width", 32, "--height", 32, "--spp", 8],
    # 6 326 shapes: the file's smooth normals; only --direct stays under the limit.
    "teapot": ["--scene", "cornell_teapot", "--direct", "--width", 24, "--height", 24,
               "--spp", 4],
    # 559 shapes, 3 bounces.
    "lamp_and_teapot": ["--scene", "lamp_and_teapot.scene", "--depth", 3, "--width", 32,
                        "--height", 32, "--spp", 8],
}


@pytest.fixture(scope="module")
def triangle_pictures(tmp_path_factory):
    """Chapter 12 and the appendix (forced 3.3, EGL), seed 1, on each TRIANGLE_SCENES."""
    folder = tmp_path_factory.mktemp("triangles")
    (folder / "lamp_and_teapot.scene").write_text(LAMP_AND_TEAPOT)
    runs = {}
    for name, options in TRIANGLE_SCENES.items():
        options = [folder / o if str(o).endswith(".scene") else o for o in options]
        runs["12", name] = render("12", folder, f"c12_{name}", *options, "--seed", 1)
        runs["A2", name] = render("A2", folder, f"a1_{name}", *options, "--seed", 1,
                                  env=GL33)
    return runs


@pytest.mark.windows
@pytest.mark.parametrize("scene", list(TRIANGLE_SCENES))
def test_triangles_same_seed_same_samples_as_chapter_12(triangle_pictures, scene):
    # The same corners and normals (placed in the world on the CPU as chapter 12 does),
    # the same hit test, normal blending and rules for the two normals: the same bits.
    ours, our_stats = triangle_pictures["A2", scene]
    theirs, their_stats = triangle_pictures["12", scene]
    for count in ("shapes", "emitters", "rays"):
        assert our_stats[count] == their_stats[count], count
    assert theirs.mean() > 0.01  # not a black picture
    if "llvmpipe" in our_stats["renderer"]:
        assert np.array_equal(ours, theirs)
    else:
        assert np.abs(ours - theirs).mean() < 0.01 * theirs.mean()


def test_flat_shading_normals_would_be_caught(tmp_path, triangle_pictures):
    # A check that cannot fail is not a check: the appendix shading the teapot with its
    # facets' own normals, as it did before it followed chapter 12, is not chapter 12's.
    shaders = copy_shaders("A2", tmp_path)
    triangle = shaders / "triangle.glsl"
    smooth = "vec3 normal = smoothNormal(normalsOf(triangle), barycentric, geometricNormal);"
    assert smooth in triangle.read_text()
    triangle.write_text(triangle.read_text().replace(smooth, "vec3 normal = geometricNormal;"))
    flat, _ = render("A2", tmp_path, "flat", *TRIANGLE_SCENES["teapot"], "--seed", 1,
                     "--shader-dir", shaders, env=GL33)
    assert not np.array_equal(flat, triangle_pictures["12", "teapot"][0])


def test_random_numbers_are_chapter_12s_file(tmp_path):
    # Bit for bit the same generator: the very same GLSL (it needs nothing above 3.30).
    ours = (ROOT / "shaders" / "A2_gl33_fragment" / "random.glsl").read_bytes()
    assert ours == (ROOT / "shaders" / "12_light_sampling" / "random.glsl").read_bytes()


def test_splitting_the_passes_changes_nothing(tmp_path):
    one, _ = render("A2", tmp_path, "one", "--width", 24, "--height", 24, "--spp", 16,
                    env=GL33)
    four, _ = render("A2", tmp_path, "four", "--width", 24, "--height", 24, "--spp", 16,
                     "--batches", 4, env=GL33)
    assert np.array_equal(one, four)


# --- GL 3.3 and nothing newer ---------------------------------------------------------

@pytest.mark.parametrize("backend", ["egl", "osmesa"])
def test_refuses_a_gl_32_context_with_exit_4(tmp_path, backend):
    out = tmp_path / "x.png"
    result = run_chapter("A2", "--headless", "--backend", backend, "--out", out,
                         env={"MESA_GL_VERSION_OVERRIDE": "3.2"})
    assert result.returncode == 4, result.stderr
    assert "needs OpenGL 3.3 core" in result.stderr
    assert "offers OpenGL 3.2" in result.stderr
    assert "compute" not in result.stderr  # the 4.3 chapters' advice is not for this one
    assert not out.exists()


# Common functions only the compute chapters call: the appendix must not.
COMPUTE_ONLY = ["dispatchCovering", "workGroupSize", "bindStorage", "bindImage",
                "loadCompute", "compileBeforeFirstDispatch"]
# How common/ keeps a newer call from a GL 3.3 context: a version check in the same
# function (or a helper that makes one, checked below).
GUARDS = ["GLAD_GL_VERSION_4_1", "GLAD_GL_VERSION_4_2", "GLAD_GL_VERSION_4_3",
          "setUniform(", "fromTexture_"]


def test_only_gl33_functions_in_the_appendix_and_the_common_code_it_runs():
    gl33 = gl_registry.core_commands((3, 3))
    assert {"glTexBuffer", "glUniformBlockBinding", "glQueryCounter"} <= gl33
    assert not {"glDispatchCompute", "glProgramUniform1i", "glMemoryBarrier"} & gl33
    appendix = sorted((ROOT / "chapters" / "A2_gl33_fragment").glob("*.[ch]*"))
    found = 0
    for path in appendix:
        for name, line in gl_registry.gl_calls(path):
            assert name in gl33, f"{path.name}:{line}: {name} is newer than GL 3.3"
            found += 1
        for function in COMPUTE_ONLY:
            assert function not in path.read_text(), f"{path.name} calls {function}"
    assert found > 30
    # common/: a newer call must sit behind a version check or in a compute-only function.
    for path in sorted((ROOT / "common").rglob("*.[ch]*")):
        for name, line in gl_registry.gl_calls(path):
            if name in gl33:
                continue
            function = gl_registry.enclosing_function(path, line)
            header = function.splitlines()[0]
            assert any(guard in function for guard in GUARDS) or \
                any(f"::{f}(" in header for f in COMPUTE_ONLY), \
                f"common/{path.relative_to(ROOT / 'common')}:{line}: {name} (newer than " \
                f"GL 3.3) is not behind a version check"
    # The helpers named as guards make the check themselves.
    program = (ROOT / "common" / "shader_program.cpp").read_text()
    assert "if (GLAD_GL_VERSION_4_1) return direct(" in program
    display = (ROOT / "common" / "display.cpp").read_text()
    assert "fromTexture_(!GLAD_GL_VERSION_4_3)" in display


# --- Scenes too large for the buffers -------------------------------------------------

CAMERA = "camera eye 0 0 3.9 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.025\n"


def test_more_materials_than_the_uniform_block_holds_is_exit_3(tmp_path):
    scene = tmp_path / "materials.scene"
    scene.write_text(CAMERA + "".join(f"material m{i} albedo 0.5 0.5 0.5 emission 1 1 1\n"
                                      for i in range(257)) + "sphere 0 0 0 1 m0\n")
    out = tmp_path / "x.png"
    result = run_chapter("A2", "--headless", "--scene", scene, "--out", out, env=GL33)
    assert result.returncode == 3, result.stderr
    assert str(scene) in result.stderr and "257 materials" in result.stderr
    assert "MAX_MATERIALS" in result.stderr
    assert not out.exists()


def test_more_emitters_than_the_uniform_block_holds_is_exit_3(tmp_path):
    scene = tmp_path / "lights.scene"
    spheres = "".join(f"sphere {i % 20 - 10} {i // 20 - 7} -5 0.1 glow\n" for i in range(257))
    scene.write_text(CAMERA + "material glow albedo 0.5 0.5 0.5 emission 1 1 1\n" + spheres)
    result = run_chapter("A2", "--headless", "--scene", scene, "--out", tmp_path / "x.png",
                         env=GL33)
    assert result.returncode == 3, result.stderr
    assert str(scene) in result.stderr and "257 emitting shapes" in result.stderr
    assert "MAX_EMITTERS" in result.stderr


def test_more_texels_than_the_buffer_texture_holds_is_exit_4(tmp_path):
    # The Cornell box with spheres needs 2 x 2 + 6 x 4 = 28 texels; a GL that allowed
    # only 27 (COURSE_MAX_TEXTURE_BUFFER_TEXELS lowers GL_MAX_TEXTURE_BUFFER_SIZE).
    out = tmp_path / "x.png"
    result = run_chapter("A2", "--headless", "--out", out,
                         env={**GL33, "COURSE_MAX_TEXTURE_BUFFER_TEXELS": "27"})
    assert result.returncode == 4, result.stderr
    assert "cornell_spheres.scene" in result.stderr and "28 texels" in result.stderr
    assert "GL_MAX_TEXTURE_BUFFER_SIZE" in result.stderr
    assert not out.exists()
    result = run_chapter("A2", "--headless", "--out", out, "--width", 8, "--height", 8,
                         env={**GL33, "COURSE_MAX_TEXTURE_BUFFER_TEXELS": "28"})
    assert result.returncode == 0, result.stderr


def test_a_triangles_corners_and_normal_count_in_the_texels(tmp_path):
    # The room's 6 quads (24 texels) and one triangle: 2 texels of indices, 3 corners
    # and the 1 normal they share (shared.h), 30 texels in all.
    scene = tmp_path / "one_triangle.scene"
    scene.write_text((SCENES / "cornell_room.scene").read_text() +
                     "triangle -0.5 -1 0  0.5 -1 0  0 0 0  white\n")
    out = tmp_path / "x.png"
    result = run_chapter("A2", "--headless", "--scene", scene, "--out", out,
                         env={**GL33, "COURSE_MAX_TEXTURE_BUFFER_TEXELS": "29"})
    assert result.returncode == 4, result.stderr
    assert "7 shapes need 30 texels" in result.stderr
    assert not out.exists()
    result = run_chapter("A2", "--headless", "--scene", scene, "--out", out, "--width", 8,
                         "--height", 8, env={**GL33, "COURSE_MAX_TEXTURE_BUFFER_TEXELS": "30"})
    assert result.returncode == 0, result.stderr


def test_too_many_loop_iterations_are_refused_as_in_chapter_12(tmp_path):
    # ~220 shapes x 1001 bounces: far beyond the 65535 iterations an invocation gets on
    # Mesa 22's llvmpipe. Refused where the appendix measures a limit for its fragment
    # shaders; drawn where there is none (paths end long before 1000 bounces).
    limit = loop_limit("A2", env=GL33)
    out = tmp_path / "x.png"
    result = run_chapter("A2", "--headless", "--scene", "cornell_gems", "--depth", 1000,
                         "--width", 8, "--height", 8, "--out", out, env=GL33)
    if limit is None:
        assert result.returncode == 0, result.stderr
        assert out.exists()
        return
    assert result.returncode == 4, result.stderr
    for words in ("cornell_gems.scene", f"after {limit} (measured)", "A lower --depth"):
        assert words in result.stderr, words
    assert not out.exists()


# --- Window mode ----------------------------------------------------------------------

@pytest.mark.skipif(not xvfb_available(), reason="Xvfb is not installed")
def test_window_on_gl33_refines_and_a_camera_move_starts_over(tmp_path, window_env):
    out = tmp_path / "window.pfm"
    result = subprocess.run(window_command("A2", out, "--frames", 20, "--frame-samples", 3,
                                           "--script-camera-move"),
                            capture_output=True, text=True, timeout=WINDOW_SAFETY_TIMEOUT,
                            env={**window_env, **GL33})
    assert result.returncode == 0, result.stderr
    stats = json.loads(result.stdout.strip().splitlines()[-1])
    assert stats["gl_version"].startswith("3.3"), stats
    # Frames 0 and 1 add 3 samples each, frame 2 moves and starts over, 2..19 add 3 each.
    assert stats["samples_per_pixel"] == 18 * 3
    assert stats["camera_z"] < 3.9 - 0.5
    assert read_pfm(out)[..., :3].mean() > 0.05


@pytest.mark.skipif(not xvfb_available(), reason="Xvfb is not installed")
def test_window_hot_reloads_and_survives_a_broken_shader(tmp_path, window_env):
    image = check_hot_reload("A2", copy_shaders("A2", tmp_path), "path.frag",
                             ("newMean = vec4(mean, 1.0);",
                              "newMean = vec4(0.25, 0.5, 0.75, 1.0);"),
                             tmp_path / "window.pfm", "--frame-samples", 1,
                             env={**window_env, **GL33})
    assert np.allclose(image, [0.25, 0.5, 0.75])
