"""Chapter 18's environment on the Python side: the numpy lookup
(environment_map.environment_radiance) reads the pixel the lat-long convention names,
from the top row down although PFM stores the bottom row first, turns the map the way
a mesh's rotate_y turns a mesh and multiplies by scale; Mitsuba 3's envmap, as
mitsuba_reference.py writes it from the scene, agrees on orientation, rotate_y and
scale, probed both through the emitter and through a render; the build's maps are
sky.py's."""

from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[3]

from python_prototypes import environment_map
from python_prototypes import environment_sampling
from python_prototypes import mitsuba_reference
from python_prototypes import pfm
from python_prototypes import scene_io
from python_prototypes import sky

CAMERA = "camera eye 0 0 0 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.036\n"
BUILT = REPO / "build" / "assets" / "environments"


def random_directions(rng, count):
    d = rng.normal(size=(count, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def turn_about_y(degrees):
    """A mesh's rotation, counter-clockwise seen from above (scene_io.Mesh)."""
    mesh = scene_io.Mesh(Path("."), "", "", rotation_y_degrees=degrees)
    return mesh.world_from_mesh()[:3, :3]


def load_environment(tmp_path, image, options=""):
    """A scene lit by `image` (written as a PFM) alone: its scene_io.Environment."""
    pfm.write_pfm(tmp_path / "map.pfm", np.asarray(image, dtype=np.float32))
    path = tmp_path / "lit.scene"
    path.write_text(CAMERA + f"environment map.pfm {options}\n")
    return scene_io.load_scene(path).environment


def blocks_map(columns=8, rows=4, block=8):
    """(rows * block, columns * block, 3): each block of block x block pixels one RGB,
    all different and no block a turn or mirror of another: (1 + column, 1 + row,
    1 + column * rows + row)."""
    row, column = np.mgrid[0:rows, 0:columns]
    small = np.stack([1.0 + column, 1.0 + row, 1.0 + column * rows + row], axis=-1)
    return np.kron(small, np.ones((block, block, 1))).astype(np.float32)


# ---------------------------------------------------------------------------------------
# The numpy lookup
# ---------------------------------------------------------------------------------------

def test_each_pixel_is_seen_across_its_whole_patch(tmp_path):
    """Every pixel (row from the top) comes back along its centre and near its corners:
    nearest pixel, no filtering, and the file's bottom-first rows undone."""
    width, height = 16, 8
    image = np.arange(width * height * 3, dtype=np.float32).reshape(height, width, 3)
    environment = load_environment(tmp_path, image)
    for inset in (0.5, 0.02, 0.98):
        u, v = np.meshgrid((np.arange(width) + inset) / width,
                           (np.arange(height) + inset) / height)
        seen = environment_map.environment_radiance(environment, sky.uv_to_direction(u, v))
        assert np.array_equal(seen, image), inset


@pytest.mark.parametrize("direction, row, column", [
    ((0, 1, 0), 0, None), ((0, -1, 0), 7, None),       # zenith: top row; nadir: bottom
    ((0, 0.1, -1), 3, 0), ((1, 0.1, 0), 3, 4), ((0, 0.1, 1), 3, 8), ((-1, 0.1, 0), 3, 12),
    ((0.0, 1e-9, -1.0), 3, 0), ((0.0, 0.0, -1.0), 4, 0)])  # v = 1/2 opens row H/2
def test_axes_read_the_pixels_the_convention_names(tmp_path, direction, row, column):
    """u = atan2(x, -z) / 2π: -z is column 0, +x a quarter across, +z half, -x three
    quarters; v = acos(y) / π: the horizon is the border of rows H/2 - 1 and H/2, and
    a patch holds its upper edge (v in [r, r+1)/H), so the horizon itself is row H/2."""
    width, height = 16, 8
    image = np.zeros((height, width, 3), dtype=np.float32)
    image[:, :, 0] = np.arange(height)[:, None]
    image[:, :, 1] = np.arange(width)[None, :]
    environment = load_environment(tmp_path, image)
    seen = environment_map.environment_radiance(environment, [direction])[0]
    assert seen[0] == row
    if column is not None:
        assert seen[1] == column


def test_rotate_y_turns_the_map_as_rotate_y_turns_a_mesh(tmp_path):
    """What the unturned map shows along d, the map turned by DEGREES shows along the
    mesh rotation of d; with 90, +x's pixel is seen along -z (counter-clockwise seen
    from above). The opposite sense is caught."""
    image = blocks_map()
    rng = np.random.default_rng(1)
    directions = random_directions(rng, 2000)
    unturned = environment_map.environment_radiance(load_environment(tmp_path, image),
                                                    directions)
    for degrees in (90.0, 37.0, -123.0, 400.0):
        turned = load_environment(tmp_path, image, f"rotate_y {degrees}")
        assert turned.rotate_y_degrees == degrees
        seen = environment_map.environment_radiance(turned,
                                                    directions @ turn_about_y(degrees).T)
        # Directions within rounding of a pixel's edge may land on either side.
        assert np.mean(np.all(seen == unturned, axis=-1)) > 0.999, degrees
        wrong_sense = environment_map.environment_radiance(
            turned, directions @ turn_about_y(-degrees).T)
        assert np.mean(np.all(wrong_sense == unturned, axis=-1)) < 0.5, degrees
    quarter = load_environment(tmp_path, image, "rotate_y 90")
    assert np.array_equal(environment_map.environment_radiance(quarter, [(0, 0, -1)]),
                          image[[16], [16]])  # +x's pixel: u = 1/4, v = 1/2


def test_scale_multiplies_and_length_does_not_matter(tmp_path):
    image = blocks_map()
    rng = np.random.default_rng(2)
    directions = random_directions(rng, 500)
    plain = environment_map.environment_radiance(load_environment(tmp_path, image),
                                                 directions)
    scaled = load_environment(tmp_path, image, "scale 2.5 rotate_y 0")
    lengths = rng.uniform(0.01, 100.0, (500, 1))
    assert np.allclose(environment_map.environment_radiance(scaled, directions * lengths),
                       2.5 * plain, rtol=1e-12)


def test_greyscale_maps_are_grey(tmp_path):
    values = np.arange(8, dtype="<f4").reshape(2, 4)
    (tmp_path / "grey.pfm").write_bytes(b"Pf\n4 2\n-1.0\n" + values.tobytes())
    path = tmp_path / "s.scene"
    path.write_text(CAMERA + "environment grey.pfm\n")
    environment = scene_io.load_scene(path).environment
    # Near the poles, towards -z (column 0: exactly at a pole u is atan2(0, -0)).
    seen = environment_map.environment_radiance(environment, [(0, 1, -0.01),
                                                              (0, -1, -0.01)])
    # The file's first row is the bottom: the zenith sees its second row.
    assert np.array_equal(seen[:, 0], [values[1, 0], values[0, 0]])
    assert np.array_equal(seen, np.repeat(seen[:, :1], 3, axis=1))


def test_the_sampler_sees_the_same_pixels():
    """environment_sampling's radiance (what importance sampling assumes) and this
    lookup are one convention."""
    image = sky.spots_map()
    rng = np.random.default_rng(3)
    directions = random_directions(rng, 5000)
    sampler = environment_sampling.EnvironmentSampler.from_image(image)
    assert np.array_equal(environment_map.lookup_nearest(image, directions),
                          sampler.radiance(directions))


# ---------------------------------------------------------------------------------------
# Mitsuba 3 against the lookup
# ---------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def mi():
    pytest.importorskip("mitsuba", reason="pip install -r requirements.txt")
    return mitsuba_reference.import_mitsuba("scalar_rgb")


def mitsuba_eval(mi, emitter, directions):
    """Mitsuba's envmap radiance seen along each direction: a ray going along d meets
    the environment with si.wi = -d."""
    values = []
    for d in np.asarray(directions, dtype=np.float64):
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(*(-d))
        values.append(np.array(emitter.eval(si), dtype=np.float64))
    return np.array(values)


ROTATIONS = [("", 0.0, 1.0), ("rotate_y 90", 90.0, 1.0), ("scale 3 rotate_y 37", 37.0, 3.0),
             ("rotate_y -123 scale 0.25", -123.0, 0.25)]


@pytest.mark.parametrize("options, degrees, scale", ROTATIONS)
def test_mitsubas_envmap_turns_and_scales_as_we_do(mi, tmp_path, options, degrees, scale):
    """The scene's envmap in Mitsuba against sky.mitsuba_envmap_eval (Mitsuba's
    bilinear reading, checked against Mitsuba in test_environment_prototypes.py) at
    our mapFromWorld d, times scale, on the spots map: the same turn and scale.
    Turned the other way, or the scale left out, it is caught."""
    image = sky.spots_map()
    environment = load_environment(tmp_path, image, options)
    emitter = mi.load_dict(mitsuba_reference.mitsuba_envmap(mi, environment))
    directions = random_directions(np.random.default_rng(4), 400)
    got = mitsuba_eval(mi, emitter, directions)

    def reading(turn, factor):
        return factor * sky.mitsuba_envmap_eval(
            image, directions @ environment_map.map_from_world(turn).T)

    # Mitsuba's float32 weights: 1e-6 of the brightest spot (60) either side.
    assert np.allclose(got, reading(degrees, scale), rtol=2e-5, atol=1e-4 * scale)
    if degrees % 180:
        assert not np.allclose(got, reading(-degrees, scale), rtol=0.01, atol=1e-3)
    if scale != 1:
        assert not np.allclose(got, reading(degrees, 1.0), rtol=0.01, atol=1e-3)


@pytest.mark.parametrize("options, degrees, scale", ROTATIONS)
def test_mitsuba_and_our_lookup_agree_where_the_map_is_flat(mi, tmp_path, options, degrees,
                                                            scale):
    """Where the map is constant round a direction (inside a block of 8 x 8 equal
    pixels), Mitsuba's bilinear reading and our nearest pixel must give exactly the
    same value: a test of our lookup by Mitsuba itself, on a map with no symmetry."""
    image = blocks_map()
    environment = load_environment(tmp_path, image, options)
    emitter = mi.load_dict(mitsuba_reference.mitsuba_envmap(mi, environment))
    directions = random_directions(np.random.default_rng(5), 600)
    ours = environment_map.environment_radiance(environment, directions)
    # Flat: the pixel 1.5 pixels away on every side holds the same value.
    in_map = directions @ environment_map.map_from_world(degrees).T
    u, v = sky.direction_to_uv(in_map)
    height, width = image.shape[:2]
    flat = np.ones(len(directions), dtype=bool)
    for du, dv in [(-1.5, 0), (1.5, 0), (0, -1.5), (0, 1.5)]:
        near = sky.uv_to_direction(u + du / width, np.clip(v + dv / height, 0, 1))
        flat &= np.all(environment_map.lookup_nearest(image, near) == ours / scale, axis=-1)
    assert flat.sum() > 150
    got = mitsuba_eval(mi, emitter, directions[flat])
    assert np.allclose(got, ours[flat], rtol=1e-5), degrees


def spot_centroid(image, background):
    """(column, row) of the image's light above the background, and how much there is."""
    excess = np.maximum(sky.luminance(image) - sky.luminance(background), 0.0)
    rows, columns = np.mgrid[0:image.shape[0], 0:image.shape[1]]
    total = excess.sum()
    return np.array([(excess * columns).sum(), (excess * rows).sum()]) / total, total


def test_mitsuba_renders_the_spot_where_we_see_it(mi, tmp_path):
    """A direction probe through the whole pipeline: a camera aimed where the turned map
    should put the blue spot (sky.SPOTS[1], azimuth 200, elevation 15), the scene
    rendered by Mitsuba from mitsuba_scene_dict (depth 0: only the environment) and by
    our lookup, ray by ray. The spot sits in the same place in both, within a pixel;
    turned the other way, our camera would see no spot at all."""
    degrees, width, height = 90.0, 32, 24
    spot = sky.SPOTS[1]
    seen_along = environment_map.map_from_world(degrees).T @ spot.direction()
    pfm.write_pfm(tmp_path / "spots.pfm", sky.spots_map())
    path = tmp_path / "probe.scene"
    path.write_text(CAMERA.replace("look 0 0 -1", "look {:.9g} {:.9g} {:.9g}".format(
        *seen_along)) + f"environment spots.pfm rotate_y {degrees:g}\n")
    scene = scene_io.load_scene(path)
    image, _ = mitsuba_reference.render_mitsuba(scene, width, height, spp=64, bounces=0)
    subsamples = 4
    rays = mitsuba_reference.ray_directions(scene.camera, width, height, subsamples)
    ours = environment_map.environment_radiance(scene.environment, rays)
    ours = ours.reshape(height, subsamples, width, subsamples, 3).mean(axis=(1, 3))
    background = np.array(sky.SPOTS_BACKGROUND)
    (theirs_at, theirs_total), (ours_at, ours_total) = (spot_centroid(i, background)
                                                        for i in (image, ours))
    print(f"spot centroid: Mitsuba {theirs_at}, ours {ours_at}; "
          f"light {theirs_total:.4g} against {ours_total:.4g}")
    assert np.linalg.norm(theirs_at - np.array([width, height]) / 2 + 0.5) < 1.5
    assert np.linalg.norm(theirs_at - ours_at) < 1.0
    assert theirs_total == pytest.approx(ours_total, rel=0.15)
    wrong = environment_map.lookup_nearest(sky.spots_map(), rays, 1.0, -degrees)
    assert np.allclose(wrong, background, atol=1e-6)


# ---------------------------------------------------------------------------------------
# The build's maps
# ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("name, make", [("sky", lambda: sky.sky_map()),
                                        ("spots", lambda: sky.spots_map())])
def test_the_build_writes_sky_pys_maps(name, make):
    """cmake/Assets.cmake's environments/*.pfm are sky.py's defaults, read as a scene
    reads them: sky.pfm 512 x 256, spots.pfm 64 x 32."""
    path = BUILT / f"{name}.pfm"
    assert path.is_file(), f"{path}: build the assets (cmake --build build)"
    image = environment_map.read_map(path)
    assert np.array_equal(image, make())
    assert environment_map.first_bad_texel(image) is None
    assert image.shape == {"sky": (256, 512, 3), "spots": (32, 64, 3)}[name]
