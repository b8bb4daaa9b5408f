"""Chapter 11's yardstick (python_prototypes/mitsuba_reference.py): our Cornell box files
hold exactly Mitsuba 3's Cornell box, Mitsuba renders them, the region masks split an
image sensibly, and Mitsuba's region means are stable from seed to seed."""

import json
import math
import os
from pathlib import Path

import numpy as np
import pytest

from python_prototypes import camera_rays
from python_prototypes import scene_io

mi = pytest.importorskip("mitsuba", reason="pip install -r requirements.txt")
from python_prototypes import mitsuba_reference as reference  # imports mitsuba lazily

ROOT = Path(__file__).resolve().parents[3]
SCENES = ROOT / "assets" / "scenes"
WALLS = ["floor", "ceiling", "back", "left_wall", "right_wall"]


@pytest.fixture(scope="module")
def mitsuba_box():
    """mitsuba.cornell_box(): the dictionary our scene files copy."""
    reference.import_mitsuba("scalar_rgb")
    return mi.cornell_box()


@pytest.fixture(scope="module")
def box_scene():
    return scene_io.load_scene(SCENES / "cornell_box.scene")


@pytest.fixture(scope="module")
def spheres_scene():
    return scene_io.load_scene(SCENES / "cornell_spheres.scene")


def matrix(transform) -> np.ndarray:
    return np.array(transform.matrix, dtype=np.float64)


# ---------------------------------------------------------------------------------------
# Our files hold Mitsuba's Cornell box
# ---------------------------------------------------------------------------------------

MITSUBA_NAMES = {"floor": "floor", "ceiling": "ceiling", "back": "back",
                 "left_wall": "red-wall", "right_wall": "green-wall", "light": "light"}


@pytest.mark.parametrize("scene_name", ["cornell_box", "cornell_spheres"])
def test_room_and_light_are_mitsubas_rectangles(mitsuba_box, scene_name):
    scene = scene_io.load_scene(SCENES / f"{scene_name}.scene")
    quads = {quad.name: quad for quad in scene.quads}
    for ours, theirs in MITSUBA_NAMES.items():
        expected = matrix(mitsuba_box[theirs]["to_world"])
        actual = reference.quad_to_world(quads[ours])
        # Same corners and same front: the rectangle's x, y axes and centre agree, and
        # its z axis (the normal, scaled by Mitsuba's transform) points the same way.
        np.testing.assert_allclose(actual[:3, [0, 1, 3]], expected[:3, [0, 1, 3]],
                                   atol=1e-6, err_msg=ours)
        normal = expected[:3, 2] / np.linalg.norm(expected[:3, 2])
        np.testing.assert_allclose(actual[:3, 2], normal, atol=1e-6, err_msg=ours)


def test_boxes_are_mitsubas_cubes(mitsuba_box, box_scene):
    for ours, theirs in [("small_box", "small-box"), ("large_box", "large-box")]:
        to_world = matrix(mitsuba_box[theirs]["to_world"])
        cube = np.array([[x, y, z, 1] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
        expected = sorted(map(tuple, np.round(cube @ to_world.T, 6)[:, :3]))
        faces = [quad for quad in box_scene.quads if quad.name == ours]
        assert len(faces) == 6
        corners = np.concatenate([face.corners() for face in faces])
        assert sorted(set(map(tuple, np.round(corners, 6) + 0.0))) == expected, ours
        center = np.mean(corners, axis=0)
        for face in faces:  # fronts face out of the box
            assert face.normal() @ (face.corners().mean(axis=0) - center) > 0


def test_materials_and_light_are_mitsubas(mitsuba_box, box_scene):
    for name in ["white", "red", "green"]:
        assert box_scene.materials[name].albedo == \
            tuple(mitsuba_box[name]["reflectance"]["value"])
    light = box_scene.materials["light"]
    assert light.emission == tuple(mitsuba_box["light"]["emitter"]["radiance"]["value"])
    assert light.albedo == box_scene.materials["white"].albedo  # its bsdf is "white"


def test_camera_is_mitsubas(mitsuba_box, box_scene):
    sensor = mitsuba_box["sensor"]
    # Square images: Mitsuba's fov along the smaller axis is our horizontal one.
    assert sensor["fov_axis"] == "smaller"
    assert box_scene.camera.horizontal_fov_degrees() == pytest.approx(sensor["fov"], abs=1e-4)
    ours = reference.mitsuba_scene_dict(mi, box_scene, 256, 256, bounces=7)
    np.testing.assert_allclose(matrix(ours["sensor"]["to_world"]),
                               matrix(sensor["to_world"]), atol=1e-6)
    # mitsuba.cornell_box() renders with max_depth 8: our depth 7.
    assert ours["integrator"]["max_depth"] == mitsuba_box["integrator"]["max_depth"]


# ---------------------------------------------------------------------------------------
# Rendering and regions
# ---------------------------------------------------------------------------------------

SIZE = 64


@pytest.fixture(scope="module")
def masks(spheres_scene):
    # Pixels wholly inside a region, not eroded further: Mitsuba renders with a box
    # filter here, and the light is only 2 pixels tall at this size.
    return reference.region_masks(spheres_scene, SIZE, SIZE, erode_pixels=0)


@pytest.fixture(scope="module")
def renders(spheres_scene):
    """Two 64 spp renders with different seeds."""
    return [reference.render_mitsuba(spheres_scene, SIZE, SIZE, spp=64, bounces=6,
                                     seed=seed) for seed in (1, 2)]


def test_region_masks_cover_the_image_sensibly(spheres_scene, masks):
    ids, names = reference.primary_ids(spheres_scene, SIZE, SIZE)
    assert names == ["left_sphere", "right_sphere", *WALLS, "light"]
    # Only the image's border looks past the open front of the box.
    assert np.mean(ids != reference.MISS) > 0.9
    assert np.all(ids[1:-1, 1:-1] >= 0)
    stacked = np.stack(list(masks.values()))
    assert stacked.sum(axis=0).max() == 1  # no pixel in two regions
    assert 0.6 < stacked.any(axis=0).mean() < 0.9  # only the edges are left out
    counts = {name: int(mask.sum()) for name, mask in masks.items()}
    assert min(counts.values()) >= 10, counts
    # Where things are: red wall on the left, green on the right, light at the top
    # centre, floor at the bottom, the left sphere left of the right one.
    columns = {name: np.nonzero(mask)[1].mean() for name, mask in masks.items()}
    rows = {name: np.nonzero(mask)[0].mean() for name, mask in masks.items()}
    assert columns["left_wall"] < SIZE / 4 and columns["right_wall"] > 3 * SIZE / 4
    assert rows["light"] < SIZE / 5 and abs(columns["light"] - SIZE / 2) < 2
    assert rows["floor"] > 3 * SIZE / 4 and rows["ceiling"] < SIZE / 4
    assert columns["left_sphere"] < SIZE / 2 < columns["right_sphere"]


def test_pixels_on_an_edge_belong_to_no_region(spheres_scene):
    ids, _ = reference.primary_ids(spheres_scene, SIZE, SIZE, subsamples=4)
    centres, _ = reference.primary_ids(spheres_scene, SIZE, SIZE)
    mixed = ids == reference.MIXED
    assert 0.03 < mixed.mean() < 0.2
    assert np.array_equal(ids[~mixed], centres[~mixed])


def test_erosion_removes_edges():
    mask = np.zeros((8, 8), dtype=bool)
    mask[2:6, 1:8] = True
    eroded = reference.erode(mask, 1)
    assert eroded.sum() == 2 * 6  # rows 3-4; columns 2-7 (the image border stays)
    assert np.array_equal(reference.erode(mask, 0), mask)


def test_mitsuba_renders_the_scene(renders):
    image, stats = renders[0]
    assert image.shape == (SIZE, SIZE, 3) and image.dtype == np.float32
    assert np.isfinite(image).all() and image.min() >= 0
    assert stats["mitsuba_max_depth"] == 7 and stats["samples_per_second"] > 0


def test_light_region_shows_the_emitted_radiance(renders, masks, spheres_scene):
    # The light reflects a little light from the room, too: a few per cent at most.
    emission = np.array(spheres_scene.materials["light"].emission)
    for image, _ in renders:
        light = reference.region_means(image, masks)["light"]
        assert np.all(light >= emission * 0.999) and np.all(light <= emission * 1.03)


def test_region_means_agree_between_seeds(renders, masks):
    (first, _), (second, _) = renders
    means = [reference.region_means(image, masks) for image in (first, second)]
    errors = reference.region_standard_errors(first, second, masks)
    for name in masks:
        difference = np.abs(means[0][name] - means[1][name])
        assert np.all(difference <= 4.5 * errors[name] + 1e-9), (
            f"{name}: {means[0][name]} vs {means[1][name]}, standard error {errors[name]}")
    # The directly lit walls agree to 2% at 64 spp (0.5% seen over 4 pairs of seeds; the
    # ceiling, lit only by bounced light, to 2.2%).
    for name in ["floor", "back", "left_wall", "right_wall"]:
        total = [means[k][name].sum() for k in range(2)]
        assert abs(total[0] - total[1]) < 0.02 * total[0], name


def test_direct_lighting_leaves_the_ceiling_dark(spheres_scene, masks):
    # --depth 1 (Mitsuba max_depth 2): the light faces down, so the ceiling gets nothing.
    image, stats = reference.render_mitsuba(spheres_scene, SIZE, SIZE, spp=4, bounces=1)
    means = reference.region_means(image, masks)
    assert stats["mitsuba_max_depth"] == 2
    assert means["ceiling"].max() == 0 and means["floor"].sum() > 0.1


def test_command_line_writes_pfm_and_json(tmp_path):
    out, stats = tmp_path / "m.pfm", tmp_path / "m.json"
    reference.main(["--scene", str(SCENES / "cornell_spheres.scene"), "--width", "32",
                    "--height", "24", "--spp", "2", "--depth", "2", "--out", str(out),
                    "--json", str(stats)])
    image = reference.read_pfm(out)
    assert image.shape == (24, 32, 3)
    data = json.loads(stats.read_text())
    assert data["mitsuba_max_depth"] == 3 and data["width"] == 32
    assert set(data["region_means"]) == {"left_sphere", "right_sphere", *WALLS, "light"}
    assert not list(tmp_path.glob("*.partial"))


def test_pfm_round_trip(tmp_path):
    image = np.random.default_rng(3).random((5, 7, 3)).astype(np.float32)
    reference.write_pfm(tmp_path / "x.pfm", image)
    assert np.array_equal(reference.read_pfm(tmp_path / "x.pfm"), image)
    data = (tmp_path / "x.pfm").read_bytes()
    assert data.startswith(b"PF\n7 5\n-1.0\n")  # little-endian, bottom row first
    assert np.frombuffer(data[12:24], dtype="<f4").tolist() == image[-1, 0].tolist()


def test_horizontal_fov_matches_a_tall_image(spheres_scene):
    # Our sensor width is horizontal for any image shape (Mitsuba: fov_axis "x"). In a
    # tall image the regions must still line up with Mitsuba's picture: the light's
    # pixels show its radiance, the walls' pixels are lit (the floor has the spheres'
    # shadows).
    width, height = 64, 96
    masks = reference.region_masks(spheres_scene, width, height, erode_pixels=0)
    image, _ = reference.render_mitsuba(spheres_scene, width, height, spp=4, bounces=1)
    means = reference.region_means(image, masks)
    emission = np.array(spheres_scene.materials["light"].emission)
    assert masks["light"].sum() >= 10
    assert np.all(means["light"] >= 0.999 * emission)
    for wall in ["back", "left_wall", "right_wall"]:
        lit = image[masks[wall]].sum(axis=-1) > 0
        assert lit.mean() > 0.95, wall
    assert math.isclose(spheres_scene.camera.horizontal_fov_degrees(), 39.30765, abs_tol=1e-4)


def test_centre_rays_are_camera_rays(spheres_scene):
    camera = spheres_scene.camera
    expected = camera_rays.camera_ray_directions(40, 30, camera.eye, camera.look, camera.up,
                                                 camera.focal_length, camera.sensor_width)
    np.testing.assert_allclose(reference.ray_directions(camera, 40, 30), expected,
                               atol=1e-12)


@pytest.mark.skipif(not (Path(reference.DEFAULT_LIBLLVM).exists()
                         or "DRJIT_LIBLLVM_PATH" in os.environ),
                    reason="llvm_ad_rgb needs LLVM 19: apt-get install libllvm19")
def test_llvm_variant_agrees_with_scalar(spheres_scene, masks):
    images = [reference.render_mitsuba(spheres_scene, SIZE, SIZE, spp=16, bounces=6,
                                       seed=1, variant=variant)[0]
              for variant in ("llvm_ad_rgb", "scalar_rgb")]
    means = [reference.region_means(image, masks) for image in images]
    errors = reference.region_standard_errors(*images, masks)
    for name in masks:
        assert np.all(np.abs(means[0][name] - means[1][name]) <= 4.5 * errors[name] + 1e-9), \
            name
