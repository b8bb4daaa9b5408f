"""Chapter 10: scenes from files. What the camera sees must be what a numpy ray caster
(python_prototypes/scene_cast.py, float64) finds in the same file: the right shape, its
material, its front or back, pixel by pixel; and the ambient occlusion the preview
darkens surfaces by must converge to its closed form, judged by statistics, for a
sphere on a floor. Each check is shown to reject a planted mistake."""

import numpy as np
import pytest

import path_checks
from python_prototypes import scene_cast
from python_prototypes import scene_io
from conftest import ROOT, copy_shaders, read_pfm, render, run_chapter

SCENES = ROOT / "assets" / "scenes"

# Every kind of shape and both sides: a sphere, a quad facing the camera, a quad
# turned away (its back is seen), a lone triangle, a glowing quad, on a grey floor.
SHAPES = """camera eye 0 1.2 4 look 0 -0.25 -1 up 0 1 0 focal 0.035 sensor 0.036
material grey albedo 0.5 0.5 0.5
material red albedo 0.8 0.1 0.1
material blue albedo 0.1 0.2 0.9
material lamp albedo 0.2 0.2 0.2 emission 3 2 1
quad -3 0 3   6 0 0   0 0 -6   grey name floor
sphere -0.9 0.5 0 0.5 red name ball
quad 0.1 0 -0.5   0.8 0 0   0 0.9 0   blue name facing
quad 1.1 0.1 0.2   0 0.8 0   0.6 0 0   blue name turned_away
triangle -0.5 1.2 -1   0.5 1.2 -1   0 1.9 -1   red name triangle
quad -2 1.6 -1.5   1 0 0   0 0.6 0   lamp name lamp
"""


def unoccluded_preview(scene: scene_io.Scene, width: int, height: int):
    """What the preview converges to with no occlusion at all: a front shows its glow
    plus its albedo, a back and the void show black. Also which pixels are the same
    surface at their centre and four points near their corners (where the GPU's
    random point in the pixel cannot land elsewhere)."""
    materials = list(scene.materials.values())
    hits = []
    for offset in [(0.5, 0.5), (0.02, 0.02), (0.98, 0.02), (0.02, 0.98), (0.98, 0.98)]:
        origin, directions = scene_cast.pixel_rays(scene.camera, width, height, offset)
        hits.append(scene_cast.nearest_hits(scene, origin, directions))
    centre = hits[0]
    uniform = np.ones(centre.t.shape, dtype=bool)
    for other in hits[1:]:
        uniform &= (other.material == centre.material) & (other.front == centre.front)
    colours = np.array([np.add(m.albedo, m.emission) for m in materials])
    expected = np.where((centre.front & (centre.material >= 0))[..., None],
                        colours[np.maximum(centre.material, 0)], 0.0)
    return expected, uniform


def preview(tmp_path, scene_file, name, *args):
    """The preview with an occlusion distance too short for anything to occlude."""
    return render("10", tmp_path / f"{name}.pfm", "--scene", scene_file, "--width", 64,
                  "--height", 64, "--spp", 4, "--ao-distance", "1e-7", *args)


def mismatched_pixels(image, scene_file):
    expected, uniform = unoccluded_preview(scene_io.load_scene(scene_file), 64, 64)
    assert uniform.mean() > 0.8  # most pixels are compared
    wrong = np.abs(image[..., :3] - expected).max(axis=-1) > 1e-4
    return int((wrong & uniform).sum())


@pytest.fixture
def shapes_scene(tmp_path):
    path = tmp_path / "shapes.scene"
    path.write_text(SHAPES)
    return path


@pytest.mark.windows
@pytest.mark.parametrize("scene", ["shapes", "cornell_spheres", "cornell_box"])
def test_every_pixel_shows_the_surface_numpy_finds(tmp_path, shapes_scene, scene):
    scene_file = shapes_scene if scene == "shapes" else SCENES / f"{scene}.scene"
    image = preview(tmp_path, scene_file, scene)
    assert mismatched_pixels(image, scene_file) == 0


def test_the_back_of_a_surface_is_black_and_its_front_is_not(tmp_path, shapes_scene):
    scene = scene_io.load_scene(shapes_scene)
    origin, directions = scene_cast.pixel_rays(scene.camera, 64, 64)
    hits = scene_cast.nearest_hits(scene, origin, directions)
    blue = list(scene.materials).index("blue")
    image = preview(tmp_path, shapes_scene, "sides")
    _, uniform = unoccluded_preview(scene, 64, 64)  # the whole pixel on one side
    backs = (hits.material == blue) & ~hits.front & uniform
    fronts = (hits.material == blue) & hits.front & uniform
    assert backs.sum() > 20 and fronts.sum() > 20  # the scene shows both sides
    assert np.all(image[backs][:, :3] < 1e-6)
    assert np.all(image[fronts][:, :3] > 0.05)


def test_a_quad_test_that_never_hits_is_caught(tmp_path, shapes_scene):
    """The starter's stub (no quad is ever hit: no floor, no walls, no lamp)."""
    inside = "return a >= 0.0 && a <= 1.0 && b >= 0.0 && b <= 1.0;"
    shaders = path_checks.shaders_with_bug("10", tmp_path,
                                           ("scene.glsl", inside, "return false;"))
    image = preview(tmp_path, shapes_scene, "no_quads", "--shader-dir", shaders)
    assert mismatched_pixels(image, shapes_scene) > 500


# ---------------------------------------------------------------------------------------
# Ambient occlusion, judged by statistics
# ---------------------------------------------------------------------------------------

RADIUS = 0.5
# A sphere resting on a floor, seen from above and in front; nothing else within reach
# but a lamp (a scene file needs one) 1 cm wide and 40 m up: a ray from the floor
# finds it about once in ten million.
SPHERE_ON_FLOOR = f"""camera eye 0 2.2 2.2 look 0 -1 -1 up 0 1 0 focal 0.02 sensor 0.036
material grey albedo 0.5 0.5 0.5
material lamp albedo 0 0 0 emission 1 1 1
quad -50 0 50   100 0 0   0 0 -100   grey name floor
sphere 0 {RADIUS} 0 {RADIUS} grey name ball
quad 0 40 0   0.01 0 0   0 0 0.01   lamp name lamp
"""
SIZE, SPP = 64, 64


def expected_floor_occlusion(scene, size):
    """The cosine-weighted share of the sky a floor point sees past a sphere of radius R
    resting on the floor: 1 - cos(theta) (R / D)^2 = 1 - R^3 / D^3, D the distance to
    the centre (the sphere's form factor from the point). Averaged over a 4 x 4 grid of
    points in each pixel; NaN for pixels that see any of the sphere."""
    total = np.zeros((size, size))
    on_floor = np.ones((size, size), dtype=bool)
    for i in range(4):
        for j in range(4):
            origin, directions = scene_cast.pixel_rays(scene.camera, size, size,
                                                       ((i + 0.5) / 4, (j + 0.5) / 4))
            hits = scene_cast.nearest_hits(scene, origin, directions)
            on_floor &= hits.material >= 0
            points = origin + np.where(np.isfinite(hits.t), hits.t, 0)[..., None] * directions
            on_floor &= np.abs(points[..., 1]) < 1e-9  # the floor, not the sphere
            distance = np.linalg.norm(points - np.array([0.0, RADIUS, 0.0]), axis=-1)
            total += 1.0 - (RADIUS / distance) ** 3
    return np.where(on_floor, total / 16, np.nan)


def occlusion_z_scores(image, expected):
    """Floor pixels grouped in rings by their expected occlusion; each ring's mean
    against the expected mean, in standard errors of a mean of 0/1 samples."""
    seen = image[..., 0]
    scores = []
    edges = np.linspace(np.nanmin(expected), 1.0, 9)
    for low, high in zip(edges[:-1], edges[1:]):
        ring = (expected >= low) & (expected < high)
        if ring.sum() < 10:
            continue
        p = expected[ring]
        error = np.sqrt(np.sum(p * (1 - p) / SPP)) / ring.sum()
        scores.append(abs(seen[ring].mean() - p.mean()) / max(error, 1e-6))
    return np.array(scores)


def occlusion_image(tmp_path, name, *args):
    path = tmp_path / "sphere_on_floor.scene"
    path.write_text(SPHERE_ON_FLOOR)
    image = render("10", tmp_path / f"{name}.pfm", "--scene", path, "--view", "ao",
                   "--ao-distance", "1e30", "--width", SIZE, "--height", SIZE,
                   "--spp", SPP, *args)
    return image, expected_floor_occlusion(scene_io.load_scene(path), SIZE)


def test_ambient_occlusion_converges_to_the_closed_form(tmp_path):
    image, expected = occlusion_image(tmp_path, "ao")
    assert np.isfinite(expected).sum() > 0.5 * SIZE * SIZE
    assert np.nanmin(expected) < 0.75  # the rings near the sphere are well occluded
    scores = occlusion_z_scores(image, expected)
    assert len(scores) >= 6
    assert scores.max() < 4.5, scores


def escaping_share(scene, points, normal, rays: int, rng) -> np.ndarray:
    """numpy's answer to --view ao with no distance limit: the share of `rays`
    cosine-weighted directions from each point that meet nothing."""
    u1, u2 = rng.random((2, len(points), rays))
    radius, angle = np.sqrt(u1), 2 * np.pi * u2
    side = np.cross(normal, [0.0, 1.0, 0.0] if abs(normal[1]) < 0.9 else [1.0, 0.0, 0.0])
    side /= np.linalg.norm(side)
    other = np.cross(normal, side)
    directions = (radius[..., None] * (np.cos(angle)[..., None] * side
                                       + np.sin(angle)[..., None] * other)
                  + np.sqrt(1 - u1)[..., None] * normal)
    origins = np.broadcast_to(points[:, None, :] + 1e-6 * normal, directions.shape)
    hits = scene_cast.nearest_hits(scene, origins, directions)
    return np.isinf(hits.t).mean(axis=1)


def test_past_the_rooms_longest_chord_only_its_open_front_lights_it(tmp_path):
    """Exercise 4's answer. The room has no wall at +z, where the camera looks in; every
    other ray from inside meets a wall within the space diagonal, 2 sqrt(3) = 3.46 m. So
    at --ao-distance 5 a point keeps the share of its sky it sees through the opening:
    at the back wall's centre, in the empty room, the form factor of the 2 x 2 m opening
    2 m away (four corner rectangles of 1 x 1 m), 0.2394; in cornell_spheres a little
    less, where a sphere hides part of it. The GPU's back wall agrees with numpy's rays."""
    rng = np.random.default_rng(10)
    x = y = 1.0 / 2.0  # each quarter of the opening over the distance
    corner = (x / np.hypot(1, x) * np.arctan(y / np.hypot(1, x))
              + y / np.hypot(1, y) * np.arctan(x / np.hypot(1, y))) / (2 * np.pi)
    assert 4 * corner == pytest.approx(0.2394, abs=1e-4)
    path = ROOT / "assets" / "scenes" / "cornell_spheres.scene"
    scene = scene_io.load_scene(str(path))
    empty = scene_io.load_scene(str(path))
    empty.spheres.clear()
    empty.quads[:] = [q for q in empty.quads if q.material != "light"]
    centre, normal = np.array([[0.0, 0.0, -1.0]]), np.array([0.0, 0.0, 1.0])
    share = escaping_share(empty, centre, normal, 200_000, rng)[0]
    assert share == pytest.approx(4 * corner, abs=4.5 * np.sqrt(0.24 * 0.76 / 200_000))
    corners = np.array([np.add(q.origin, np.multiply(a, q.edge1) + np.multiply(b, q.edge2))
                        for q in empty.quads for a in (0, 1) for b in (0, 1)])
    longest = np.linalg.norm(corners[:, None] - corners[None], axis=-1).max()
    assert longest == pytest.approx(2 * np.sqrt(3)) and longest < 5  # the space diagonal

    from python_prototypes import mitsuba_reference
    size, spp = 32, 256
    image = render("10", tmp_path / "ao.pfm", "--scene", path, "--view", "ao",
                   "--ao-distance", "5", "--width", size, "--height", size, "--spp", spp)
    back = mitsuba_reference.region_masks(scene, size, size)["back"]
    origin, directions = scene_cast.pixel_rays(scene.camera, size, size)
    t = scene_cast.nearest_hits(scene, origin, directions).t
    points = (origin + t[..., None] * directions)[back]
    expected = escaping_share(scene, points, normal, 1000, rng)
    seen = image[..., 0][back]
    error = np.sqrt(np.sum(expected * (1 - expected)) / spp + np.sum(
        expected * (1 - expected)) / 1000) / back.sum()
    print(f"back wall at --ao-distance 5: {seen.mean():.4f}, numpy {expected.mean():.4f}")
    assert back.sum() > 100 and expected.mean() > 0.15  # not dark: the opening shows
    assert abs(seen.mean() - expected.mean()) < 4.5 * error


def test_uniform_directions_taken_for_cosine_ones_are_rejected(tmp_path):
    """A planted mistake: directions uniform over the hemisphere (cos theta = u) in
    place of cosine-distributed ones (cos theta = sqrt(1 - u)): occlusion is then
    weighted by solid angle, not by the cosine, and the rings disagree."""
    shaders = copy_shaders("10", tmp_path / "shaders")
    trace = shaders / "trace.comp"
    text = trace.read_text()
    cosine = "float radius = sqrt(random01(random)), angle"
    assert cosine in text
    text = text.replace(cosine, "float height = random01(random);\n"
                        "    float radius = sqrt(1.0 - height * height), angle")
    text = text.replace("+ sqrt(max(0.0, 1.0 - radius * radius)) * normal;",
                        "+ height * normal;")
    trace.write_text(text)
    image, expected = occlusion_image(tmp_path, "uniform", "--shader-dir", shaders)
    assert occlusion_z_scores(image, expected).max() > 4.5


# ---------------------------------------------------------------------------------------
# Options
# ---------------------------------------------------------------------------------------

def test_a_negative_occlusion_distance_is_bad_usage(tmp_path):
    result = run_chapter("10", "--headless", "--ao-distance", "-1", "--out",
                         tmp_path / "x.png")
    assert result.returncode == 2
    assert "--ao-distance" in result.stderr
    assert not (tmp_path / "x.png").exists()


def test_an_unknown_scene_name_is_bad_usage(tmp_path):
    result = run_chapter("10", "--headless", "--scene", "no_such_room", "--out",
                         tmp_path / "x.png")
    assert result.returncode == 2
    assert "no_such_room" in result.stderr


def test_the_random_number_dump_of_chapter_09_still_works(tmp_path):
    """Chapter 09's generator, unchanged: --dump-random continues its streams."""
    dump = tmp_path / "numbers.bin"
    result = run_chapter("10", "--headless", "--width", 8, "--height", 4, "--spp", 1,
                         "--view", "noise", "--dump-random", dump, "--count", 3,
                         "--out", tmp_path / "noise.png")
    assert result.returncode == 0, result.stderr
    numbers = np.fromfile(dump, dtype="<u4").reshape(3, 4, 8)
    assert len(np.unique(numbers)) == numbers.size  # 96 distinct 32-bit numbers
