"""The instances chapter's figures, drawn from the numpy prototype (instances.py):

    python python_prototypes/instances_figures.py --figure levels.png --which levels
    python python_prototypes/instances_figures.py --figure motion.png --which motion
    python python_prototypes/instances_figures.py --figure refit.png --which refit

levels: one object and its own tree in object space (left); six placements of it in the
  world, their world boxes under the top-level tree, and a ray (right); the ray carried
  into the object's space for the instance it meets is drawn on the left, where the
  object's tree is walked;
motion: the share of the shutter during which rays across a moving ball's path meet it,
  the closed form against the two levels at random times;
refit: a twisting teapot's tree refitted against rebuilt, SAH cost as the twist grows."""

from __future__ import annotations

import argparse

import numpy as np

from python_prototypes import bvh_2d, instances, teapot
from python_prototypes.figure_file import new_figure, save_figure_file

# A flat arrow of triangles in the plane z = 0: its shape shows which way it is placed.
ARROW = np.array([[[0.0, 0.0], [2.0, 0.0], [2.0, 0.6]], [[0.0, 0.0], [2.0, 0.6], [0.0, 0.6]],
                  [[2.0, -0.5], [3.0, 0.3], [2.0, 1.1]], [[0.3, 0.6], [0.9, 0.6], [0.6, 1.4]],
                  [[1.2, 0.6], [1.8, 0.6], [1.5, 1.2]], [[0.3, 0.0], [0.9, 0.0], [0.6, -0.7]]])
PLACEMENTS = ["translate 1 1 0", "scale 1.4 rotate 0 0 1 35 translate 6 0.5 0",
              "scale 0.8 rotate 0 0 1 -90 translate 11 5 0", "scale -1 1 1 translate 5 6 0",
              "scale 1.6 0.6 1 rotate 0 0 1 160 translate 12 9.5 0",
              "scale 0.6 rotate 0 0 1 70 translate 2 7 0"]
RAY = (np.array([-0.5, 4.8, 0.0]), np.array([1.0, -0.22, 0.0]))


def draw_box(axes, lower, upper, **style):
    import matplotlib.patches as patches
    axes.add_patch(patches.Rectangle(lower[:2], *(np.asarray(upper) - lower)[:2], fill=False,
                                     **style))


def prisms(flat, depth=0.5):
    """Each flat triangle made a prism from z = -depth to z = depth (caps and side
    walls), so that a ray in the plane z = 0 meets its sides."""
    made = []
    for corners in flat:
        low = np.concatenate([corners, np.full((3, 1), -depth)], axis=1)
        high = np.concatenate([corners, np.full((3, 1), depth)], axis=1)
        made += [low[[0, 2, 1]], high]
        for a, b in ((0, 1), (1, 2), (2, 0)):
            made += [[low[a], low[b], high[b]], [low[a], high[b], high[a]]]
    return np.array(made)


def draw_levels(figure):
    triangles = prisms(ARROW)
    scene = instances.InstancedScene(
        [instances.SceneObject(triangles)],
        [instances.Instance(0, instances.placement_from_words(text.split()))
         for text in PLACEMENTS])
    hits = scene.intersect(RAY[0][None], RAY[1][None])
    found = int(hits.instance[0])

    local = figure.add_subplot(1, 2, 1)
    for node in bvh_2d.nodes_of(bvh_2d.build(ARROW, max_leaf=2)):
        draw_box(local, node.lower, node.upper, edgecolor="#2e6fd8", lw=1.0, alpha=0.7)
    for corners in ARROW:
        local.fill(*corners.T, color="#999999", alpha=0.8)
    origin, direction = scene.instances[found].placement.ray_to_object(RAY[0], RAY[1])
    ends = np.array([origin, origin + hits.t[0] * direction])
    local.plot(*ends[:, :2].T, color="#c0392b", lw=1.5)
    local.plot(*ends[1, :2], "o", color="#c0392b")
    local.set_title(f"object space: the object's own tree, and the ray of instance {found}",
                    fontsize=9)

    world = figure.add_subplot(1, 2, 2)
    tlas = scene.tlas
    for node in range(len(tlas.count)):
        inner = tlas.count[node] == 0
        draw_box(world, tlas.lower[node], tlas.upper[node], lw=1.2 if inner else 0.8,
                 edgecolor="#27ae60" if inner else "#888888", ls="-" if inner else "--")
    for index, instance in enumerate(scene.instances):
        for corners in instance.placement.to_world(triangles):
            world.fill(*corners[:, :2].T, color="#c0392b" if index == found else "#999999",
                       alpha=0.8)
        centre = instance.placement.to_world(np.array([1.5, 0.3, 0.0]))
        world.annotate(str(index), centre[:2] + 0.4, fontsize=8)
    ends = np.array([RAY[0], RAY[0] + hits.t[0] * RAY[1]])
    world.plot(*ends[:, :2].T, color="#c0392b", lw=1.5)
    world.plot(*ends[1, :2], "o", color="#c0392b")
    world.set_title("world: instances, their boxes (dashed) and the top-level tree (green)",
                    fontsize=9)
    for axes in (local, world):
        axes.set_aspect("equal")
        axes.autoscale_view()
        axes.margins(0.08)


def draw_motion(figure):
    ball = instances.SceneObject(np.zeros((0, 3, 3)), spheres=[((0.0, 0.0, 0.0), 1.0)])
    moving = instances.Instance(0, instances.placement_from_words(
        "scale 0.5 translate -2 0 0 moving 4 0 0".split()))
    scene = instances.InstancedScene([ball], [moving])
    down = np.array([0.0, 0.0, -1.0])
    axes = figure.add_subplot(1, 1, 1)
    for height, colour in ((0.0, "#2e6fd8"), (0.35, "#27ae60"), (0.47, "#c0392b")):
        xs = np.linspace(-3.0, 3.0, 241)
        exact = [instances.moving_sphere_coverage((x, height, 10), down, (-2, 0, 0),
                                                  (4, 0, 0), 0.5) for x in xs]
        axes.plot(xs, exact, color=colour, label=f"closed form, rays at y = {height:g}")
        rng = np.random.default_rng(int(height * 100) + 1)
        sampled_x = np.linspace(-2.9, 2.9, 30)
        shares = []
        for x in sampled_x:
            origins = np.tile([x, height, 10.0], (400, 1))
            hits = scene.intersect(origins, np.tile(down, (400, 1)), rng.uniform(size=400))
            shares.append(np.mean(np.isfinite(hits.t)))
        axes.plot(sampled_x, shares, "o", color=colour, ms=3)
    axes.set_xlabel("where the ray crosses the ball's path (x)")
    axes.set_ylabel("share of the shutter the ray meets the ball")
    axes.set_title("a ball of radius 0.5 moving from x = −2 to x = 2: closed form (lines), "
                   "400 random times a ray (dots)", fontsize=9)
    axes.legend(fontsize=8)
    axes.grid(alpha=0.3)


def draw_refit(figure):
    patches, control_points = teapot.load_patches()
    positions, _, indices = teapot.tessellate(patches, control_points, 4)
    mesh = positions[indices]
    tree = instances.build_tree(mesh.min(axis=1), mesh.max(axis=1))
    amounts = np.linspace(0.0, 3.0, 13)
    refitted, rebuilt = [], []
    for amount in amounts:
        moved = instances.twisted(mesh, amount)
        refitted.append(instances.sah_cost(instances.refit(tree, moved.min(axis=1),
                                                           moved.max(axis=1))))
        rebuilt.append(instances.sah_cost(instances.build_tree(moved.min(axis=1),
                                                               moved.max(axis=1))))
    axes = figure.add_subplot(1, 1, 1)
    axes.plot(amounts, refitted, "o-", color="#c0392b", label="refitted (the first tree's shape)")
    axes.plot(amounts, rebuilt, "o-", color="#2e6fd8", label="rebuilt at each step")
    axes.set_xlabel("twist (radians per unit of height)")
    axes.set_ylabel("SAH cost (node visits + triangle tests a ray)")
    axes.set_title(f"a teapot of {len(mesh)} triangles twisting", fontsize=9)
    axes.set_ylim(bottom=0.0)
    axes.legend(fontsize=8)
    axes.grid(alpha=0.3)


FIGURES = {"levels": (draw_levels, (10, 4.4)), "motion": (draw_motion, (7, 4)),
           "refit": (draw_refit, (6.5, 4))}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figure", required=True, help="the PNG to write")
    parser.add_argument("--which", choices=sorted(FIGURES), required=True)
    arguments = parser.parse_args(argv)
    draw, size = FIGURES[arguments.which]
    figure = new_figure(figsize=size, dpi=110)
    draw(figure)
    save_figure_file(figure, arguments.figure)
    print(arguments.figure)


if __name__ == "__main__":
    main()
