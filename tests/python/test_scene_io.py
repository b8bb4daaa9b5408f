"""Chapter 11's scene files on the Python side: the reader (python_prototypes/scene_io.py)
and the gem meshes (python_prototypes/gems.py) that cornell_gems.scene places."""

from pathlib import Path

import numpy as np
import pytest

import gems
import obj_io
import scene_io

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "assets" / "scenes"
CAMERA = "camera eye 0 1 4 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.036\n"
VALID = CAMERA + "material lamp albedo 0.5 0.5 0.5 emission 1 2 3\nsphere 0 3 0 0.5 lamp\n"


@pytest.fixture(scope="module")
def mesh_folder(tmp_path_factory):
    """The generated assets as the build makes them: meshes/gem_<cut>.obj."""
    folder = tmp_path_factory.mktemp("generated")
    gems.main(["--out", str(folder / "meshes")])
    return folder


# ---------------------------------------------------------------------------------------
# The reader
# ---------------------------------------------------------------------------------------

def test_shipped_scenes_load(mesh_folder):
    names = sorted(path.stem for path in SCENES.glob("*.scene"))
    assert {"cornell_spheres", "cornell_gems", "cornell_box"} <= set(names)
    # The teapots (chapter 13's scenes) come from the build (cmake/Assets.cmake).
    built = ROOT / "build" / "assets"
    for name in names:
        scene = scene_io.load_scene(SCENES / f"{name}.scene", [mesh_folder, built])
        # Every scene is lit: the Cornell rooms by their one lamp, but the grader's room
        # of two (chapter 12's choice of light); the plates and the showcase by several.
        lamps = len(scene.emitters())
        if name.startswith("cornell"):
            assert lamps == (2 if name == "cornell_two_lights" else 1), name
            # Mitsuba's Cornell box camera.
            assert scene.camera.horizontal_fov_degrees() == pytest.approx(39.3077, abs=1e-4)
        else:
            assert lamps >= 1, name


def test_gems_scene_places_every_cut_inside_the_room(mesh_folder):
    scene = scene_io.load_scene(SCENES / "cornell_gems.scene", [mesh_folder])
    assert {Path(mesh.path).name for mesh in scene.meshes} == \
        {f"gem_{cut}.obj" for cut in gems.CUTS}
    footprints = []
    for mesh in scene.meshes:
        positions = obj_io.read_obj(mesh.path)[0]
        matrix = mesh.world_from_mesh()
        world = positions @ matrix[:3, :3].T + matrix[:3, 3]
        assert world[:, 1].min() == pytest.approx(-1.0, abs=1e-9), mesh.name  # on the floor
        assert np.abs(world[:, [0, 2]]).max() < 0.9, mesh.name  # clear of the walls
        assert world[:, 1].max() < 0, mesh.name
        footprints.append((world[:, [0, 2]].mean(axis=0),
                           np.linalg.norm(world[:, [0, 2]] - world[:, [0, 2]].mean(axis=0),
                                          axis=1).max()))
    for i, (center_a, radius_a) in enumerate(footprints):
        for center_b, radius_b in footprints[i + 1:]:
            assert np.linalg.norm(center_a - center_b) > radius_a + radius_b


def test_cornell_spheres_rest_on_the_floor():
    scene = scene_io.load_scene(SCENES / "cornell_spheres.scene")
    for sphere in scene.spheres:
        assert sphere.center[1] - sphere.radius == pytest.approx(-1.0)
        assert all(abs(c) + sphere.radius < 1 for c in (sphere.center[0], sphere.center[2]))


def test_reads_every_statement(tmp_path):
    (tmp_path / "m.obj").write_text("v 0 0 0\n")
    path = tmp_path / "s.scene"
    path.write_text(CAMERA + "material lamp albedo 0.1 0.2 0.3 emission 1 2 3\n"
                    "sphere 1 2 3 0.5 lamp name sun  # comment\n"
                    "quad 0 0 0 1 0 0 0 1 0 white\n"
                    "triangle 0 0 0 1 0 0 0 1 0 white name t\n"
                    "mesh m.obj white rotate_y 90 scale 2 translate 1 0 0\n"
                    "material white albedo 1 1 1\n")
    scene = scene_io.load_scene(path)
    assert scene.materials["lamp"].emission == (1, 2, 3)
    assert scene.spheres[0].name == "sun" and scene.spheres[0].radius == 0.5
    assert scene.quads[0].material == "white" and scene.triangles[0].name == "t"
    mesh = scene.meshes[0]
    assert mesh.path == tmp_path / "m.obj" and mesh.line == 6
    # Scale, then turn (counter-clockwise from above: +x to -z), then move.
    np.testing.assert_allclose(mesh.world_from_mesh() @ [1, 1, 0, 1], [1, 2, -2, 1],
                               atol=1e-12)
    assert [scene.region_name(*entry) for entry in scene.shapes()] == \
        ["sun", "quad_0", "t", "mesh_0"]


# The same mistakes as tests/cpp/test_scene_file.cpp, with the same messages.
MISTAKES = [
    ("", 0, "empty file"),
    (VALID + "cylinder 0 0 0 1 lamp\n", 4,
     "unknown keyword 'cylinder' (expected camera, material, sphere, quad, triangle or mesh)"),
    (VALID + "sphere 0 0 0 lamp\n", 4,
     "'sphere' needs 5 fields (CX CY CZ RADIUS MATERIAL), then optionally name NAME; got 4"),
    (VALID + "material m albedo 1 1\n", 4, "albedo needs three numbers R G B"),
    (VALID + "material m metal\n", 4, "unknown material kind 'metal' (expected albedo, "
     "mirror, conductor or dielectric)"),
    (VALID + "material m conductor eta 1 1 1 k 1 1 1 roughness -0.1\n", 4,
     "roughness '-0.1' is negative"),
    (VALID + "material m dielectric ior 0\n", 4, "ior '0' must be above 0"),
    (VALID + "material m mirror emission 1 1 1\n", 4,
     "only an 'albedo' material may have an emission, not material 'm' (mirror)"),
    (VALID + "material m dielectric ior 1.5 shiny\n", 4,
     "unexpected 'shiny' in material 'm' (dielectric)"),
    (VALID + "material m mirror reflectance 2 1 1\n", 4,
     "reflectance '2' is outside [0, 1]: a surface cannot reflect more light than reaches it"),
    ("camera eye 0 0 0 at 0 0 -1 up 0 1 0 focal 1 sensor 1\n", 1,
     "'camera' expects 'look' here, got 'at'"),
    (VALID + "sphere 0 0 zero 1 lamp\n", 4, "'zero' is not a number"),
    (VALID + "sphere 0 0 0 nan lamp\n", 4, "'nan' is not a finite number"),
    (VALID + "sphere -INF 0 0 1 lamp\n", 4, "'-INF' is not a finite number"),
    (VALID + "sphere 1e39 0 0 1 lamp\n", 4, "'1e39' is too large for a float"),
    (VALID + "\n# comment\nsphere 0 0 0 1 gold\n", 6, "material 'gold' is not defined"),
    (VALID + "material lamp albedo 1 1 1\n", 4, "material 'lamp' is already defined on line 2"),
    (VALID + "material m albedo 1.2 0 0\n", 4,
     "albedo '1.2' is outside [0, 1]: a surface cannot reflect more light than reaches it"),
    (VALID + "sphere 0 0 0 -1 lamp\n", 4, "the sphere's radius must be positive, got '-1'"),
    (VALID + "quad 0 0 0 1 0 0 2 0 0 lamp\n", 4,
     "the quad has zero area: an edge is zero or the two edges are parallel"),
    (VALID + "triangle 0 0 0 1 1 1 2 2 2 lamp\n", 4,
     "the triangle has zero area: its corners are on one line"),
    (VALID + CAMERA, 4, "a second camera (the first is on line 1)"),
    ("camera eye 0 0 0 look 0 2 0 up 0 1 0 focal 1 sensor 1\n", 1,
     "the camera's up must not be parallel to its look direction"),
    ("# only a comment\n", 0, "no camera: a scene needs one 'camera' line"),
    (CAMERA + "material white albedo 1 1 1\nsphere 0 0 0 1 white\n", 0,
     "no emitter: no shape uses a material with an emission"),
    (VALID + "sphere 0 0 0 1 lamp\0\n", 4,
     "binary data (a control byte) in what should be a text file"),
    (VALID + "sphere 0 0 0 1 lamp label x\n", 4, "'sphere' expects 'name' here, got 'label'"),
    (VALID + "mesh\n", 4, "'mesh' needs a PATH and a MATERIAL, then optionally scale S, "
                          "rotate_y DEGREES, translate X Y Z, name NAME"),
]


@pytest.mark.parametrize("text, line, message", MISTAKES,
                         ids=[message[:40] for _, _, message in MISTAKES])
def test_mistakes_name_file_line_and_problem(tmp_path, text, line, message):
    path = tmp_path / "bad.scene"
    path.write_text(text)
    with pytest.raises(scene_io.SceneError) as error:
        scene_io.load_scene(path)
    assert str(error.value) == f"{path}:{line}: {message}"


def test_missing_mesh_lists_where_it_looked(tmp_path):
    path = tmp_path / "s.scene"
    path.write_text(VALID + "mesh meshes/x.obj lamp\n")
    with pytest.raises(scene_io.SceneError) as error:
        scene_io.load_scene(path, [tmp_path / "generated" / ".."])
    assert str(error.value) == (
        f"{path}:4: mesh file 'meshes/x.obj' not found (looked for "
        f"{tmp_path}/meshes/x.obj, {tmp_path}/meshes/x.obj)")


# ---------------------------------------------------------------------------------------
# The gems
# ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("cut", gems.CUTS)
def test_gems_are_closed_convex_flat_and_wound_outwards(cut):
    vertices, faces = gems.make_gem(cut)
    gems.check_gem(vertices, faces)  # raises if not
    assert len(gems.triangles(faces)) < 200
    assert vertices[:, 1].min() == 0.0  # stands on y = 0
    assert np.abs(vertices[:, 0]).max() == pytest.approx(1.0)  # 1 from the y axis along x


def test_gem_check_catches_a_flipped_face():
    vertices, faces = gems.make_gem("octahedron")
    faces[3] = faces[3][::-1]
    with pytest.raises(ValueError, match="same direction"):
        gems.check_gem(vertices, faces)


@pytest.mark.parametrize("cut", gems.CUTS)
def test_written_gems_read_back_with_one_normal_per_facet(mesh_folder, cut):
    path = mesh_folder / "meshes" / f"gem_{cut}.obj"
    positions, normals, triangles, triangle_normals = obj_io.read_obj(path)
    vertices, faces = gems.make_gem(cut)
    assert len(triangles) == len(gems.triangles(faces))
    # Each triangle's three corners share its facet's normal, which is its own
    # geometric normal: flat shading under any normal interpolation.
    corners = positions[triangles]
    geometric = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    geometric /= np.linalg.norm(geometric, axis=1, keepdims=True)
    for k in range(3):
        np.testing.assert_allclose(normals[triangle_normals[:, k]], geometric, atol=1e-6)
    assert not list(path.parent.glob("*.partial"))


def test_material_kinds_and_their_mitsuba_words(tmp_path):
    """The four kinds of material, read as the C++ reader reads them, and each in
    Mitsuba 3's words; Mitsuba loads every one."""
    import mitsuba_reference
    path = tmp_path / "kinds.scene"
    path.write_text(VALID + "material m mirror\n"
                    "material r mirror reflectance 0.9 0.8 0.7\n"
                    "material gold conductor eta 0.2 0.4 1.4 k 3.6 2.4 1.8\n"
                    "material brushed conductor eta 0.2 0.4 1.4 k 3.6 2.4 1.8 roughness 0.2\n"
                    "material glass dielectric ior 1.5\n"
                    "material frosted dielectric ior 1.33 roughness 0.1\n")
    materials = scene_io.load_scene(path).materials
    assert materials["m"].kind == "mirror" and materials["m"].reflectance == (1.0, 1.0, 1.0)
    assert materials["r"].reflectance == pytest.approx((0.9, 0.8, 0.7))
    assert materials["gold"].k == pytest.approx((3.6, 2.4, 1.8))
    assert materials["brushed"].roughness == pytest.approx(0.2)
    assert materials["frosted"].ior == pytest.approx(1.33)
    words = {name: mitsuba_reference.mitsuba_bsdf(m) for name, m in materials.items()}
    assert words["m"] == {"type": "conductor", "material": "none", "specular_reflectance":
                          {"type": "rgb", "value": [1.0, 1.0, 1.0]}}
    assert words["gold"]["type"] == "conductor" and words["brushed"]["type"] == "roughconductor"
    assert words["brushed"]["distribution"] == "ggx" and words["brushed"]["sample_visible"]
    assert words["glass"] == {"type": "dielectric", "int_ior": pytest.approx(1.5),
                              "ext_ior": 1.0}
    assert words["frosted"]["type"] == "roughdielectric"
    pytest.importorskip("mitsuba")
    mi = mitsuba_reference.import_mitsuba("scalar_rgb")
    for name, bsdf in words.items():
        assert mi.load_dict(bsdf) is not None, name
