"""Instances in numpy: a mesh's tree built once, placed many times, and a tree over the
placements. The prototype of the instances chapter, in float64, with every ray at once.

A placement is an affine map, world = A object + b, written in a scene as steps applied
in the order written, as Mitsuba composes its to_world chain: `scale 2 rotate_y 30
translate 0 1 0` scales, then turns, then moves, so its matrix is T R S (the last step
on the left; names read as pbrt's, world_from_object).

Two levels of trees:

- the bottom level (a BLAS) is the object's own SAH tree over its triangles, in object
  space, built once however often the object is placed;
- the top level (the TLAS) is an SAH tree over the instances' world boxes (the eight
  corners of the object's box, carried to the world), rebuilt whenever an instance moves.

A ray that reaches an instance in the TLAS is carried into the object's space by the
inverse map, origin and direction alike, and the direction is *not* normalised: the
point at parameter t is then the same point in both spaces, so the object's tree can
be walked with the world's nearest t so far and the t it finds is already a world
distance. Normalising the direction there would measure t in object units, which is
wrong for every scaled instance (planted as a bug in the checks).

A surface normal goes back to the world by the inverse transpose of A: a normal is
perpendicular to the surface's tangents, and A^-T keeps it so (A itself does not once
A scales unevenly). Where A mirrors (det A < 0) a triangle's corners turn the other
way round, so the same triangles written out in the world ("flattened") keep their
fronts in front only with two corners swapped; A^-T needs no such care.

Motion blur: an instance may move by `velocity` over the camera's shutter; each ray has a
time in [0, 1] (a fraction of the shutter), and the instance is then at b + time
velocity. The TLAS holds each moving instance's box swept over the shutter, so a ray of
any time finds it. A pixel's value is the average over the shutter; for a moving sphere,
the fraction of the shutter during which a ray hits it has a closed form
(moving_sphere_coverage), which the checks hold the sampled average to.

A deforming mesh keeps its tree's shape and has its boxes refitted, bottom up, instead
of rebuilding: cheap, but the tree's SAH cost climbs as the triangles wander from the
places it was split for (refit, sah_cost).

    python python_prototypes/instances.py          # a ray through a small field of teapots
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass, field

import numpy as np

from python_prototypes import scene_io
from python_prototypes.scene_cast import sphere_t

NODE_COST = 1.0      # the SAH's prices, as chapter 14's BvhOptions
TRIANGLE_COST = 1.0
BINS = 16
MAX_LEAF = 4
NOTHING = -(2 ** 31)  # no primitive found (spheres are -1, -2, ...)


# ---------------------------------------------------------------------------------------
# Placements
# ---------------------------------------------------------------------------------------

@dataclass
class Placement:
    """world = linear @ object + offset (+ time * velocity while the shutter is open)."""
    linear: np.ndarray = field(default_factory=lambda: np.eye(3))
    offset: np.ndarray = field(default_factory=lambda: np.zeros(3))
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def then(self, linear=None, offset=None) -> "Placement":
        """This placement followed by x -> linear x + offset."""
        linear = np.eye(3) if linear is None else np.asarray(linear, dtype=np.float64)
        offset = np.zeros(3) if offset is None else np.asarray(offset, dtype=np.float64)
        return Placement(linear @ self.linear, linear @ self.offset + offset,
                         linear @ self.velocity)

    def offset_at(self, time) -> np.ndarray:
        """The translation at `time` (an array of times gives one row each)."""
        time = np.asarray(time, dtype=np.float64)
        return self.offset + time[..., None] * self.velocity

    def to_world(self, points, time=0.0) -> np.ndarray:
        return np.asarray(points) @ self.linear.T + self.offset_at(time)

    def ray_to_object(self, origins, directions, time=0.0):
        """The rays in the object's space: the inverse map on the origin (a point) and on
        the direction (a vector, no translation), which is left unnormalised."""
        object_from_world = np.linalg.inv(self.linear)
        origins = (np.asarray(origins) - self.offset_at(time)) @ object_from_world.T
        return origins, np.asarray(directions) @ object_from_world.T

    def normal_to_world(self, normals) -> np.ndarray:
        """Object-space normals to unit world normals, by the inverse transpose."""
        world = np.asarray(normals) @ np.linalg.inv(self.linear)  # n^T A^-1 = (A^-T n)^T
        return world / np.linalg.norm(world, axis=-1, keepdims=True)

    @property
    def mirrors(self) -> bool:
        return bool(np.linalg.det(self.linear) < 0.0)


def placement_from_words(words) -> Placement:
    """A placement from the words after `instance OBJECT`, read by the scene reader
    (scene_io.read_instance: scale S | scale X Y Z, rotate X Y Z DEGREES, rotate_y
    DEGREES, translate X Y Z in the order written, moving X Y Z). A mistake raises its
    scene_io.SceneError."""
    instance = scene_io.read_instance(["placed", *words])
    world = instance.world_from_object()
    return Placement(world[:3, :3], world[:3, 3], np.asarray(instance.motion, dtype=np.float64))


# ---------------------------------------------------------------------------------------
# Trees: the same binned-SAH build for triangles (the BLAS) and instances (the TLAS)
# ---------------------------------------------------------------------------------------

@dataclass
class Tree:
    """A BVH over primitives with boxes, depth first (node 0 is the root, a node's left
    child follows it). A leaf has count > 0 and holds order[first : first + count]; an
    inner node has count 0 and its right child at index right."""
    lower: np.ndarray  # (nodes, 3)
    upper: np.ndarray
    first: np.ndarray
    count: np.ndarray
    right: np.ndarray
    order: np.ndarray  # primitive indices in leaf order


def half_area(lower, upper) -> np.ndarray:
    size = np.maximum(np.asarray(upper) - np.asarray(lower), 0.0)
    return size[..., 0] * size[..., 1] + size[..., 1] * size[..., 2] \
        + size[..., 2] * size[..., 0]


def best_split(lower, upper, bins):
    """(cost, axis, left mask) of the cheapest binned-SAH plane on any axis, or None."""
    centroids = 0.5 * (lower + upper)
    parent = half_area(lower.min(axis=0), upper.max(axis=0))
    best = None
    for axis in range(3):
        low, high = centroids[:, axis].min(), centroids[:, axis].max()
        if not high > low:
            continue
        bin_of = np.minimum(((centroids[:, axis] - low) * (bins / (high - low))).astype(int),
                            bins - 1)
        for plane in range(bins - 1):
            left = bin_of <= plane
            n_left = int(left.sum())
            if n_left == 0 or n_left == len(left):
                continue
            area_left = half_area(lower[left].min(axis=0), upper[left].max(axis=0))
            area_right = half_area(lower[~left].min(axis=0), upper[~left].max(axis=0))
            cost = NODE_COST + TRIANGLE_COST * (area_left * n_left + area_right
                                                * (len(left) - n_left)) / max(parent, 1e-300)
            if best is None or cost < best[0]:
                best = (cost, axis, left)
    return best


def build_tree(lower, upper, bins=BINS, max_leaf=MAX_LEAF) -> Tree:
    """The SAH tree over primitives with boxes (lower[i], upper[i])."""
    lower, upper = np.asarray(lower, dtype=np.float64), np.asarray(upper, dtype=np.float64)
    nodes, order = [], []

    def build_range(indices):
        node = len(nodes)
        nodes.append([lower[indices].min(axis=0), upper[indices].max(axis=0), 0, 0, -1])
        split = best_split(lower[indices], upper[indices], bins) if len(indices) > 1 else None
        if len(indices) <= max_leaf and (split is None or split[0] >= TRIANGLE_COST
                                         * len(indices)):
            nodes[node][2:4] = [len(order), len(indices)]
            order.extend(indices.tolist())
            return
        halves = (indices[:len(indices) // 2], indices[len(indices) // 2:]) if split is None \
            else (indices[split[2]], indices[~split[2]])
        build_range(halves[0])
        nodes[node][4] = len(nodes)
        build_range(halves[1])

    build_range(np.arange(len(lower)))
    columns = list(zip(*nodes))
    return Tree(np.array(columns[0]), np.array(columns[1]), np.array(columns[2]),
                np.array(columns[3]), np.array(columns[4]), np.array(order, dtype=int))


def sah_cost(tree: Tree) -> float:
    """The tree's SAH cost: what a ray through the root box pays on average, in node
    visits and primitive tests (chapter 14's BvhStats::sahCost)."""
    weight = half_area(tree.lower, tree.upper) / half_area(tree.lower[0], tree.upper[0])
    return float(np.sum(weight * np.where(tree.count > 0, TRIANGLE_COST * tree.count,
                                          NODE_COST)))


def refit(tree: Tree, lower, upper) -> Tree:
    """The same tree with its boxes made anew around moved primitives, children before
    parents (depth first order puts every child after its parent, so backwards works)."""
    new_lower, new_upper = tree.lower.copy(), tree.upper.copy()
    for node in range(len(tree.count) - 1, -1, -1):
        if tree.count[node] > 0:
            held = tree.order[tree.first[node]: tree.first[node] + tree.count[node]]
            new_lower[node], new_upper[node] = lower[held].min(axis=0), upper[held].max(axis=0)
        else:
            children = [node + 1, tree.right[node]]
            new_lower[node] = new_lower[children].min(axis=0)
            new_upper[node] = new_upper[children].max(axis=0)
    return Tree(new_lower, new_upper, tree.first, tree.count, tree.right, tree.order)


def twisted(triangles, amount) -> np.ndarray:
    """The triangles (n, 3, 3) turned about the y axis by amount x height radians: a
    mesh deforming smoothly, for refitting."""
    corners = triangles.reshape(-1, 3)
    angle = amount * corners[:, 1]
    c, s = np.cos(angle), np.sin(angle)
    turned = np.stack([c * corners[:, 0] + s * corners[:, 2], corners[:, 1],
                       -s * corners[:, 0] + c * corners[:, 2]], axis=1)
    return turned.reshape(triangles.shape)


def twisted_about_middle(points, vectors, degrees):
    """Chapter 27's twist (refit.cpp's twistObjects): points (n, 3) turned about the
    upright line through the middle of their box, by `degrees` at its top and none at
    its bottom, evenly in between; vectors (n, 3), one a point (its normal), turned
    with it. Returns (points, vectors)."""
    points, vectors = np.asarray(points, np.float64), np.asarray(vectors, np.float64)
    low, high = points.min(axis=0), points.max(axis=0)
    middle = (low + high) / 2
    angle = np.radians(degrees) * (points[:, 1] - low[1]) / max(high[1] - low[1], 1e-30)
    c, s = np.cos(angle), np.sin(angle)

    def turn(v):
        return np.stack([c * v[:, 0] + s * v[:, 2], v[:, 1], -s * v[:, 0] + c * v[:, 2]], 1)
    return turn(points - middle) + middle, turn(vectors)


def box_entry(lower, upper, origins, directions, t_far):
    """Whether each ray enters the box [lower, upper] before t_far (slab test)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        inverse = 1.0 / directions
        t0, t1 = (lower - origins) * inverse, (upper - origins) * inverse
    t_near = np.nanmax(np.minimum(t0, t1), axis=-1)
    t_exit = np.nanmin(np.maximum(t0, t1), axis=-1)
    return (t_near <= t_exit) & (t_exit >= 0.0) & (t_near < t_far)


def walk(tree: Tree, origins, directions, best_t, test_leaf):
    """Every ray through the tree at once: a node passes on the rays that enter its box
    before their nearest hit so far; a leaf calls test_leaf(primitives, rays), which
    lowers best_t (updated in place) where it finds nearer hits."""
    stack = [(0, np.arange(len(best_t)))]
    while stack:
        node, rays = stack.pop()
        rays = rays[box_entry(tree.lower[node], tree.upper[node], origins[rays],
                              directions[rays], best_t[rays])]
        if len(rays) == 0:
            continue
        if tree.count[node] > 0:
            test_leaf(tree.order[tree.first[node]: tree.first[node] + tree.count[node]], rays)
        else:
            stack += [(tree.right[node], rays), (node + 1, rays)]


# ---------------------------------------------------------------------------------------
# Objects, instances and the scene
# ---------------------------------------------------------------------------------------

def triangle_t(corners, origins, directions):
    """Möller-Trumbore for rays against one triangle (3, 3): t, or inf for a miss. t is
    in units of each direction's length, so an unnormalised direction is fine."""
    edge1, edge2 = corners[1] - corners[0], corners[2] - corners[0]
    p = np.cross(directions, edge2)
    determinant = p @ edge1
    with np.errstate(divide="ignore", invalid="ignore"):
        inverse = 1.0 / determinant
        to_origin = origins - corners[0]
        u = np.einsum("ij,ij->i", to_origin, p) * inverse
        q = np.cross(to_origin, edge1)
        v = np.einsum("ij,ij->i", directions, q) * inverse
        t = (q @ edge2) * inverse
    hit = (np.abs(determinant) > 1e-300) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-9)
    return np.where(hit, t, np.inf)


@dataclass
class SceneObject:
    """What `object NAME begin ... end` defines: triangles (n, 3, 3) under its own tree,
    and spheres ((centre, radius) pairs, few, tested one by one as the chapters do)."""
    triangles: np.ndarray
    spheres: list = field(default_factory=list)
    tree: Tree = None

    def __post_init__(self):
        self.triangles = np.asarray(self.triangles, dtype=np.float64).reshape(-1, 3, 3)
        if self.tree is None and len(self.triangles):
            self.tree = build_tree(self.triangles.min(axis=1), self.triangles.max(axis=1))

    def box(self):
        corners = [self.triangles.reshape(-1, 3)] + [
            np.array([np.subtract(c, r), np.add(c, r)]) for c, r in self.spheres]
        points = np.concatenate(corners)
        return points.min(axis=0), points.max(axis=0)


@dataclass
class Instance:
    object: int
    placement: Placement


def world_box(scene_object: SceneObject, placement: Placement, swept=True):
    """The instance's world box: the object box's eight corners carried to the world
    (at the shutter's opening and, when it moves and swept, at its closing too)."""
    low, high = scene_object.box()
    corners = np.array([[(low, high)[(k >> axis) & 1][axis] for axis in range(3)]
                        for k in range(8)])
    points = [placement.to_world(corners, 0.0)]
    if swept and np.any(placement.velocity):
        points.append(placement.to_world(corners, 1.0))
    points = np.concatenate(points)
    return points.min(axis=0), points.max(axis=0)


@dataclass
class Hits:
    """Per ray: world distance t (inf: a miss), the instance, the primitive (a triangle's
    index, or -1 - k for the object's sphere k) and the unit world normal."""
    t: np.ndarray
    instance: np.ndarray
    primitive: np.ndarray
    normal: np.ndarray


class InstancedScene:
    """Objects, each with its own tree, placed by instances under one top-level tree."""

    def __init__(self, objects, instances):
        self.objects, self.instances = list(objects), list(instances)
        boxes = [world_box(self.objects[i.object], i.placement) for i in self.instances]
        self.tlas = build_tree(np.array([b[0] for b in boxes]), np.array([b[1] for b in boxes]))

    def intersect(self, origins, directions, times=None) -> Hits:
        origins = np.broadcast_to(np.asarray(origins, dtype=np.float64), np.shape(directions))
        directions = np.asarray(directions, dtype=np.float64)
        times = np.zeros(len(directions)) if times is None else np.asarray(times)
        hits = Hits(np.full(len(directions), np.inf), np.full(len(directions), -1),
                    np.zeros(len(directions), dtype=int), np.zeros_like(directions))
        object_normals = np.zeros_like(directions)

        def test_instances(instance_indices, rays):
            for index in instance_indices:
                self._test_instance(index, rays, origins, directions, times, hits,
                                    object_normals)

        walk(self.tlas, origins, directions, hits.t, test_instances)
        for index, instance in enumerate(self.instances):
            mine = hits.instance == index
            if np.any(mine):
                hits.normal[mine] = instance.placement.normal_to_world(object_normals[mine])
        return hits

    def _test_instance(self, index, rays, origins, directions, times, hits, object_normals):
        """Tests `rays` (indices) against instance `index` in its object's space, where
        t means the same points as in the world: the world's nearest hits so far prune
        the object's tree, and a nearer hit found there is kept as it is."""
        instance = self.instances[index]
        scene_object = self.objects[instance.object]
        local_origins, local_directions = instance.placement.ray_to_object(
            origins[rays], directions[rays], times[rays])
        best = hits.t[rays].copy()
        primitive = np.full(len(rays), NOTHING)
        normal = np.zeros((len(rays), 3))

        def keep(t, local_rays, which, normals):
            nearer = t < best[local_rays]
            chosen = local_rays[nearer]
            best[chosen], primitive[chosen] = t[nearer], which
            normal[chosen] = np.broadcast_to(normals, (len(t), 3))[nearer]

        def test_triangles(triangle_indices, local_rays):
            for triangle in triangle_indices:
                corners = scene_object.triangles[triangle]
                keep(triangle_t(corners, local_origins[local_rays],
                                local_directions[local_rays]), local_rays, triangle,
                     np.cross(corners[1] - corners[0], corners[2] - corners[0]))

        if scene_object.tree is not None:
            walk(scene_object.tree, local_origins, local_directions, best, test_triangles)
        everyone = np.arange(len(rays))
        for k, (centre, radius) in enumerate(scene_object.spheres):
            t = sphere_t(np.asarray(centre, dtype=np.float64), radius, local_origins,
                         local_directions)
            points = local_origins + np.where(np.isfinite(t), t, 0.0)[:, None] \
                * local_directions
            keep(t, everyone, -1 - k, points - np.asarray(centre))
        found = primitive != NOTHING
        chosen = rays[found]
        hits.t[chosen], hits.instance[chosen] = best[found], index
        hits.primitive[chosen], object_normals[chosen] = primitive[found], normal[found]

    def flattened_triangles(self, time=0.0) -> np.ndarray:
        """Every instance's triangles written out in the world (n, 3, 3), a mirrored
        instance's with two corners swapped so that its fronts stay in front."""
        written = []
        for instance in self.instances:
            corners = instance.placement.to_world(self.objects[instance.object].triangles, time)
            written.append(corners[:, [0, 2, 1]] if instance.placement.mirrors else corners)
        return np.concatenate(written)

    def memory_words(self) -> dict:
        """What the two levels keep, in 4-byte words as the GPU would store them: a node
        is 8 (two corners, first, count); a triangle 9; an instance 12 (a 3 x 4 inverse
        map) + 1 (its object)."""
        nodes = sum(len(o.tree.count) for o in self.objects if o.tree is not None)
        triangles = sum(len(o.triangles) for o in self.objects)
        return {"objects": 8 * nodes + 9 * triangles, "instances": 13 * len(self.instances),
                "top level": 8 * len(self.tlas.count)}


def brute_force(scene: InstancedScene, origins, directions, times=None) -> np.ndarray:
    """The nearest world t of each ray against every instance's world triangles and
    spheres, no trees: what the two levels must agree with."""
    directions = np.asarray(directions, dtype=np.float64)
    origins = np.broadcast_to(np.asarray(origins, dtype=np.float64), directions.shape)
    times = np.zeros(len(directions)) if times is None else np.asarray(times)
    best = np.full(len(directions), np.inf)
    for instance in scene.instances:
        scene_object = scene.objects[instance.object]
        for time in np.unique(times):
            rays = times == time
            for corners in instance.placement.to_world(scene_object.triangles, time):
                best[rays] = np.minimum(best[rays], triangle_t(corners, origins[rays],
                                                               directions[rays]))
            # Spheres in the object's space (an unevenly scaled one is an ellipsoid).
            local_origins, local_directions = instance.placement.ray_to_object(
                origins[rays], directions[rays], time)
            for centre, radius in scene_object.spheres:
                best[rays] = np.minimum(best[rays], sphere_t(
                    np.asarray(centre, dtype=np.float64), radius, local_origins,
                    local_directions))
    return best


# ---------------------------------------------------------------------------------------
# Motion blur's closed form
# ---------------------------------------------------------------------------------------

def moving_sphere_coverage(origin, direction, centre, velocity, radius) -> float:
    """The fraction of the shutter (time 0 to 1) during which the line through `origin`
    along `direction` meets a sphere whose centre moves from `centre` by `velocity`.
    The squared distance from the centre to the line is a quadratic in time; the sphere
    is met while it is below radius^2."""
    direction = np.asarray(direction, dtype=np.float64)
    direction = direction / np.linalg.norm(direction)

    def across(vector):  # the part of a vector perpendicular to the line
        vector = np.asarray(vector, dtype=np.float64)
        return vector - (vector @ direction) * direction

    start, drift = across(np.subtract(centre, origin)), across(velocity)
    a, half_b, c = drift @ drift, start @ drift, start @ start - radius * radius
    if a == 0.0:
        return 1.0 if c < 0.0 else 0.0
    discriminant = half_b * half_b - a * c
    if discriminant <= 0.0:
        return 0.0
    root = math.sqrt(discriminant)
    enter, leave = (-half_b - root) / a, (-half_b + root) / a
    return max(0.0, min(leave, 1.0) - max(enter, 0.0))


# ---------------------------------------------------------------------------------------
# A small demonstration
# ---------------------------------------------------------------------------------------

def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--side", type=int, default=4, help="teapots along each side")
    arguments = parser.parse_args(argv)
    from python_prototypes import teapot
    patches, control_points = teapot.load_patches()
    positions, _, triangles = teapot.tessellate(patches, control_points, 4)[:3]
    mesh = SceneObject(positions[triangles])
    instances = [Instance(0, placement_from_words(
        ["rotate_y", str(37 * i), "translate", str(8 * (i % arguments.side)), "0",
         str(8 * (i // arguments.side))])) for i in range(arguments.side ** 2)]
    scene = InstancedScene([mesh], instances)
    words = scene.memory_words()
    print(f"{len(instances)} teapots of {len(mesh.triangles)} triangles; "
          f"words kept: {words}; flattened: {9 * len(instances) * len(mesh.triangles)}")
    hits = scene.intersect(np.array([[-20.0, 2.0, -20.0]]), np.array([[1.0, -0.05, 1.0]]))
    print(f"a ray from the corner: t = {hits.t[0]:.4f}, instance {hits.instance[0]}, "
          f"normal {np.round(hits.normal[0], 4)}")


if __name__ == "__main__":
    main()
