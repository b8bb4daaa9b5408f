"""Chapter 17's textures on the Python side: textures.py's lookup (the numpy reference
the GPU is compared with), the images texture_images.py draws, the teapot's vt, and
that Mitsuba 3 looks textures up exactly as textures.py does once mitsuba_reference.py
has mapped the scene: same (u, v) on a quad and on a mesh, same texel, same sRGB
decoding and bilinear weights, same repeat and checker, and the scene's thin lens."""

from pathlib import Path

import numpy as np
import pytest

from python_prototypes import obj_io
from python_prototypes import scene_io
from python_prototypes import teapot
from python_prototypes import texture_images
from python_prototypes import textures
from python_prototypes import thin_lens

W, H = 24, 16  # the probe image: pixel centres fall between texel centres
CAMERA = "camera eye 0 0 1 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.036"
LAMP = "material lamp albedo 1 1 1 emission 1 1 1\nsphere 0 0 3 0.1 lamp\n"  # behind the eye
# A square of side 1.3 turned 30 degrees in the plane z = 0, centred on the view, its
# front (edge1 x edge2 = +z) towards the camera; every pixel sees it.
ANGLE = np.radians(30)
EDGE1 = 1.3 * np.array([np.cos(ANGLE), np.sin(ANGLE), 0.0])
EDGE2 = 1.3 * np.array([-np.sin(ANGLE), np.cos(ANGLE), 0.0])
ORIGIN = -(EDGE1 + EDGE2) / 2


def mesh_vt(a, b):
    """The OBJ quad's vt at quad coordinates (a, b): affine, so both triangles
    interpolate it exactly, and beyond [0, 1] so the image repeats."""
    return 2.0 * a - 0.25, 1.5 * b + 0.1


@pytest.fixture(scope="module")
def images(tmp_path_factory):
    folder = tmp_path_factory.mktemp("assets")
    texture_images.main(["--out", str(folder / "textures")])
    return folder


@pytest.fixture(scope="module")
def pattern(images):
    return textures.read_image(images / "textures" / "test_pattern.png")


# ---------------------------------------------------------------------------------------
# textures.py
# ---------------------------------------------------------------------------------------

def test_srgb_decoding_is_the_standard_curve():
    assert textures.srgb_to_linear(0.0) == 0.0 and textures.srgb_to_linear(1.0) == 1.0
    assert textures.srgb_to_linear(0.5) == pytest.approx(0.214041, abs=1e-6)
    assert textures.srgb_to_linear(10 / 255) == pytest.approx(10 / 255 / 12.92)  # straight
    assert textures.srgb_to_linear(11 / 255) == pytest.approx(((11 / 255 + 0.055) / 1.055)
                                                              ** 2.4)
    # The two pieces meet at 0.04045 (to 1e-7: the standard's rounded constants).
    assert textures.srgb_to_linear(0.04045) == pytest.approx(
        ((0.04045 + 0.055) / 1.055) ** 2.4, abs=1e-7)
    values = np.arange(256) / 255
    assert np.all(np.diff(textures.srgb_to_linear(values)) > 0)


def test_images_read_top_row_first_decoded_unless_linear(images, pattern):
    rows, columns = np.meshgrid(np.arange(4), np.arange(8), indexing="ij")
    encoded = texture_images.pattern_texel(rows, columns) / 255
    assert pattern.shape == (4, 8, 3)
    np.testing.assert_array_equal(pattern, textures.srgb_to_linear(encoded))
    linear = textures.read_image(images / "textures" / "test_pattern.png", linear=True)
    np.testing.assert_array_equal(linear, encoded)
    assert len({tuple(t) for t in encoded.reshape(-1, 3)}) == 32  # every texel differs


def test_grey_images_repeat_into_rgb_and_alpha_is_ignored(tmp_path):
    from PIL import Image
    grey = np.array([[0, 128], [200, 255]], dtype=np.uint8)
    Image.fromarray(grey, "L").save(tmp_path / "grey.png")
    Image.fromarray(np.dstack([grey] * 3 + [np.zeros_like(grey)]), "RGBA").save(
        tmp_path / "clear.png")
    for name in ("grey.png", "clear.png"):
        image = textures.read_image(tmp_path / name)
        np.testing.assert_array_equal(image, textures.srgb_to_linear(
            np.dstack([grey] * 3) / 255), err_msg=name)


def test_bilinear_returns_texels_at_centres_and_means_between(pattern):
    rows, columns = np.meshgrid(np.arange(4), np.arange(8), indexing="ij")
    u, v = (columns + 0.5) / 8, 1 - (rows + 0.5) / 4  # texel centres, v up
    np.testing.assert_array_equal(textures.bilinear_repeat(pattern, u, v), pattern)
    # vt (0, 0)'s nearest texel is the bottom-left one.
    np.testing.assert_array_equal(textures.bilinear_repeat(pattern, 0.5 / 8, 0.5 / 4),
                                  pattern[3, 0])
    # Midway between two, and four, texel centres.
    np.testing.assert_allclose(textures.bilinear_repeat(pattern, 2 / 8, 1 - 1.5 / 4),
                               (pattern[1, 1] + pattern[1, 2]) / 2, rtol=1e-12)
    np.testing.assert_allclose(textures.bilinear_repeat(pattern, 3 / 8, 1 - 2 / 4),
                               pattern[1:3, 2:4].mean(axis=(0, 1)), rtol=1e-12)
    # A quarter of the way: weights 3/4 and 1/4.
    np.testing.assert_allclose(textures.bilinear_repeat(pattern, 2.75 / 8, 1 - 0.5 / 4),
                               0.75 * pattern[0, 2] + 0.25 * pattern[0, 3], rtol=1e-12)


def test_bilinear_repeats_beyond_the_unit_square(pattern):
    rng = np.random.default_rng(17)
    u, v = rng.random(100), rng.random(100)
    inside = textures.bilinear_repeat(pattern, u, v)
    for du, dv in [(1, 0), (-1, 0), (0, 3), (-2, -5)]:
        np.testing.assert_allclose(textures.bilinear_repeat(pattern, u + du, v + dv), inside,
                                   atol=1e-12)
    # At the left edge, half of column 0 and half of the last column (wrapped).
    np.testing.assert_allclose(textures.bilinear_repeat(pattern, 0.0, 1 - 0.5 / 4),
                               (pattern[0, 0] + pattern[0, 7]) / 2, rtol=1e-12)
    np.testing.assert_allclose(textures.bilinear_repeat(pattern, 0.5 / 8, 1.0),
                               (pattern[0, 0] + pattern[3, 0]) / 2, rtol=1e-12)


def test_checker_squares():
    c0, c1 = (0.1, 0.2, 0.3), (0.9, 0.8, 0.7)
    u = np.array([0.25, 0.75, 0.75, 0.25, -0.25, 0.3, 0.3])
    v = np.array([0.25, 0.25, 0.75, 0.75, 0.25, 0.1, 0.3])
    expected = [c0, c1, c0, c1, c1, c0, c0]  # frac(-0.25) = 0.75
    np.testing.assert_array_equal(textures.checker(c0, c1, 1.0, u, v), expected)
    # Scale 2: (0.3, 0.1) -> (0.6, 0.2), different halves; (0.3, 0.3) -> (0.6, 0.6).
    np.testing.assert_array_equal(textures.checker(c0, c1, 2.0, u[5:], v[5:]), [c1, c0])


# ---------------------------------------------------------------------------------------
# The images and the teapot's vt
# ---------------------------------------------------------------------------------------

def test_handwritten_pngs_read_back_exactly(images):
    from PIL import Image
    for name, make in texture_images.IMAGES.items():
        with Image.open(images / "textures" / name) as image:
            assert image.mode == "RGB", name
            np.testing.assert_array_equal(np.asarray(image), make(), err_msg=name)
        assert textures.image_problem(images / "textures" / name) == ""
    assert not list((images / "textures").glob("*.partial"))


def test_uv_grid_has_its_letter_f_upright_near_vt_origin(images):
    grid = textures.read_image(images / "textures" / "uv_grid.png")
    black = grid.max(axis=-1) == 0
    # Looked up with v up: the F's stem on the left, its top bar above its middle bar.
    assert textures.bilinear_repeat(grid, 0.11, 0.15).max() == 0  # the stem
    assert textures.bilinear_repeat(grid, 0.30, 0.39).max() == 0  # the top bar's end
    assert textures.bilinear_repeat(grid, 0.30, 0.25).max() > 0.1  # right of the middle bar
    assert textures.bilinear_repeat(grid, 0.30, 0.11).max() > 0.1  # no bottom bar
    assert black[:128, :].sum() == 0  # nothing black in the top half


@pytest.fixture(scope="module")
def teapot_uv():
    patches, control_points = teapot.load_patches()
    return patches, control_points, teapot.tessellate(patches, control_points, 3,
                                                      with_uv=True)


def test_teapot_vt_are_each_patchs_own_grid(teapot_uv):
    patches, control_points, (positions, normals, triangles, uv, triangle_uv) = teapot_uv
    plain = teapot.tessellate(patches, control_points, 3)
    for ours, theirs in zip((positions, normals, triangles), plain):
        np.testing.assert_array_equal(ours, theirs)  # vt change nothing else
    assert uv.shape == (16, 2) and uv.min() == 0 and uv.max() == 1
    # Each triangle is half a grid cell in (u, v), counter-clockwise like its positions.
    corners = uv[triangle_uv]
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    np.testing.assert_allclose(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0], 1 / 9, atol=1e-12)
    # Every corner of a triangle is one patch evaluated at that corner's vt.
    nets = control_points[patches].reshape(-1, 4, 4, 3)  # [patch, v, u]
    flat_uv = corners.reshape(-1, 2)
    on_patches = np.einsum("kj,ki,pjic->pkc", teapot.bernstein(flat_uv[:, 1]),
                           teapot.bernstein(flat_uv[:, 0]), nets)
    distance = np.linalg.norm(on_patches - positions[triangles].reshape(-1, 3), axis=-1)
    worst_corner = distance.reshape(len(nets), -1, 3).max(axis=-1)  # (patch, triangle)
    assert worst_corner.min(axis=0).max() < 1e-5


def test_teapot_with_vt_writes_and_reads_back(tmp_path, teapot_uv):
    path = tmp_path / "teapot_uv.obj"
    teapot.main(["--segments", "3", "--uv", "--out", str(path)])
    text = path.read_text()
    assert text.count("\nvt ") == 16 and "f 1/" not in text.split("\nf ")[0]
    positions, normals, triangles, _ = obj_io.read_obj(path)  # obj_io skips vt
    _, _, (ours, _, our_triangles, _, _) = teapot_uv
    np.testing.assert_allclose(positions, ours, atol=1e-6)
    np.testing.assert_array_equal(triangles, our_triangles)


# ---------------------------------------------------------------------------------------
# Mitsuba 3 looks textures up as textures.py does
# ---------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def mi():
    pytest.importorskip("mitsuba", reason="pip install -r requirements.txt")
    from python_prototypes import mitsuba_reference
    return mitsuba_reference.import_mitsuba("scalar_rgb")


def write_scene(folder: Path, texture_line: str, shape: str) -> scene_io.Scene:
    """A scene whose one visible shape, textured by `texture_line`'s texture t, is the
    turned square: as a quad, or (shape "mesh") as an OBJ quad with vt = mesh_vt."""
    corners = [ORIGIN, ORIGIN + EDGE1, ORIGIN + EDGE1 + EDGE2, ORIGIN + EDGE2]
    quad_ab = [(0, 0), (1, 0), (1, 1), (0, 1)]
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in corners]
    lines += ["vt {:.9g} {:.9g}".format(*mesh_vt(a, b)) for a, b in quad_ab]
    (folder / "square.obj").write_text("\n".join(lines) + "\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
    numbers = " ".join(f"{x:.9g}" for x in [*ORIGIN, *EDGE1, *EDGE2])
    shape_line = f"quad {numbers} wall" if shape == "quad" else "mesh square.obj wall"
    path = folder / f"{shape}.scene"
    path.write_text(f"{CAMERA}\n{LAMP}{texture_line}\nmaterial wall albedo texture t\n"
                    f"{shape_line}\n")
    return scene_io.load_scene(path)


def our_uv(scene: scene_io.Scene, width=W, height=H):
    """(u, v) our way at each pixel centre's hit (camera_rays.py's rays): (height,
    width) each."""
    from python_prototypes import mitsuba_reference
    eye = np.asarray(scene.camera.eye, dtype=np.float64)
    directions = mitsuba_reference.ray_directions(scene.camera, width, height)
    points = eye + directions * (-eye[2] / directions[..., 2])[..., None]  # z = 0
    normal = np.cross(EDGE1, EDGE2)
    across1, across2 = np.cross(EDGE2, normal), np.cross(normal, EDGE1)
    a = (points - ORIGIN) @ across1 / (EDGE1 @ across1)
    b = (points - ORIGIN) @ across2 / (EDGE2 @ across2)
    assert a.min() > 0 and a.max() < 1 and b.min() > 0 and b.max() < 1  # all on the square
    return (a, b) if scene.quads else mesh_vt(a, b)


def mitsuba_lookup(mi, scene: scene_io.Scene, **shape_options):
    """Mitsuba's uv (H, W, 2) and albedo (H, W, 3) where each pixel centre's ray hits:
    its own camera, intersection, uv and texture (what the aov integrator's albedo
    shows), without the random position in the pixel a render would add."""
    from python_prototypes import mitsuba_reference
    scene_dict = mitsuba_reference.mitsuba_scene_dict(mi, scene, W, H, bounces=1)
    for key in scene_dict:
        if key.startswith("mesh_"):
            scene_dict[key].update(shape_options)
    loaded = mi.load_dict(scene_dict)
    sensor = loaded.sensors()[0]
    uv, albedo = np.zeros((H, W, 2)), np.zeros((H, W, 3))
    for row in range(H):
        for column in range(W):
            ray, _ = sensor.sample_ray(0.0, 0.5, [(column + 0.5) / W, (row + 0.5) / H],
                                       [0.5, 0.5])
            si = loaded.ray_intersect(ray)
            assert si.is_valid(), (row, column)
            uv[row, column] = si.uv
            albedo[row, column] = si.bsdf().eval_diffuse_reflectance(si)
    return uv, albedo


@pytest.mark.parametrize("shape", ["quad", "mesh"])
@pytest.mark.parametrize("linear", [False, True])
def test_mitsuba_shows_images_as_textures_py(mi, tmp_path, images, shape, linear):
    image = images / "textures" / "test_pattern.png"
    scene = write_scene(tmp_path, f"texture t image {image}" + (" linear" if linear else ""),
                        shape)
    u, v = our_uv(scene)
    uv, albedo = mitsuba_lookup(mi, scene)
    np.testing.assert_allclose(uv[..., 0], u, atol=2e-6)  # Mitsuba's uv is ours
    np.testing.assert_allclose(uv[..., 1], v, atol=2e-6)
    texels = textures.read_image(image, linear)
    ours = textures.bilinear_repeat(texels, u, v)
    np.testing.assert_allclose(albedo, ours, atol=2e-5)
    # The comparison would catch an image upside down, half a texel off, or decoded
    # after filtering instead of before.
    encoded = textures.read_image(image, linear=True)
    mistakes = {
        "upside down": textures.bilinear_repeat(texels, u, 1 - v),
        "mirrored": textures.bilinear_repeat(texels, -u, v),
        "half a texel off": textures.bilinear_repeat(texels, u + 0.5 / 8, v + 0.5 / 4)}
    if not linear:
        mistakes["decoded after filtering"] = textures.srgb_to_linear(
            textures.bilinear_repeat(encoded, u, v))
    for name, wrong in mistakes.items():
        assert np.abs(albedo - wrong).max() > 1e-3, name


@pytest.mark.parametrize("shape", ["quad", "mesh"])
def test_mitsuba_checkerboard_is_textures_py_checker(mi, tmp_path, shape):
    scene = write_scene(tmp_path, "texture t checker 0.1 0.2 0.3 0.9 0.8 0.7 scale 3",
                        shape)
    u, v = our_uv(scene)
    _, albedo = mitsuba_lookup(mi, scene)
    ours = textures.checker((0.1, 0.2, 0.3), (0.9, 0.8, 0.7), 3.0, u, v)
    np.testing.assert_allclose(albedo, ours, atol=1e-6)
    assert np.abs(albedo - textures.checker((0.1, 0.2, 0.3), (0.9, 0.8, 0.7), 3.0, u,
                                            1 - v)).max() > 0.5
    if shape == "mesh":
        # Why meshes are loaded with flip_tex_coords false: Mitsuba's default turns the
        # vt upside down, which its bitmap undoes but its checkerboard does not.
        _, flipped = mitsuba_lookup(mi, scene, flip_tex_coords=True)
        assert np.abs(flipped - ours).max() > 0.5


def test_mitsubas_albedo_render_agrees_over_each_pixel(mi, tmp_path, images):
    """Through mitsuba.render too: the aov integrator's albedo, averaged over each pixel
    by the box filter, against the numpy lookup averaged over 8 x 8 points per pixel."""
    from python_prototypes import mitsuba_reference
    scene = write_scene(tmp_path, f"texture t image {images}/textures/test_pattern.png",
                        "mesh")
    scene_dict = mitsuba_reference.mitsuba_scene_dict(mi, scene, W, H, bounces=1, spp=64)
    scene_dict["integrator"] = {"type": "aov", "aovs": "albedo:albedo"}
    rendered = np.array(mi.render(mi.load_dict(scene_dict), seed=3))[..., -3:]
    sub = 8  # the centres of 8 x 8 sub-pixels: a finer image's pixel centres
    u, v = our_uv(scene, W * sub, H * sub)
    texels = textures.read_image(images / "textures" / "test_pattern.png")

    def pixel_means(values):
        return values.reshape(H, sub, W, sub, 3).mean(axis=(1, 3))
    assert np.abs(rendered - pixel_means(textures.bilinear_repeat(texels, u, v))).mean() \
        < 0.01
    assert np.abs(rendered - pixel_means(textures.bilinear_repeat(texels, u, 1 - v))).mean() \
        > 0.05


# ---------------------------------------------------------------------------------------
# The thin lens, and whole scenes through render_mitsuba
# ---------------------------------------------------------------------------------------

def test_scene_lens_is_mitsubas_thinlens_of_that_radius(mi, tmp_path):
    from python_prototypes import mitsuba_reference
    path = tmp_path / "lens.scene"
    path.write_text(f"{CAMERA} lens 0.02 focus 1.5\n{LAMP}")
    scene = scene_io.load_scene(path)
    sensor_dict = mitsuba_reference.mitsuba_scene_dict(mi, scene, W, H, 1)["sensor"]
    assert sensor_dict["type"] == "thinlens" and sensor_dict["aperture_radius"] == 0.02
    assert sensor_dict["focus_distance"] == 1.5
    sensor = mi.load_dict(sensor_dict)
    camera = scene.camera.as_thin_lens_camera()
    rng = np.random.default_rng(5)
    x, y, u1, u2 = rng.uniform(0, W, 50), rng.uniform(0, H, 50), rng.random(50), \
        rng.random(50)
    origins, directions = thin_lens.thin_lens_rays(camera, W, H, x, y, u1, u2)
    for i in range(50):
        ray, _ = sensor.sample_ray(0.0, 0.5, [x[i] / W, y[i] / H], [1 - u1[i], u2[i]])
        d = np.array(ray.d, dtype=np.float64)
        o = np.array(ray.o, dtype=np.float64) - d * sensor.near_clip() / -d[2]
        np.testing.assert_allclose(d, directions[i], atol=2e-6)
        np.testing.assert_allclose(o, origins[i], atol=2e-6)
    path.write_text(f"{CAMERA} lens 0 focus 1.5\n{LAMP}")  # radius 0: the pinhole
    no_lens = mitsuba_reference.mitsuba_scene_dict(mi, scene_io.load_scene(path), W, H, 1)
    assert no_lens["sensor"]["type"] == "perspective"


def test_render_mitsuba_renders_a_textured_teapot_through_a_lens(mi, tmp_path, images):
    from python_prototypes import mitsuba_reference
    teapot.main(["--segments", "3", "--uv", "--out", str(tmp_path / "teapot_uv.obj")])
    path = tmp_path / "teapot.scene"
    path.write_text("camera eye 0 1.5 5 look 0 -0.2 -1 up 0 1 0 focal 0.035 sensor 0.036 "
                    "lens 0.01 focus 5\n"
                    "texture grid image textures/uv_grid.png\n"
                    "texture tiles checker 0.2 0.2 0.2 0.8 0.8 0.8 scale 4\n"
                    "material pot albedo texture grid\nmaterial floor albedo texture tiles\n"
                    "material lamp albedo 0 0 0 emission 4 4 4\n"
                    "mesh teapot_uv.obj pot\nquad -3 0 3 6 0 0 0 0 -6 floor\n"
                    "quad -1 4 -1 2 0 0 0 0 2 lamp\n")
    scene = scene_io.load_scene(path, [images])
    image, stats = mitsuba_reference.render_mitsuba(scene, 24, 16, spp=4, bounces=2)
    assert image.shape == (16, 24, 3) and np.isfinite(image).all() and image.max() > 0
    assert stats["spp"] == 4
