"""Chapter 11's scene files on the Python side: the reader (python_prototypes/scene_io.py)
and the gem meshes (python_prototypes/gems.py) that cornell_gems.scene places; chapter
17's words for the thin lens and textures; chapter 18's environment."""

from pathlib import Path

import numpy as np
import pytest

from python_prototypes import environment_map
from python_prototypes import gems
from python_prototypes import obj_io
from python_prototypes import pfm
from python_prototypes import scene_io
from python_prototypes import texture_images

ROOT = Path(__file__).resolve().parents[3]
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
        # of two (chapter 12's choice of light); the plates and the showcase by several;
        # chapter 18's scenes may be lit by their environment alone.
        lamps = len(scene.emitters())
        if name.startswith("cornell"):
            assert lamps == (2 if name == "cornell_two_lights" else 1), name
            # Mitsuba's Cornell box camera.
            assert scene.camera.horizontal_fov_degrees() == pytest.approx(39.3077, abs=1e-4)
        else:
            assert lamps >= 1 or scene.environment is not None, name


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
     "unknown keyword 'cylinder' (expected camera, texture, material, medium, sphere, "
     "quad, triangle, mesh, environment, object, end or instance)"),
    (VALID + "sphere 0 0 0 lamp\n", 4,
     "'sphere' needs 5 fields (CX CY CZ RADIUS MATERIAL), then optionally interior MEDIUM "
     "and name NAME; got 4"),
    (VALID + "material m albedo 1 1\n", 4, "albedo needs three numbers R G B"),
    (VALID + "material m metal\n", 4, "unknown material kind 'metal' (expected albedo, "
     "mirror, conductor, dielectric or boundary)"),
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
    (VALID + "sphere 0 0 0 1 lamp label x\n", 4, "'sphere' takes after its 5 fields only interior MEDIUM and name NAME, each once; "
     "got 'label'"),
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
    from python_prototypes import mitsuba_reference
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


# ---------------------------------------------------------------------------------------
# Chapter 17: the thin lens and textures
# ---------------------------------------------------------------------------------------

CHECKER = "texture t checker 0 0 0 1 1 1\n"
LENS = CAMERA.replace("sensor 0.036", "sensor 0.036 lens 0.01 focus 2")


def test_reads_the_lens_and_the_textures(tmp_path):
    """Images are found as meshes are: beside the scene, then in the generated assets."""
    generated = tmp_path / "generated"
    texture_images.main(["--out", str(generated / "textures")])
    (tmp_path / "m.obj").write_text("v 0 0 0\n")
    path = tmp_path / "s.scene"
    path.write_text(LENS + "texture grid image textures/uv_grid.png\n"
                    "texture data image textures/test_pattern.png linear\n"
                    "texture board checker 0.1 0.2 0.3 0.9 0.8 0.7 scale 4\n"
                    "texture plain checker 0 0 0 1 1 1\n"
                    "material lamp albedo texture board emission 1 1 1\n"
                    "material wood albedo texture grid\n"
                    "quad 0 0 0 1 0 0 0 1 0 lamp\n"
                    "mesh m.obj wood\n")
    scene = scene_io.load_scene(path, [generated])
    camera = scene.camera
    assert (camera.lens_radius, camera.focus_distance) == (0.01, 2.0)
    # thin_lens.py's camera takes the diameter.
    assert camera.as_thin_lens_camera().aperture_diameter == 0.02
    textures = scene.textures
    assert list(textures) == ["grid", "data", "board", "plain"]
    assert textures["grid"].path == generated / "textures" / "uv_grid.png"
    assert textures["grid"].written_path == "textures/uv_grid.png"
    assert not textures["grid"].linear and textures["data"].linear
    assert textures["board"].kind == "checker" and textures["board"].scale == 4
    assert textures["board"].color1 == (0.9, 0.8, 0.7) and textures["plain"].scale == 1
    assert textures["grid"].line == 2
    assert scene.materials["wood"].texture == "grid"
    assert scene.materials["lamp"].texture == "board" and scene.materials["lamp"].emits


def test_lens_zero_is_the_pinhole(tmp_path):
    path = tmp_path / "s.scene"
    path.write_text(VALID.replace("sensor 0.036", "sensor 0.036 lens 0 focus 3"))
    camera = scene_io.load_scene(path).camera
    assert (camera.lens_radius, camera.focus_distance) == (0.0, 3.0)
    path.write_text(VALID)
    assert scene_io.load_scene(path).camera.lens_radius == 0.0


TEXTURE_MISTAKES = [
    (VALID.replace("sensor 0.036", "sensor 0.036 lens 0.01"), 1,
     "unexpected 'lens' in 'camera' (after the sensor: lens RADIUS focus DISTANCE, "
     "medium MEDIUM, shutter OPEN CLOSE, each once)"),
    (VALID.replace("sensor 0.036", "sensor 0.036 lens -0.01 focus 2"), 1,
     "the lens radius '-0.01' must be 0 or more"),
    (VALID.replace("sensor 0.036", "sensor 0.036 lens 0.01 focus 0"), 1,
     "the focus distance '0' must be positive"),
    (VALID.replace("sensor 0.036", "sensor 0.036 aperture 0.01 focus 2"), 1,
     "unexpected 'aperture' in 'camera' (after the sensor: lens RADIUS focus DISTANCE, "
     "medium MEDIUM, shutter OPEN CLOSE, each once)"),
    (VALID.replace("sensor 0.036", "sensor 0.036 lens 0.01 distance 2"), 1,
     "'camera' expects 'focus' here, got 'distance'"),
    (VALID + "texture t\n", 4, "'texture' needs a name and a kind (NAME image PATH "
     "[linear], NAME checker R G B R G B [scale S])"),
    (VALID + "texture 1x checker 0 0 0 1 1 1\n", 4,
     "texture name '1x': use letters, digits, '_' and '-', starting with a letter or '_'"),
    (VALID + CHECKER + CHECKER, 5, "texture 't' is already defined on line 4"),
    (VALID + "texture t noise\n", 4, "unknown texture kind 'noise' (expected image or "
     "checker)"),
    (VALID + "texture t image a.png srgb\n", 4,
     "'texture NAME image PATH' takes only the word 'linear' after PATH"),
    (VALID + "texture t checker 0 0 0 1 1\n", 4, "checker colour needs three numbers R G B"),
    (VALID + "texture t checker 0 0 0 1 1 2\n", 4, "checker colour '2' is outside [0, 1]: "
     "a surface cannot reflect more light than reaches it"),
    (VALID + "texture t checker 0 0 0 1 1 1 scale 0\n", 4,
     "the checker's scale '0' must be positive"),
    (VALID + "texture t checker 0 0 0 1 1 1 size 2\n", 4,
     "'texture' expects 'scale' here, got 'size'"),
    (VALID + "texture t checker 0 0 0 1 1 1 scale\n", 4,
     "'texture NAME checker' needs two colours R G B R G B, then optionally scale S"),
    (VALID + "material m albedo texture\n", 4, "'albedo texture' needs the name of a texture"),
    (VALID + "material m albedo texture wood\n", 4,
     "texture 'wood' is not defined on an earlier line"),
    # A texture is defined before the material that uses it (unlike a material).
    (VALID + "material m albedo texture t\n" + CHECKER, 4,
     "texture 't' is not defined on an earlier line"),
    (VALID + CHECKER + "material m albedo texture t shiny\n", 5,
     "unexpected 'shiny' in material 'm' (albedo)"),
    (VALID + CHECKER + "sphere 0 0 0 1 m\nmaterial m albedo texture t\n", 5,
     "material 'm' is textured, and this shape has no texture coordinates: textures "
     "apply to quads and meshes"),
    (VALID + CHECKER + "material m albedo texture t\ntriangle 0 0 0 1 0 0 0 1 0 m\n", 6,
     "material 'm' is textured, and this shape has no texture coordinates: textures "
     "apply to quads and meshes"),
]


@pytest.mark.parametrize("text, line, message", TEXTURE_MISTAKES,
                         ids=[message[:40] for _, _, message in TEXTURE_MISTAKES])
def test_lens_and_texture_mistakes_name_their_line(tmp_path, text, line, message):
    path = tmp_path / "bad.scene"
    path.write_text(text)
    with pytest.raises(scene_io.SceneError) as error:
        scene_io.load_scene(path)
    assert str(error.value) == f"{path}:{line}: {message}"


def test_image_mistakes_name_the_file_and_the_line(tmp_path):
    path = tmp_path / "s.scene"
    (tmp_path / "not_an_image.png").write_text("hello\n")
    (tmp_path / "huge.png").write_bytes(  # a header only: 9000 x 2 texels
        texture_images.png_bytes(np.zeros((2, 1, 3), np.uint8))[:16]
        + (9000).to_bytes(4, "big") + (2).to_bytes(4, "big"))
    for written, message in [
            ("missing.png", f"image file 'missing.png' not found (looked for "
                            f"{tmp_path}/missing.png, {tmp_path}/generated/missing.png)"),
            ("not_an_image.png", f"image 'not_an_image.png' ({tmp_path}/not_an_image.png) "
                                 "is not a PNG or JPEG image"),
            ("huge.png", f"image 'huge.png' ({tmp_path}/huge.png) is too big: 9000 x 2 "
                         "texels: at most 8192 a side")]:
        path.write_text(VALID + f"texture t image {written}\n")
        with pytest.raises(scene_io.SceneError) as error:
            scene_io.load_scene(path, [tmp_path / "generated"])
        assert str(error.value) == f"{path}:4: {message}"


# ---------------------------------------------------------------------------------------
# Chapter 18: the environment
# ---------------------------------------------------------------------------------------

LIT_BY_SKY = CAMERA + "material white albedo 0.8 0.8 0.8\nsphere 0 0 0 1 white\n"


def write_map(path, image):
    path.parent.mkdir(parents=True, exist_ok=True)
    pfm.write_pfm(path, np.asarray(image, dtype=np.float32))
    return path


@pytest.fixture
def generated(tmp_path):
    """A generated-assets folder as the build makes it: environments/spots.pfm."""
    folder = tmp_path / "generated"
    write_map(folder / "environments" / "spots.pfm", np.full((4, 8, 3), 0.5))
    return folder


def test_reads_the_environment(tmp_path, generated):
    """Found as meshes and images are (beside the scene, then in the generated assets);
    options in any order; a scene lit by its environment alone needs no emitter."""
    path = tmp_path / "s.scene"
    path.write_text(LIT_BY_SKY + "environment environments/spots.pfm rotate_y -30 "
                    "scale 2.5  # the sky\n")
    scene = scene_io.load_scene(path, [generated])
    environment = scene.environment
    assert environment.path == generated / "environments" / "spots.pfm"
    assert environment.written_path == "environments/spots.pfm"
    assert (environment.scale, environment.rotate_y_degrees, environment.line) == \
        (2.5, -30.0, 4)
    assert not scene.emitters()
    path.write_text(VALID + "environment environments/spots.pfm\n")
    environment = scene_io.load_scene(path, [generated]).environment
    assert (environment.scale, environment.rotate_y_degrees) == (1.0, 0.0)
    path.write_text(VALID)
    assert scene_io.load_scene(path, [generated]).environment is None
    # Beside the scene first, as a mesh.
    write_map(tmp_path / "environments" / "spots.pfm", np.zeros((2, 4, 3)))
    path.write_text(VALID + "environment environments/spots.pfm\n")
    assert scene_io.load_scene(path, [generated]).environment.path == \
        tmp_path / "environments" / "spots.pfm"


def test_greyscale_and_big_endian_maps_are_read(tmp_path):
    values = np.arange(8, dtype=np.float32).reshape(2, 4)
    (tmp_path / "grey.pfm").write_bytes(b"Pf\n4 2\n-1.0\n" + values.astype("<f4").tobytes())
    (tmp_path / "big.pfm").write_bytes(b"PF\n4 2\n1.0\n"
                                       + np.repeat(values, 3).astype(">f4").tobytes())
    path = tmp_path / "s.scene"
    for name in ("grey.pfm", "big.pfm"):
        path.write_text(LIT_BY_SKY + f"environment {name}\n")
        assert scene_io.load_scene(path).environment.written_path == name


# The same mistakes as the C++ reader's, with the same messages.
ENVIRONMENT_MISTAKES = [
    (LIT_BY_SKY + "environment\n", 4,
     "'environment' needs a PATH, then optionally scale S, rotate_y DEGREES"),
    (LIT_BY_SKY + "environment environments/spots.pfm tilt 3\n", 4,
     "unknown environment option 'tilt' (expected scale or rotate_y)"),
    (LIT_BY_SKY + "environment environments/spots.pfm scale 2 rotate_y 5 scale 3\n", 4,
     "'scale' is given twice"),
    (LIT_BY_SKY + "environment environments/spots.pfm rotate_y\n", 4,
     "'rotate_y' needs 1 number"),
    (LIT_BY_SKY + "environment environments/spots.pfm scale 0\n", 4,
     "the environment's scale must be positive, got '0'"),
    (LIT_BY_SKY + "environment environments/spots.pfm scale -1\n", 4,
     "the environment's scale must be positive, got '-1'"),
    (LIT_BY_SKY + "environment environments/spots.pfm rotate_y inf\n", 4,
     "'inf' is not a finite number"),
    (LIT_BY_SKY + "environment environments/spots.pfm\n\n"
     "environment environments/spots.pfm scale 2\n", 6,
     "a second environment (the first is on line 4)"),
    # Without an environment, the message is the one scenes have always had.
    (LIT_BY_SKY, 0, "no emitter: no shape uses a material with an emission"),
]


@pytest.mark.parametrize("text, line, message", ENVIRONMENT_MISTAKES,
                         ids=[message[:40] for _, _, message in ENVIRONMENT_MISTAKES])
def test_environment_mistakes_name_their_line(tmp_path, generated, text, line, message):
    path = tmp_path / "bad.scene"
    path.write_text(text)
    with pytest.raises(scene_io.SceneError) as error:
        scene_io.load_scene(path, [generated])
    assert str(error.value) == f"{path}:{line}: {message}"


def test_missing_environment_lists_where_it_looked(tmp_path, generated):
    path = tmp_path / "s.scene"
    path.write_text(LIT_BY_SKY + "environment environments/sky.pfm\n")
    with pytest.raises(scene_io.SceneError) as error:
        scene_io.load_scene(path, [generated])
    assert str(error.value) == (
        f"{path}:4: environment file 'environments/sky.pfm' not found (looked for "
        f"{tmp_path}/environments/sky.pfm, {generated}/environments/sky.pfm)")


GOOD_HEADER = b"PF\n2 1\n-1.0\n"
NOT_PFM = ("not a PFM or OpenEXR image (it starts with neither PF, Pf nor the EXR magic "
           "number)")
BAD_HEADER = "not a PFM image (a bad width, height or scale line)"
CUT_SHORT = "not a whole PFM image (the file ends before its last row)"
# As tests/cpp/test_scene_file.cpp's EnvironmentMistakes and common/image_read.cpp.
NOT_PFMS = [
    (b"P6\n2 1\n255\n" + bytes(6), NOT_PFM),
    (b"#?RADIANCE\n", NOT_PFM),
    (b"", NOT_PFM),
    (b"PFX\n2 1\n-1.0\n" + bytes(24), NOT_PFM),
    (b"PF\n2 1\n", BAD_HEADER),
    (b"PF\n2 0\n-1.0\n", BAD_HEADER),
    (b"PF\n2.5 1\n-1.0\n" + bytes(24), BAD_HEADER),
    (b"PF\n2 1\n0\n" + bytes(24), BAD_HEADER),
    (b"PF\n2 1\nnan\n" + bytes(24), BAD_HEADER),
    (b"PF\n9000 2\n-1.0\n", "too big: 9000 x 2 texels: at most 8192 a side"),
    (b"PF\n4 4\n-1.0\n" + bytes(12), CUT_SHORT),
    (GOOD_HEADER + bytes(20), CUT_SHORT),
    (b"Pf\n2 1\n-1.0\n" + bytes(4), CUT_SHORT),
]


@pytest.mark.parametrize("data, reason", NOT_PFMS, ids=[f"{n}-{r[:20]}" for n, (_, r)
                                                        in enumerate(NOT_PFMS)])
def test_a_map_that_is_not_a_pfm_is_refused_with_the_reason(tmp_path, data, reason):
    (tmp_path / "bad.pfm").write_bytes(data)
    path = tmp_path / "s.scene"
    path.write_text(LIT_BY_SKY + "environment bad.pfm scale 2\n")
    with pytest.raises(scene_io.SceneError) as error:
        scene_io.load_scene(path)
    assert str(error.value) == f"{path}:4: environment 'bad.pfm' ({tmp_path}/bad.pfm) " \
                               f"is {reason}"


def test_an_exr_map_is_read_as_its_pfm(tmp_path):
    """Through Mitsuba's reader, R, G, B or a grey Y; a cut file is refused."""
    import mitsuba
    mitsuba.set_variant("scalar_rgb")
    colour = np.arange(24, dtype=np.float32).reshape(2, 4, 3) / 7
    mitsuba.Bitmap(colour).write(str(tmp_path / "colour.exr"))
    mitsuba.Bitmap(colour[..., :1].astype(np.float16)).write(str(tmp_path / "grey.exr"))
    path = tmp_path / "s.scene"
    for name, expected in [("colour.exr", colour),
                           ("grey.exr", np.repeat(colour[..., :1].astype(np.float16), 3, -1))]:
        path.write_text(LIT_BY_SKY + f"environment {name}\n")
        environment = scene_io.load_scene(path).environment
        assert np.array_equal(environment_map.read_map(environment.path), expected), name
    (tmp_path / "cut.exr").write_bytes((tmp_path / "colour.exr").read_bytes()[:300])
    path.write_text(LIT_BY_SKY + "environment cut.exr\n")
    with pytest.raises(scene_io.SceneError) as error:
        scene_io.load_scene(path)
    assert str(error.value).startswith(f"{path}:4: environment 'cut.exr' ({tmp_path}/cut.exr) "
                                       "is not a readable OpenEXR image (")


def test_bytes_after_the_last_row_are_ignored(tmp_path):
    """As the C++ reader: the file must hold the rows, and may hold more."""
    (tmp_path / "long.pfm").write_bytes(GOOD_HEADER + bytes(24) + b"trailer")
    path = tmp_path / "s.scene"
    path.write_text(LIT_BY_SKY + "environment long.pfm\n")
    assert scene_io.load_scene(path).environment.written_path == "long.pfm"


@pytest.mark.parametrize("value, what", [(np.nan, "nan"), (np.inf, "inf"),
                                         (-np.inf, "inf"), (-0.5, "negative")])
def test_bad_texels_are_refused_counting_rows_from_the_top(tmp_path, value, what):
    """The file stores the bottom row first: row 1 of 4 from the top is the file's
    third row. Earlier texels are fine, later ones bad too: the first is named."""
    image = np.ones((4, 6, 3), dtype=np.float32)
    image[1, 4, 2] = value
    image[2, 0, 0] = -1.0  # later, reading from the top
    image[3, :, 1] = np.nan
    write_map(tmp_path / "bad.pfm", image)
    path = tmp_path / "s.scene"
    path.write_text(LIT_BY_SKY + "environment bad.pfm\n")
    with pytest.raises(scene_io.SceneError) as error:
        scene_io.load_scene(path)
    assert str(error.value) == (f"{path}:4: environment 'bad.pfm': texel (row 1, column "
                                f"4) is {what}: a radiance map holds finite values >= 0")


def test_negative_zero_is_a_radiance_of_zero(tmp_path):
    write_map(tmp_path / "zero.pfm", np.full((2, 4, 3), -0.0))
    path = tmp_path / "s.scene"
    path.write_text(LIT_BY_SKY + "environment zero.pfm\n")
    assert scene_io.load_scene(path).environment is not None



# ---------------------------------------------------------------------------------------
# Objects and instances (the instances chapter), as tests/cpp/test_scene_file.cpp reads them
# ---------------------------------------------------------------------------------------

OBJECTS = ("material white albedo 0.8 0.8 0.8\n"
           "object pot begin\n"
           "  sphere 0 0.5 0 0.5 white name lid\n"
           "  quad 0 0 0 1 0 0 0 0 1 white\n"
           "  triangle 0 0 0 1 0 0 0 1 0 white\n"
           "end\n"
           "instance pot\n"
           "instance pot scale 2 rotate_y 30 translate 1 0 -2 name big\n"
           "instance pot scale -1 1 0.5 rotate 1 1 0 45 translate 0 1 0 moving 0.5 0 0\n")


def test_reads_objects_and_instances(tmp_path):
    path = tmp_path / "objects.scene"
    path.write_text(CAMERA.replace("\n", " shutter 0 0.5\n") + VALID[len(CAMERA):] + OBJECTS)
    scene = scene_io.load_scene(path)
    assert len(scene.spheres) == 1  # the lamp: the object's shapes are its own
    pot = scene.objects["pot"]
    assert pot.line == 5 and pot.spheres[0].name == "lid"
    assert len(pot.quads) == len(pot.triangles) == 1
    assert [i.name for i in scene.instances] == ["", "big", ""]
    assert scene.instances[2].motion == (0.5, 0.0, 0.0)
    assert (scene.camera.shutter_open, scene.camera.shutter_close) == (0.0, 0.5)
    point = np.array([1.0, 0.0, 0.0, 1.0])
    assert np.allclose(scene.instances[0].world_from_object(), np.eye(4))
    # scale 2, a quarter of a right-handed turn less 60 degrees about y, then a move
    turned = scene.instances[1].world_from_object() @ point
    angle = np.radians(30)
    assert np.allclose(turned[:3], [1 + 2 * np.cos(angle), 0, -2 - 2 * np.sin(angle)])
    mirrored = scene.instances[2].world_from_object()
    assert np.linalg.det(mirrored[:3, :3]) == pytest.approx(-0.5)


OBJECT_MISTAKES = [
    ("instance nothing", 5, "object 'nothing' is not defined"),
    ("object o begin\nend", 5, "object 'o' is empty: put shapes between its begin and end"),
    ("object o begin\nsphere 0 0 0 1 w\ninstance o\nend", 7, "object 'o' is used inside itself"),
    ("object o begin\nsphere 0 0 0 1 w\nend\nobject p begin\ninstance o\nend", 9,
     "'instance' inside object 'p' (line 8): objects hold shapes, not objects or instances; "
     "'end' it first"),
    ("object o begin\nobject p begin", 6, "'object' inside object 'o' (line 5): objects hold "
     "shapes, not objects or instances; 'end' it first"),
    ("object o begin\nmaterial x albedo 1 1 1", 6, "'material' inside object 'o' (line 5): "
     "only sphere, quad, triangle and mesh statements stand between its begin and end"),
    ("end", 5, "'end' without an 'object NAME begin' before it"),
    ("object o begin\nsphere 0 0 0 1 w", 5, "object 'o' has no 'end'"),
    ("object o", 5, "'object' needs a name and the word begin: object NAME begin"),
    ("object 9 begin", 5, "object name '9': use letters, digits, '_' and '-', starting with "
     "a letter or '_'"),
    ("object o begin\nsphere 0 0 0 1 w\nend\nobject o begin", 8,
     "object 'o' is already defined on line 5"),
    ("object o begin\nsphere 0 0 0 1 lamp\nend", 6, "object 'o': material 'lamp' emits, and "
     "an object's shapes may not (a light is placed as it is, not through instances)"),
    ("instance o scale 0", 5, "scale by 0 squashes the object flat"),
    ("instance o scale 1 0 1", 5, "scale by 0 squashes the object flat"),
    ("instance o scale 1e-10 translate 1 1 1", 5, "the placement squashes the object flat or "
     "blows it up (the determinant of its matrix is 1e-30)"),
    ("instance o scale 1 2", 5, "'scale' needs 1 number (S) or 3 (X Y Z), got 2 numbers"),
    ("instance o rotate 0 0 0 30", 5, "rotate needs an axis that is not 0 0 0"),
    ("instance o rotate 0 1 0", 5, "'rotate' needs 4 numbers (axis X Y Z, DEGREES), got 3 "
     "numbers"),
    ("instance o translate 1 2", 5, "'translate' needs 3 numbers (X Y Z), got 2 numbers"),
    ("instance o rotate_y", 5, "'rotate_y' needs 1 number (DEGREES), got 0 numbers"),
    ("instance o spin 3", 5, "unexpected 'spin' in 'instance' (expected scale, rotate, "
     "rotate_y, translate, and moving X Y Z and name NAME once each)"),
    ("instance o moving 1 0 0 moving 1 0 0", 5, "unexpected 'moving' in 'instance' (expected "
     "scale, rotate, rotate_y, translate, and moving X Y Z and name NAME once each)"),
    ("instance o translate 1 x 3", 5, "'translate' needs 3 numbers (X Y Z), got 1 number"),
    ("instance", 5, "'instance' needs the name of an object, then its placement"),
    ("medium m homogeneous sigma_a 1 1 1 sigma_s 0 0 0\nmaterial e boundary\nobject o begin\n"
     "sphere 0 0 0 1 e interior m\nend", 8,
     "object 'o': an object's shapes hold no medium (interior)"),
]


@pytest.mark.parametrize("lines, line, message", OBJECT_MISTAKES,
                         ids=[message[:40] for _, _, message in OBJECT_MISTAKES])
def test_object_mistakes_are_the_cpp_readers(tmp_path, lines, line, message):
    path = tmp_path / "bad.scene"
    path.write_text(VALID + "material w albedo 1 1 1\n" + lines + "\n")
    with pytest.raises(scene_io.SceneError) as error:
        scene_io.load_scene(path)
    assert str(error.value) == f"{path}:{line}: {message}"


@pytest.mark.parametrize("shutter, message", [
    ("shutter 1 0.5", "the camera's shutter '1' '0.5' must open at 0 or later and close no "
                      "earlier than it opens"),
    ("shutter 1", "the camera's shutter needs two numbers, OPEN CLOSE (seconds), once")])
def test_shutter_mistakes_are_the_cpp_readers(tmp_path, shutter, message):
    path = tmp_path / "bad.scene"
    path.write_text(CAMERA.replace("\n", f" {shutter}\n") + VALID[len(CAMERA):])
    with pytest.raises(scene_io.SceneError) as error:
        scene_io.load_scene(path)
    assert str(error.value) == f"{path}:1: {message}"
