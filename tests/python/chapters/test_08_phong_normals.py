"""Chapter 08: smooth shading. The chapter's teapot, with the file's normals or with
normals it computes itself, must agree with the numpy reference (mesh_scene.py, smooth
mode, which computes its own area-weighted normals) on both backends; --flat must give
chapter 07's picture; planted mistakes in the interpolation must be rejected; and the
shadow terminator problem must be there, as the book describes it, not hidden."""

import numpy as np
import pytest

from python_prototypes import obj_io
from python_prototypes.reference import mesh_scene
from python_prototypes import teapot
from conftest import (BACKENDS, ROOT, assert_images_agree, copy_shaders, loop_limit,
                      read_image, render, run_chapter, srgb_encode_8bit)

WIDTH, HEIGHT = 160, 120
SMALL = 80, 60  # for pictures that only have to be rejected
MESHES = ROOT / "build" / "assets" / "meshes"
OBJ = ROOT / "tests" / "data" / "obj"
TEAPOT = MESHES / "teapot_552.obj"
TEAPOT_NO_NORMALS = MESHES / "teapot_552_no_normals.obj"


@pytest.fixture(scope="module")
def reference():
    """reference(obj, width, height, smooth): mesh_scene.py's trace, computed once per
    module for each file, size and mode; .png holds the picture as 8-bit sRGB."""
    cache = {}

    def trace(obj, width=WIDTH, height=HEIGHT, smooth=True):
        key = (str(obj), width, height, smooth)
        if key not in cache:
            positions, normals, triangles, normal_triangles = obj_io.read_obj(obj)
            result = mesh_scene.trace_mesh(positions, triangles, normals, normal_triangles,
                                           width, height, smooth)
            cache[key] = (result, srgb_encode_8bit(result.image))
        return cache[key]
    return trace


def png_of(reference, *args, **kwargs):
    return reference(*args, **kwargs)[1]


def render_mesh(tmp_path, *args, size=(WIDTH, HEIGHT), name="mesh.png"):
    return render("08", tmp_path / name, "--width", size[0], "--height", size[1], *args)


@pytest.fixture(scope="module")
def smooth_png(tmp_path_factory):
    """The chapter's default picture (teapot_552.obj) on the first backend, rendered once."""
    return render_mesh(tmp_path_factory.mktemp("smooth"), "--backend", BACKENDS[0])


# ---------------------------------------------------------------------------------------
# Pictures against the reference
# ---------------------------------------------------------------------------------------

@pytest.mark.windows
@pytest.mark.parametrize("backend", BACKENDS)
def test_smooth_teapot_agrees_with_numpy(tmp_path, reference, smooth_png, backend):
    png = (smooth_png if backend == BACKENDS[0]  # rendered already
           else render_mesh(tmp_path, "--backend", backend))  # no --obj: teapot_552.obj
    assert_images_agree(png, png_of(reference, TEAPOT), label=backend)


def test_computed_normals_agree_with_numpy(tmp_path, reference):
    """A file without vn lines: the chapter computes area-weighted vertex normals in
    C++, the reference computes its own in numpy."""
    png = render_mesh(tmp_path, "--obj", TEAPOT_NO_NORMALS)
    assert_images_agree(png, png_of(reference, TEAPOT_NO_NORMALS))


@pytest.mark.parametrize("name", ["cube_normals.obj", "no_normals.obj", "tri_vn.obj",
                                  "negative_idx.obj"])
def test_corpus_files_agree_with_numpy(tmp_path, reference, name):
    png = render_mesh(tmp_path, "--obj", OBJ / name)
    assert_images_agree(png, png_of(reference, OBJ / name), label=name)


def test_flat_is_chapter_07s_picture(tmp_path, reference, smooth_png):
    flat = render_mesh(tmp_path, "--flat", name="flat.png")
    assert_images_agree(flat, png_of(reference, TEAPOT, smooth=False))
    smooth = smooth_png
    result, _ = reference(TEAPOT)
    on_mesh = (result.triangle >= 0) & (result.triangle < 552)
    differs = np.any(np.abs(flat - smooth) > 2, axis=-1)
    assert not differs[~on_mesh].any(), "floor and sky are the same"
    assert np.mean(differs[on_mesh]) > 0.5, "the facets are gone from most of the teapot"


# ---------------------------------------------------------------------------------------
# Mistakes the check must catch
# ---------------------------------------------------------------------------------------

MISTAKES = {
    # u and v swapped: each corner's normal blended with another corner's weight.
    "swap_uv": ("triangle.glsl", "u * normals.n1 + v * normals.n2",
                "v * normals.n1 + u * normals.n2"),
    # The blend not normalised: between the corners it is shorter than 1, so darker.
    "not_normalized": ("triangle.glsl", "? normalize(blended) :", "? blended :"),
    # The flat normal used for shading after all: chapter 07's facets.
    "flat_after_all": ("triangle.glsl", "vec3 normal = flatShading ? geometricNormal",
                       "vec3 normal = true ? geometricNormal"),
}


@pytest.mark.parametrize("mistake", MISTAKES)
def test_check_rejects_a_planted_mistake(tmp_path, reference, mistake):
    file_name, right, wrong = MISTAKES[mistake]
    shaders = copy_shaders("08", tmp_path)
    source = shaders / file_name
    assert right in source.read_text()
    source.write_text(source.read_text().replace(right, wrong))
    png = render_mesh(tmp_path, "--shader-dir", shaders, size=SMALL)
    with pytest.raises(AssertionError):
        assert_images_agree(png, png_of(reference, TEAPOT, *SMALL))


# ---------------------------------------------------------------------------------------
# The shadow terminator problem, as the book tells it
# ---------------------------------------------------------------------------------------

def test_the_shadow_terminator_problem_is_not_hidden(reference, smooth_png):
    """Where the smooth normal faces the light but the flat triangle does not, the
    shadow ray crosses the triangle's own plane: those pixels get ambient light only."""
    png = smooth_png
    result, _ = reference(TEAPOT)
    to_light = result.light_position - result.position
    on_mesh = (result.triangle >= 0) & (result.triangle < 552)
    smooth_says_lit = np.sum(result.normal * to_light, axis=-1) > 0.0
    flat_faces_away = np.sum(result.geometric_normal * to_light, axis=-1) <= 0.0
    mismatch = on_mesh & smooth_says_lit & flat_faces_away
    assert mismatch.sum() >= 20, "the teapot of 552 triangles shows the problem"
    ambient = srgb_encode_8bit(np.array(mesh_scene.MESH_ALBEDO) * mesh_scene.AMBIENT)
    assert np.mean(np.all(np.abs(png[mismatch] - ambient) <= 2, axis=-1)) > 0.95


# ---------------------------------------------------------------------------------------
# What chapter 07 taught still holds
# ---------------------------------------------------------------------------------------

def test_bad_obj_is_still_exit_3_with_file_and_line(tmp_path):
    bad = OBJ / "bad" / "index_zero.obj"
    result = run_chapter("08", "--headless", "--out", tmp_path / "x.png", "--obj", bad)
    assert result.returncode == 3
    assert f"{bad}:5: " in result.stderr
    assert not (tmp_path / "x.png").exists()


def test_the_loop_limit_still_holds(tmp_path, reference):
    # 69 432 triangles: over Mesa 22's limit even for the camera rays' loop alone. As
    # the chapter measures its GL: refused, or (no limit) drawn like the reference.
    patches, control_points = teapot.load_patches()
    positions, normals, triangles = teapot.tessellate(patches, control_points, segments=33)
    big = tmp_path / "teapot_69432.obj"
    teapot.write_obj(big, positions, normals, triangles)
    result = run_chapter("08", "--headless", "--out", tmp_path / "big.png", "--width", 8,
                         "--height", 8, "--obj", big)
    if loop_limit("08") is None:
        assert result.returncode == 0, result.stderr
        assert_images_agree(read_image(tmp_path / "big.png"), png_of(reference, big, 8, 8))
        return
    assert result.returncode == 4, result.stderr
    assert f"{len(triangles) + 2} triangles" in result.stderr and "Chapter 13" in result.stderr
    assert not (tmp_path / "big.png").exists()
