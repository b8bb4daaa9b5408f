"""python_prototypes/instances.py: placements against Mitsuba's transforms, two levels of
trees against the same triangles written out in the world, the planted mistakes the
instances chapter must not make, motion blur against its closed form, and refitting."""

import math

import numpy as np
import pytest

from python_prototypes import instances, scene_io, teapot


@pytest.fixture(scope="module")
def small_teapot():
    patches, control_points = teapot.load_patches()
    positions, _, triangles = teapot.tessellate(patches, control_points, 2)
    return positions[triangles]


def placement(text):
    return instances.placement_from_words(text.split())


# Rotated, unevenly scaled, mirrored, and plain: every kind the chapter's scenes use.
PLACEMENTS = ["translate 0 0 0",
              "scale 1.5 rotate_y 40 translate 5 0 0",
              "scale 2 0.5 1 rotate 1 1 0 70 translate -4 1 2",
              "scale -1 1 1 translate 0 0 6",
              "rotate 0 0 1 25 scale 0.7 translate 3 -1 -5",
              "scale 1 1 -2 rotate_y -120 translate -6 0 -4"]


def random_rays(count, seed, target=(0.0, 0.5, 0.0), spread=6.0):
    """Rays from a sphere of radius 25 towards points near the scene's middle."""
    rng = np.random.default_rng(seed)
    origins = rng.normal(size=(count, 3))
    origins = 25.0 * origins / np.linalg.norm(origins, axis=1, keepdims=True)
    aims = np.asarray(target) + rng.uniform(-spread, spread, size=(count, 3))
    directions = aims - origins
    return origins, directions / np.linalg.norm(directions, axis=1, keepdims=True)


def flattened_hits(scene, origins, directions):
    """t and the unit normal (cross(edge1, edge2)) of the nearest flattened triangle."""
    triangles = scene.flattened_triangles()
    t = np.stack([instances.triangle_t(c, origins, directions) for c in triangles])
    nearest = np.argmin(t, axis=0)
    corners = triangles[nearest]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    return t[nearest, np.arange(len(nearest))], \
        normals / np.linalg.norm(normals, axis=1, keepdims=True)


def instanced_scene(small_teapot, texts=PLACEMENTS):
    mesh = instances.SceneObject(small_teapot)
    return instances.InstancedScene(
        [mesh], [instances.Instance(0, placement(text)) for text in texts])


# ---------------------------------------------------------------------------------------
# Placements
# ---------------------------------------------------------------------------------------

def test_steps_apply_in_the_order_written():
    point = np.array([1.0, 0.0, 0.0])
    assert np.allclose(placement("scale 2 translate 1 0 0").to_world(point), [3, 0, 0])
    assert np.allclose(placement("translate 1 0 0 scale 2").to_world(point), [4, 0, 0])
    # Right-handed: a quarter turn about y takes x to -z.
    assert np.allclose(placement("rotate_y 90").to_world(point), [0, 0, -1])
    assert np.allclose(placement("rotate 0 2 0 33").linear, placement("rotate_y 33").linear)


@pytest.mark.parametrize("text", PLACEMENTS[1:])
def test_a_placement_is_mitsubas_to_world_chain(text):
    """The same steps through Mitsuba's own transforms (an independent implementation):
    each step multiplies from the left, as nested elements of its to_world do."""
    mi = pytest.importorskip("mitsuba")
    mi.set_variant("scalar_rgb")
    words, chain = text.split(), mi.ScalarTransform4f()
    while words:
        step = words.pop(0)
        if step == "scale":
            values = [float(w) for w in words[:3]] if len(words) > 2 and \
                words[1][0] in "-0123456789" else [float(words[0])] * 3
            del words[:3 if words[1:2] and words[1][0] in "-0123456789" else 1]
            chain = mi.ScalarTransform4f().scale(values) @ chain
        elif step == "rotate":  # Mitsuba's rotate takes a unit axis as it is; ours any
            axis = np.array([float(w) for w in words[:3]])
            chain = mi.ScalarTransform4f().rotate(axis / np.linalg.norm(axis),
                                                  float(words[3])) @ chain
            del words[:4]
        elif step == "rotate_y":
            chain = mi.ScalarTransform4f().rotate([0, 1, 0], float(words.pop(0))) @ chain
        else:
            chain = mi.ScalarTransform4f().translate([float(w) for w in words[:3]]) @ chain
            del words[:3]
    matrix = np.array(chain.matrix, dtype=np.float64)
    ours = placement(text)
    assert np.allclose(ours.linear, matrix[:3, :3], atol=1e-6)
    assert np.allclose(ours.offset, matrix[:3, 3], atol=1e-5)


def test_a_placement_that_cannot_be_made_is_the_scene_readers_mistake():
    """The prototype reads placements through the scene reader (one copy): its mistakes
    are the scene file's (checked word for word in test_scene_io.py)."""
    with pytest.raises(scene_io.SceneError, match="scale by 0 squashes the object flat"):
        placement("scale 0")


# ---------------------------------------------------------------------------------------
# Two levels against the same triangles written out
# ---------------------------------------------------------------------------------------

def test_instances_see_what_their_triangles_written_out_see(small_teapot):
    scene = instanced_scene(small_teapot)
    origins, directions = random_rays(600, seed=1)
    hits = scene.intersect(origins, directions)
    t, normals = flattened_hits(scene, origins, directions)
    assert np.sum(np.isfinite(t)) > 200  # most rays hit something
    assert np.array_equal(np.isfinite(hits.t), np.isfinite(t))
    hit = np.isfinite(t)
    assert np.allclose(hits.t[hit], t[hit], rtol=1e-9)
    # The inverse transpose gives the normal the triangle has in the world, mirrored
    # instances included (their written-out triangles have two corners swapped).
    assert np.allclose(hits.normal[hit], normals[hit], atol=1e-7)
    assert {hits.instance[k] for k in np.flatnonzero(hit)} == set(range(len(PLACEMENTS)))


def test_the_top_level_finds_what_testing_every_instance_finds(small_teapot):
    rng = np.random.default_rng(5)
    texts = [f"rotate_y {rng.uniform(0, 360):.3f} scale {rng.uniform(0.3, 1.2):.3f} "
             f"translate {rng.uniform(-20, 20):.3f} {rng.uniform(-2, 2):.3f} "
             f"{rng.uniform(-20, 20):.3f}" for _ in range(120)]
    scene = instanced_scene(small_teapot, texts)
    origins, directions = random_rays(400, seed=2, spread=20.0)
    hits = scene.intersect(origins, directions)
    expected = instances.brute_force(scene, origins, directions)
    assert np.sum(np.isfinite(expected)) > 100
    assert np.array_equal(np.isfinite(hits.t), np.isfinite(expected))
    assert np.allclose(hits.t[np.isfinite(expected)], expected[np.isfinite(expected)],
                       rtol=1e-9)


def test_memory_is_one_mesh_and_a_few_words_an_instance(small_teapot):
    scene = instanced_scene(small_teapot, [f"translate {3 * k} 0 0" for k in range(1000)])
    words = scene.memory_words()
    assert words["objects"] < 9 * len(small_teapot) * 2  # one mesh and its tree
    assert words["instances"] + words["top level"] < 40 * 1000
    assert sum(words.values()) < 9 * len(small_teapot) * 1000 / 20  # vs writing them out


# ---------------------------------------------------------------------------------------
# The chapter's planted mistakes make these checks fail
# ---------------------------------------------------------------------------------------

def normals_by_the_matrix(self, normals):
    world = np.asarray(normals) @ self.linear.T
    return world / np.linalg.norm(world, axis=-1, keepdims=True)


def direction_normalised(original):
    def ray_to_object(self, origins, directions, time=0.0):
        local_origins, local_directions = original(self, origins, directions, time)
        return local_origins, local_directions / np.linalg.norm(local_directions, axis=-1,
                                                                 keepdims=True)
    return ray_to_object


def object_box_only(scene_object, placement, swept=True):
    return scene_object.box()


@pytest.mark.parametrize("mistake", ["normal by the matrix", "t in object units",
                                     "box not carried to the world"])
def test_a_planted_mistake_is_caught(small_teapot, monkeypatch, mistake):
    if mistake == "normal by the matrix":
        monkeypatch.setattr(instances.Placement, "normal_to_world", normals_by_the_matrix)
    elif mistake == "t in object units":
        monkeypatch.setattr(instances.Placement, "ray_to_object",
                            direction_normalised(instances.Placement.ray_to_object))
    else:
        monkeypatch.setattr(instances, "world_box", object_box_only)
    scene = instanced_scene(small_teapot)
    origins, directions = random_rays(600, seed=1)
    hits = scene.intersect(origins, directions)
    t, normals = flattened_hits(scene, origins, directions)
    hit = np.isfinite(t) & np.isfinite(hits.t)
    agrees = np.array_equal(np.isfinite(hits.t), np.isfinite(t)) \
        and np.allclose(hits.t[hit], t[hit], rtol=1e-9) \
        and np.allclose(hits.normal[hit], normals[hit], atol=1e-7)
    assert not agrees


# ---------------------------------------------------------------------------------------
# Motion blur
# ---------------------------------------------------------------------------------------

def test_a_moving_spheres_smear_is_its_closed_form():
    """Rays across a sphere's path: the share of random shutter times at which the
    two levels find it is the closed form's fraction (binomial error, 4.5 sigma)."""
    ball = instances.SceneObject(np.zeros((0, 3, 3)), spheres=[((0.0, 0.0, 0.0), 1.0)])
    moving = instances.Instance(0, placement("scale 0.5 translate -2 0 0 moving 4 0.5 0"))
    scene = instances.InstancedScene([ball], [moving])
    rng = np.random.default_rng(7)
    samples = 4000
    for x, y in [(-2.0, 0.0), (-1.0, 0.1), (0.0, 0.2), (0.5, 0.6), (1.9, 0.2), (2.6, 0.0),
                 (0.0, -0.6)]:
        origin, direction = np.array([x, y, 10.0]), np.array([0.0, 0.0, -1.0])
        expected = instances.moving_sphere_coverage(origin, direction, (-2.0, 0.0, 0.0),
                                                    (4.0, 0.5, 0.0), 0.5)
        hits = scene.intersect(np.tile(origin, (samples, 1)), np.tile(direction, (samples, 1)),
                               rng.uniform(size=samples))
        share = np.mean(np.isfinite(hits.t))
        sigma = math.sqrt(max(expected * (1 - expected), 1e-4) / samples)
        assert abs(share - expected) < 4.5 * sigma, (x, y, share, expected)


def test_a_box_not_swept_over_the_shutter_loses_the_late_sphere(monkeypatch):
    """The planted mistake: the top level's box where the sphere is at the shutter's
    opening only. A ray it crosses late is then never tested."""
    original = instances.world_box
    monkeypatch.setattr(instances, "world_box",
                        lambda o, p, swept=True: original(o, p, swept=False))
    ball = instances.SceneObject(np.zeros((0, 3, 3)), spheres=[((0.0, 0.0, 0.0), 1.0)])
    scene = instances.InstancedScene(
        [ball], [instances.Instance(0, placement("scale 0.5 translate -2 0 0 moving 4 0 0"))])
    origin, direction = np.array([1.5, 0.0, 10.0]), np.array([0.0, 0.0, -1.0])
    expected = instances.moving_sphere_coverage(origin, direction, (-2, 0, 0), (4, 0, 0), 0.5)
    hits = scene.intersect(np.tile(origin, (1000, 1)), np.tile(direction, (1000, 1)),
                           np.random.default_rng(3).uniform(size=1000))
    assert expected == pytest.approx(0.25)
    assert np.mean(np.isfinite(hits.t)) == 0.0


def test_the_closed_form_for_a_still_or_missing_sphere():
    down = np.array([0.0, 0.0, -1.0])
    assert instances.moving_sphere_coverage((0, 0, 5), down, (0, 0, 0), (0, 0, 0), 1) == 1
    assert instances.moving_sphere_coverage((3, 0, 5), down, (0, 0, 0), (0, 0, 0), 1) == 0
    # Sideways at speed 4 through a ball of diameter 2: a ray on the path sees it half
    # the time.
    assert instances.moving_sphere_coverage((0, 0, 5), down, (-2, 0, 0), (4, 0, 0),
                                            1) == pytest.approx(0.5)


# ---------------------------------------------------------------------------------------
# Refitting a deforming mesh
# ---------------------------------------------------------------------------------------

def test_a_refit_tree_holds_its_triangles_and_costs_more_as_they_wander(small_teapot):
    tree = instances.build_tree(small_teapot.min(axis=1), small_teapot.max(axis=1))
    same = instances.refit(tree, small_teapot.min(axis=1), small_teapot.max(axis=1))
    assert np.array_equal(same.lower, tree.lower) and np.array_equal(same.upper, tree.upper)
    costs = []
    for amount in (0.0, 0.3, 1.0, 3.0):
        moved = instances.twisted(small_teapot, amount)
        refitted = instances.refit(tree, moved.min(axis=1), moved.max(axis=1))
        for node in range(len(refitted.count)):  # every box holds what is below it
            if refitted.count[node] > 0:
                held = refitted.order[refitted.first[node]:
                                      refitted.first[node] + refitted.count[node]]
                assert np.all(moved[held].min(axis=(0, 1)) >= refitted.lower[node])
                assert np.all(moved[held].max(axis=(0, 1)) <= refitted.upper[node])
        rebuilt = instances.build_tree(moved.min(axis=1), moved.max(axis=1))
        costs.append((instances.sah_cost(refitted), instances.sah_cost(rebuilt)))
    assert costs[0][0] == pytest.approx(costs[0][1])
    refit_costs = [c[0] / c[1] for c in costs]
    # Measured: 1.00, 1.03, 1.13, 1.18 times the rebuilt tree's cost.
    assert refit_costs == sorted(refit_costs) and refit_costs[-1] > 1.1, refit_costs
