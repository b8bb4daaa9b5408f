"""Why chapter 04's shader intersects spheres geometrically: the two textbook forms,
run in float32 as a GPU would, against float64.

Both forms compute the same number, the square of the half chord,
    h^2 = r^2 - (distance from the centre to the ray)^2,
and take its square root. The quadratic form gets it as b^2 - c, where b^2 and c are
both close to D^2 for a sphere at distance D; the geometric form subtracts vectors of
length D and squares only the (small) result. In float32 the first loses digits like
(D/r)^2, the second like D/r.

    python python_prototypes/reference/spheres_numerics.py --figure numerics.png
"""

import argparse

import numpy as np

RADIUS = 1.0
PANEL_DISTANCE = 1500.0  # the sphere's distance in the three pictures (--distance)
PIXELS = 96


def rays_at_sphere(distance, pixels, dtype):
    """A camera at the origin looking at a sphere of RADIUS at `distance` (in a direction
    off the axes, so no coordinate is conveniently zero), the field of view 1.5x the
    sphere's width; unit directions (pixels, pixels, 3) and the sphere's centre."""
    forward = np.array([0.3, 0.2, -1.0]) / np.linalg.norm([0.3, 0.2, -1.0])
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half_width = 1.5 * RADIUS / distance
    offsets = ((np.arange(pixels) + 0.5) / pixels - 0.5) * 2.0 * half_width
    x, y = np.meshgrid(offsets, -offsets)
    directions = forward + x[..., np.newaxis] * right + y[..., np.newaxis] * up
    directions /= np.linalg.norm(directions, axis=-1, keepdims=True)
    center = forward * distance
    return directions.astype(dtype), center.astype(dtype)


def half_chord_squared_quadratic(directions, center, radius):
    """b^2 - c with b = (o - c).d, c = |o - c|^2 - r^2 and the ray origin o = 0."""
    offset = -center
    b = directions @ offset
    c = offset @ offset - radius * radius
    return b * b - c


def half_chord_squared_geometric(directions, center, radius):
    """r^2 - |closest point to centre|^2, the closest point found by projection."""
    t_closest = directions @ center
    closest_to_center = center - t_closest[..., np.newaxis] * directions
    miss_by_squared = np.sum(closest_to_center * closest_to_center, axis=-1)
    return radius * radius - miss_by_squared


def normal_colors(directions, center, radius, half_chord_squared):
    """The chapter's picture: normal as colour where h^2 >= 0, dark grey elsewhere."""
    directions = directions.astype(np.float64)
    hit = half_chord_squared >= 0
    t = directions @ center.astype(np.float64) - np.sqrt(np.maximum(half_chord_squared, 0))
    normals = (t[..., np.newaxis] * directions - center.astype(np.float64)) / radius
    colors = np.clip(0.5 * normals + 0.5, 0, 1)
    return np.where(hit[..., np.newaxis], colors, 0.15)


def relative_errors(distances):
    """Median |h^2(float32) - h^2(float64)| / r^2 over the rays that hit, per form."""
    results = {"quadratic": [], "geometric": []}
    forms = {"quadratic": half_chord_squared_quadratic,
             "geometric": half_chord_squared_geometric}
    for distance in distances:
        d64, c64 = rays_at_sphere(distance, 64, np.float64)
        d32, c32 = rays_at_sphere(distance, 64, np.float32)
        exact = half_chord_squared_geometric(d64, c64, RADIUS)
        hit = exact > 0
        for name, form in forms.items():
            approx = form(d32, c32, np.float32(RADIUS)).astype(np.float64)
            results[name].append(np.median(np.abs(approx - exact)[hit]) / RADIUS ** 2)
    return results


def draw(path, panel_distance=PANEL_DISTANCE):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(1, 4, figsize=(13, 3.4), dpi=110,
                                gridspec_kw={"width_ratios": [1, 1, 1, 1.5]})
    d64, c64 = rays_at_sphere(panel_distance, PIXELS, np.float64)
    d32, c32 = rays_at_sphere(panel_distance, PIXELS, np.float32)
    r32 = np.float32(RADIUS)
    panels = [("float64 (either form)", d64, c64,
               half_chord_squared_geometric(d64, c64, RADIUS)),
              ("float32, quadratic: b² − c", d32, c32,
               half_chord_squared_quadratic(d32, c32, r32)),
              ("float32, geometric", d32, c32,
               half_chord_squared_geometric(d32, c32, r32))]
    for axis, (title, directions, center, h2) in zip(axes, panels):
        axis.imshow(normal_colors(directions, center, RADIUS, h2.astype(np.float64)),
                    interpolation="nearest")
        axis.set_title(title, fontsize=10)
        axis.set_xticks([])
        axis.set_yticks([])
    axes[1].set_xlabel(f"a sphere of radius 1 at distance {panel_distance:g}", fontsize=9)

    distances = np.geomspace(3, 3e4, 25)
    errors = relative_errors(distances)
    plot = axes[3]
    plot.loglog(distances, errors["quadratic"], "o-", markersize=3, label="quadratic")
    plot.loglog(distances, errors["geometric"], "s-", markersize=3, label="geometric")
    plot.axhline(1.0, color="0.5", linestyle=":", linewidth=1)
    plot.text(distances[0], 1.3, "error as large as r²: noise", fontsize=8, color="0.4")
    plot.set_xlabel("distance / radius")
    plot.set_ylabel("median error of h² / r² (float32)")
    plot.set_title("the error grows like (D/r)² or like D/r", fontsize=10)
    plot.legend(fontsize=8, loc="lower right")
    plot.grid(True, which="major", alpha=0.3)
    figure.tight_layout()
    figure.savefig(path, bbox_inches="tight")
    plt.close(figure)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--figure", required=True, help="write the figure to this file")
    parser.add_argument("--distance", type=float, default=PANEL_DISTANCE,
                        help="the sphere's distance (radius 1) in the pictures")
    args = parser.parse_args(argv)
    draw(args.figure, args.distance)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
