"""Chapter 07: a mesh from an OBJ file. The chapter's picture of the teapot (and of
corpus files given with --obj) must agree with the numpy reference (mesh_scene.py, flat
shading) on both backends; the std430 mistake (--packed-vec3) and planted shader
mistakes must be rejected; bad files must end with exit code 3 and file:line; and where
the GL ends long loops (as the chapter measures: Mesa 22's llvmpipe), a mesh beyond
that limit must be refused with exit code 4, while one just inside it still renders
right. Where the GL has no such limit, the same meshes must render right."""

import json

import numpy as np
import pytest

from python_prototypes import obj_io
from python_prototypes.reference import mesh_scene
from python_prototypes import teapot
from conftest import (BACKENDS, ROOT, SMALLEST_KNOWN_LOOP_LIMIT, assert_images_agree,
                      copy_shaders, loop_limit, read_image, render, run_chapter,
                      srgb_encode_8bit)

WIDTH, HEIGHT = 160, 120
SMALL = 80, 60  # for pictures that only have to be rejected
MESHES = ROOT / "build" / "assets" / "meshes"
OBJ = ROOT / "tests" / "data" / "obj"


@pytest.fixture(scope="module")
def reference():
    """reference(obj, width, height): the sRGB picture of mesh_scene.py, computed once
    per module for each file and size (the numpy reference is what costs time here)."""
    cache = {}

    def picture(obj, width=WIDTH, height=HEIGHT):
        key = (str(obj), width, height)
        if key not in cache:
            positions, normals, triangles, normal_triangles = obj_io.read_obj(obj)
            linear = mesh_scene.render_mesh(positions, triangles, normals,
                                            normal_triangles, width, height)
            cache[key] = srgb_encode_8bit(linear)
        return cache[key]
    return picture


def render_mesh(tmp_path, *args, size=(WIDTH, HEIGHT), name="mesh.png"):
    return render("07", tmp_path / name, "--width", size[0], "--height", size[1], *args)


# ---------------------------------------------------------------------------------------
# Pictures against the reference
# ---------------------------------------------------------------------------------------

@pytest.mark.windows
@pytest.mark.parametrize("backend", BACKENDS)
def test_teapot_agrees_with_numpy(tmp_path, reference, backend):
    """No --obj: the generated teapot of 552 triangles, framed automatically."""
    result = run_chapter("07", "--headless", "--out", tmp_path / "teapot.png", "--width",
                         WIDTH, "--height", HEIGHT, "--backend", backend, "--json")
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["triangles"] == 552
    assert_images_agree(read_image(tmp_path / "teapot.png"),
                        reference(MESHES / "teapot_552.obj"), label=backend)


# A cube with normals, a quad with texture coordinates, negative indices, a pentagon:
# any mesh, framed the same way.
@pytest.mark.parametrize("name", ["cube_normals.obj", "quad_vt.obj", "negative_idx.obj",
                                  "pentagon.obj"])
def test_corpus_files_agree_with_numpy(tmp_path, reference, name):
    png = render_mesh(tmp_path, "--obj", OBJ / name)
    assert_images_agree(png, reference(OBJ / name), label=name)


def test_teapot_6320_renders_inside_the_budget(tmp_path, reference):
    """12 644 loop iterations per pixel: far below Mesa 22's llvmpipe's 65 535."""
    size = (64, 48)
    png = render_mesh(tmp_path, "--obj", MESHES / "teapot_6320.obj", size=size)
    assert_images_agree(png, reference(MESHES / "teapot_6320.obj", *size))


def test_relative_obj_path_from_any_folder(tmp_path, reference):
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "cube.obj").write_bytes((OBJ / "cube_normals.obj").read_bytes())
    png = render_mesh(tmp_path, "--obj", "meshes/cube.obj")
    assert_images_agree(png, reference(OBJ / "cube_normals.obj"))


# ---------------------------------------------------------------------------------------
# Mistakes the check must catch
# ---------------------------------------------------------------------------------------

def test_packed_vec3_positions_are_rejected(tmp_path, reference):
    """glm::vec3 is 12 bytes, a std430 vec3 or vec4 array element 16: every vertex but
    the first is read from the wrong bytes."""
    png = render_mesh(tmp_path, "--packed-vec3", size=SMALL)
    right = reference(MESHES / "teapot_552.obj", *SMALL)
    with pytest.raises(AssertionError):
        assert_images_agree(png, right)
    assert np.mean(np.abs(png - right) > 2) > 0.3  # not a subtle difference


MISTAKES = {
    # The normal turned away from the ray instead of towards it: lit faces go dark.
    "flip_sign": ("triangle.glsl", "dot(normal, ray.direction) > 0.0",
                  "dot(normal, ray.direction) < 0.0"),
    # The off-by-one, on the GPU's side: each corner takes the next vertex.
    "next_vertex": ("scene.glsl", "positions[triangle.corners.x].xyz",
                    "positions[triangle.corners.x + 1u].xyz"),
    # Shadow rays leaving below the surface: every lit face shadows itself.
    "offset_inward": ("shading.glsl", "hit.position + hit.normal * shadowOffset",
                      "hit.position - hit.normal * shadowOffset"),
}


@pytest.mark.parametrize("mistake", MISTAKES)
def test_check_rejects_a_planted_mistake(tmp_path, reference, mistake):
    file_name, right, wrong = MISTAKES[mistake]
    shaders = copy_shaders("07", tmp_path)
    source = shaders / file_name
    assert right in source.read_text()
    source.write_text(source.read_text().replace(right, wrong))
    png = render_mesh(tmp_path, "--shader-dir", shaders, size=SMALL)
    with pytest.raises(AssertionError):
        assert_images_agree(png, reference(MESHES / "teapot_552.obj", *SMALL))


# ---------------------------------------------------------------------------------------
# Bad files: exit code 3, file:line, no picture
# ---------------------------------------------------------------------------------------

def bad_files():
    rows = (OBJ / "bad" / "expected.tsv").read_text().splitlines()[1:]
    return [tuple(row.split("\t")) for row in rows if row.strip()]


@pytest.mark.parametrize("name, line, substring", bad_files())
def test_bad_obj_is_exit_3_with_file_and_line(tmp_path, name, line, substring):
    out = tmp_path / "out" / "never.png"
    out.parent.mkdir()
    result = run_chapter("07", "--headless", "--out", out, "--obj", OBJ / "bad" / name)
    assert result.returncode == 3, result.stderr
    assert f"{OBJ / 'bad' / name}:{line}: " in result.stderr
    assert substring in result.stderr.lower()
    assert list(out.parent.iterdir()) == []  # nothing written, not even a partial file


def test_missing_obj_names_the_absolute_path(tmp_path):
    result = run_chapter("07", "--headless", "--out", tmp_path / "x.png", "--obj",
                         "no/such/mesh.obj")
    assert result.returncode == 3
    assert str(tmp_path / "no" / "such" / "mesh.obj") in result.stderr
    assert not (tmp_path / "x.png").exists()


def test_mesh_without_extent_cannot_be_framed(tmp_path):
    point = tmp_path / "point.obj"
    point.write_text("v 1 2 3\nv 1 2 3\nv 1 2 3\nf 1 2 3\n")
    result = run_chapter("07", "--headless", "--out", tmp_path / "x.png", "--obj", point)
    assert result.returncode == 3
    assert f"{point}:0: cannot frame the mesh" in result.stderr
    assert not (tmp_path / "x.png").exists()


# ---------------------------------------------------------------------------------------
# The loop limit, as the chapter measures it
# ---------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def limit():
    """The chapter's own measurement: 65 535 on Mesa 22's llvmpipe, None without a limit."""
    return loop_limit("07")


@pytest.fixture(scope="module")
def renderer(tmp_path_factory):
    """The GL_RENDERER and GL_VERSION strings of the default backend."""
    out = tmp_path_factory.mktemp("probe") / "probe.png"
    probe = run_chapter("07", "--headless", "--width", 8, "--height", 8, "--json",
                        "--obj", OBJ / "tri_v.obj", "--out", out)
    assert probe.returncode == 0, probe.stderr
    stats = json.loads(probe.stdout)
    return f"{stats['renderer']}, OpenGL {stats['gl_version']}"


def test_a_mesh_beyond_the_measured_limit_is_refused_else_rendered_right(
        tmp_path, limit, renderer, reference):
    """102 082 triangles with the floor: 204 164 loop iterations for a lit pixel, beyond
    every known limit. Refused, naming the mesh, the count, the measured limit, the GL
    and the way out; or, on a GL without a limit, drawn like the reference."""
    patches, control_points = teapot.load_patches()
    positions, normals, triangles = teapot.tessellate(patches, control_points, segments=40)
    big = tmp_path / "teapot_102080.obj"
    teapot.write_obj(big, positions, normals, triangles)
    out = tmp_path / "big.png"
    result = run_chapter("07", "--headless", "--width", 16, "--height", 12, "--out", out,
                         "--obj", big)
    if limit is None:
        assert result.returncode == 0, result.stderr
        assert_images_agree(read_image(out), reference(big, 16, 12))
        return
    assert result.returncode == 4, result.stderr
    total = len(triangles) + 2  # the floor's two
    for words in (f"{big}: {total} triangles", str(2 * total), f"after {limit} (measured)",
                  renderer, "Chapter 13's BVH"):
        assert words in result.stderr
    assert not out.exists()


def grid_obj(path, triangle_count):
    """A tilted square of `triangle_count` small triangles, all in one plane (so that
    pixels on their shared edges look the same whichever triangle they hit)."""
    side = 128
    lines = [f"v {x / side} {0.5 * z / side} {z / side}"
             for z in range(side + 1) for x in range(side + 1)]
    faces = []
    for z in range(side):
        for x in range(side):
            a = z * (side + 1) + x + 1
            faces += [f"f {a} {a + 1} {a + side + 2}", f"f {a} {a + side + 2} {a + side + 1}"]
    assert triangle_count <= len(faces)
    path.write_text("\n".join(lines + faces[:triangle_count]) + "\n")


def test_a_mesh_just_inside_the_limit_still_renders_right(tmp_path, limit, reference):
    """With the floor, 32 767 triangles: 65 534 loop iterations for a lit pixel, one under
    Mesa 22's limit. One more triangle and the chapter refuses, where the GL measures
    that limit; where it has none, that one renders right too."""
    budget = limit or SMALLEST_KNOWN_LOOP_LIMIT
    inside = tmp_path / "inside.obj"
    grid_obj(inside, budget // 2 - 2)
    png = render_mesh(tmp_path, "--obj", inside, size=(16, 12))
    assert_images_agree(png, reference(inside, 16, 12))

    beyond = tmp_path / "beyond.obj"
    grid_obj(beyond, budget // 2 - 1)
    result = run_chapter("07", "--headless", "--width", 16, "--height", 12, "--out",
                         tmp_path / "beyond.png", "--obj", beyond)
    if limit is None:
        assert result.returncode == 0, result.stderr
        assert_images_agree(read_image(tmp_path / "beyond.png"), reference(beyond, 16, 12))
    else:
        assert result.returncode == 4, result.stderr
