"""Chapter 26: instances, checked against the same triangles written out in the world and
against Mitsuba 3's shape groups and instances (book/docs/maintainers.md).

- Written out: a scene of instances (rotated, scaled evenly and unevenly, mirrored) and
  the same scene with each instance's triangles placed in the world by numpy (normals
  by the inverse transpose, a mirrored instance's corners swapped) draw the same
  picture: one ray through each pixel's centre sees the same distance (within float
  rounding: 1e-4 of it), the same normal (2e-3) and the same albedo; the path traced
  light agrees block by block within the noise.
- Mitsuba 3 (`shapegroup` and `instance`), region by region within 2%, on the chapter's
  scene: six instances of a teapot and a ball, an ellipsoid and a mirrored teapot among
  them.
- Planted bugs, each failing the check that catches it: normals turned by the placement
  itself instead of its inverse transpose, the ray's direction normalised in object
  space (t then counts object units), the object's boxes tested with the world's ray.
- Memory: a hundred instances of the teapot keep its triangles once.
- Bad input: the scene reader's mistakes are exit code 3 at their line; chapter 18
  refuses instances and names this chapter; --brute-force refuses instances.

The limits and why: tests/python/path_checks.py."""

from __future__ import annotations

import numpy as np
import path_checks
import pytest
from conftest import ROOT, run_chapter
from path_checks import SIGMAS, mean_and_error

from course_tools.program_output import last_json_line
from python_prototypes import obj_io, scene_io, teapot

SCENES = ROOT / "assets" / "scenes"
MESH_FOLDERS = [ROOT / "build" / "assets"]
TEAPOT = ROOT / "build" / "assets" / "meshes" / "teapot_6320.obj"

# The planted bugs: (file, the right text, the wrong one). Each must fail its check.
NORMAL_BY_THE_PLACEMENT = (  # world-from-object itself, the inverse of M
    "instances.glsl", "    return normalize(transposeOfM(placed) * normal);\n",
    "    return normalize(inverse(transpose(transposeOfM(placed))) * normal);\n")
T_IN_OBJECT_UNITS = (
    "instances.glsl",
    "    return Ray(ray.origin * transposed + offset, ray.direction * transposed);\n",
    "    return Ray(ray.origin * transposed + offset, normalize(ray.direction * transposed));\n")
BOXES_WITH_THE_WORLDS_RAY = (
    "bvh_traversal.glsl",
    "            ray = rayToObject(worldRay, placed);\n            boxRay = bvhRay(ray);\n",
    "            ray = rayToObject(worldRay, placed);\n")

ROOM = (SCENES / "cornell_instances.scene").read_text().split("object pot begin")[0]
POTS = [  # (placement, name): every kind of map the chapter's scenes use
    ("scale 0.12 rotate_y -30 translate -0.45 -1 0.35", "small_pot"),
    ("scale -0.16 0.16 0.16 rotate_y 25 translate 0.42 -1 0.3", "mirrored_pot"),
    ("scale 0.22 0.1 0.16 rotate_y 60 translate -0.05 -1 -0.45", "squashed_pot"),
    ("scale 0.09 rotate 1 0 1 -40 translate 0.45 0.1 -0.5", "tilted_pot"),
]
SIZE = 48


def instanced_scene(folder):
    """The room with the four teapots as instances of one object."""
    path = folder / "instanced.scene"
    path.write_text(ROOM + f"object pot begin\n  mesh {TEAPOT} teapot\nend\n"
                    + "".join(f"instance pot {steps} name {name}\n" for steps, name in POTS))
    return path


def written_out_scene(folder):
    """The same room with each teapot's triangles placed in the world here, in numpy:
    positions by the placement, normals by its inverse transpose, and a mirrored one's
    corners swapped, so that its fronts stay in front."""
    positions, normals, triangles, _ = obj_io.read_obj(TEAPOT)
    lines = []
    for steps, name in POTS:
        world = scene_io.read_instance(["pot", *steps.split()]).world_from_object()
        linear = world[:3, :3]
        placed = positions @ linear.T + world[:3, 3]
        turned = normals @ np.linalg.inv(linear)  # n^T A^-1 = (A^-T n)^T
        turned /= np.linalg.norm(turned, axis=1, keepdims=True)
        corners = triangles[:, [0, 2, 1]] if np.linalg.det(linear) < 0 else triangles
        teapot.write_obj(folder / f"{name}.obj", placed, turned, corners)
        lines.append(f"mesh {name}.obj teapot name {name}\n")
    path = folder / "written_out.scene"
    path.write_text(ROOM + "".join(lines))
    return path


def render(tmp_path, scene, name, *args, shader_dir=None):
    extra = ["--shader-dir", shader_dir] if shader_dir else []
    return path_checks.path_trace("26", tmp_path, name, "--scene", scene, "--width", SIZE,
                                  "--height", SIZE, *extra, *args)


def views(tmp_path, scene, label, shader_dir=None):
    return {view: render(tmp_path, scene, f"{label}_{view}", "--view", view, "--spp", 1,
                         shader_dir=shader_dir)
            for view in ("distance", "normals", "albedo")}


def assert_same_views(ours, written):
    """The same distance (1e-4 of it: float rounding of the placed corners), the same
    normal (2e-3 in the view's 0.5 + 0.5 n) and albedo, at every pixel but the few
    where a silhouette's rounding lets one ray through and not the other."""
    hit = written["distance"][..., 0] > 0
    agree = np.isclose(ours["distance"][..., 0], written["distance"][..., 0], rtol=1e-4)
    agree &= np.all(np.abs(ours["normals"] - written["normals"]) < 2e-3, axis=-1)
    agree &= np.all(np.abs(ours["albedo"] - written["albedo"]) < 1e-6, axis=-1)
    assert hit.sum() > 0.9 * SIZE * SIZE
    assert np.sum(~agree) <= 4, np.argwhere(~agree)[:8]


@pytest.fixture
def scenes(tmp_path):
    return instanced_scene(tmp_path), written_out_scene(tmp_path)


@pytest.mark.windows
def test_instances_see_what_their_triangles_written_out_see(tmp_path, scenes):
    instanced, written = scenes
    assert_same_views(views(tmp_path, instanced, "instanced"),
                      views(tmp_path, written, "written"))


def test_instances_light_the_room_as_their_triangles_written_out(tmp_path, scenes):
    """The path traced pictures agree in every 8 x 8 block, within the noise."""
    instanced, written = scenes
    a = render(tmp_path, instanced, "instanced", "--spp", 256)
    b = render(tmp_path, written, "written", "--spp", 256, "--seed", 7)
    blocks = (a - b).reshape(SIZE // 8, 8, SIZE // 8, 8, 3).transpose(0, 2, 1, 3, 4)
    for block in blocks.reshape(-1, 64, 3):
        mean, error = mean_and_error(block)
        assert np.all(np.abs(mean) < SIGMAS * error + 1e-3), (mean, error)


@pytest.mark.parametrize("bug", [NORMAL_BY_THE_PLACEMENT, T_IN_OBJECT_UNITS,
                                 BOXES_WITH_THE_WORLDS_RAY],
                         ids=["normal_by_the_placement", "t_in_object_units",
                              "boxes_with_the_worlds_ray"])
def test_planted_bug_fails_the_written_out_comparison(tmp_path, scenes, bug):
    instanced, written = scenes
    shader_dir = path_checks.shaders_with_bug("26", tmp_path, bug)
    with pytest.raises(AssertionError):
        assert_same_views(views(tmp_path, instanced, "instanced", shader_dir),
                          views(tmp_path, written, "written"))


# --- Mitsuba 3's shape groups and instances ------------------------------------------------

def test_instances_agree_with_mitsuba(tmp_path):
    scene_file = SCENES / "cornell_instances.scene"
    reference = path_checks.mitsuba_regions(scene_file, 1024, 64, MESH_FOLDERS)
    ours = path_checks.path_trace("26", tmp_path, "cornell_instances", "--scene", scene_file,
                                  "--width", 64, "--height", 64, "--spp", 512)
    compared = path_checks.assert_regions_within_two_percent(ours, reference, MESH_FOLDERS)
    assert {"small_pot", "mirrored_pot", "tall_ball", "back", "floor"} <= set(compared), \
        compared


# --- Memory ---------------------------------------------------------------------------------

def test_a_hundred_teapots_keep_one_teapots_triangles(tmp_path):
    """The instances' memory for a hundred teapots: the teapot's triangles and tree once,
    and a few words an instance (64 bytes, and about two tree nodes)."""
    def stats(count):
        scene = tmp_path / f"pots_{count}.scene"
        scene.write_text(ROOM + f"object pot begin\n  mesh {TEAPOT} teapot\nend\n" + "".join(
            f"instance pot scale 0.03 translate {-0.9 + 0.18 * (k % 10):.2f} -1 "
            f"{-0.9 + 0.18 * (k // 10):.2f}\n" for k in range(count)))
        result = run_chapter("26", "--headless", "--scene", scene, "--width", 8,
                             "--height", 8, "--spp", 1, "--json")
        assert result.returncode == 0, result.stderr
        return last_json_line(result.stdout)
    one, hundred = stats(1), stats(100)
    assert hundred["object_triangles"] == one["object_triangles"] == 6320
    assert hundred["placed_triangles"] == 100 * 6320
    assert hundred["instance_bytes"] - one["instance_bytes"] < 99 * (64 + 2 * 64)
    assert hundred["instance_bytes"] < 1.1 * one["instance_bytes"]


# --- Bad input ------------------------------------------------------------------------------

def test_a_scene_mistake_is_exit_3_at_its_line(tmp_path):
    scene = tmp_path / "bad.scene"
    scene.write_text(ROOM + "object pot begin\nend\n")
    result = run_chapter("26", "--headless", "--scene", scene, "--out", tmp_path / "x.png")
    assert result.returncode == 3
    line = ROOM.count("\n") + 1
    assert f"{scene}:{line}: object 'pot' is empty" in result.stderr
    assert not (tmp_path / "x.png").exists()


def test_chapter_18_refuses_instances_and_names_this_chapter(tmp_path):
    scene = SCENES / "cornell_instances.scene"
    result = run_chapter("18", "--headless", "--scene", scene, "--out", tmp_path / "x.png")
    assert result.returncode == 3
    line = next(n for n, text in enumerate(scene.read_text().splitlines(), start=1)
                if text.startswith("object"))
    assert (f"{scene}:{line}: this program draws no objects or instances (object ... end, "
            "instance); instances come in chapter 26") in result.stderr


def test_moving_instances_are_refused_here(tmp_path):
    scene = tmp_path / "moving.scene"
    scene.write_text(ROOM + f"object pot begin\n  mesh {TEAPOT} teapot\nend\n"
                     "instance pot scale 0.1 moving 0.2 0 0\n")
    result = run_chapter("26", "--headless", "--scene", scene, "--out", tmp_path / "x.png")
    assert result.returncode == 3
    assert "this program renders nothing that moves (moving X Y Z)" in result.stderr


def test_brute_force_refuses_instances(tmp_path):
    result = run_chapter("26", "--headless", "--brute-force", "--out", tmp_path / "x.png")
    assert result.returncode == 2
    assert "instances are found through the trees only" in result.stderr
