"""The geometric ray-sphere intersection of chapter 04, drawn in the plane that holds
the ray and the sphere's centre.

    python python_prototypes/reference/spheres_diagram.py --figure diagram.png
"""

import argparse

import numpy as np


def draw(path, miss_by):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    origin = np.array([0.0, 0.0])
    direction = np.array([1.0, 0.0])
    radius = 1.0
    t_closest = 3.2
    center = origin + t_closest * direction + np.array([0.0, miss_by])
    closest = origin + t_closest * direction
    half_chord = np.sqrt(radius ** 2 - miss_by ** 2)
    enter = origin + (t_closest - half_chord) * direction
    leave = origin + (t_closest + half_chord) * direction

    figure, axis = plt.subplots(figsize=(7.5, 3.6), dpi=120)
    axis.add_patch(plt.Circle(center, radius, facecolor="tab:blue", alpha=0.12,
                              edgecolor="tab:blue", linewidth=1.5))
    axis.annotate("", xy=origin + 5.2 * direction, xytext=origin,
                  arrowprops=dict(arrowstyle="->", color="tab:orange", linewidth=1.8))
    axis.text(*(origin + [0.0, 0.1]), "ray origin", ha="left", fontsize=9)
    axis.text(5.0, 0.08, "ray", color="tab:orange", fontsize=10)

    def segment(a, b, color, label, offset, **style):
        axis.plot(*np.stack([a, b]).T, color=color, linewidth=2, **style)
        middle = (np.asarray(a) + np.asarray(b)) / 2 + offset
        axis.text(*middle, label, color=color, fontsize=10, ha="center")

    axis.plot(*np.stack([origin, center]).T, color="0.45", linestyle="--", linewidth=1)
    axis.text(*(center * 0.45 + [-0.2, 0.15]), "toCenter", color="0.35", fontsize=10)
    # Lengths along the ray are drawn as dimension lines just below and above it.
    below, above = np.array([0.0, -0.14]), np.array([0.0, 0.12])
    segment(origin + below, closest + below, "tab:green",
            "tClosest = dot(toCenter, direction)", [-0.5, -0.5])
    segment(enter + above, closest + above, "tab:purple", "halfChord", [-0.1, 0.1])
    segment(closest, center, "tab:red", "missBy", [0.38, -0.05])
    axis.plot(*np.stack([center, enter]).T, color="tab:blue", linewidth=1.2)
    upper = 0.75 * center + 0.25 * enter  # label the radius near its upper end
    axis.text(upper[0] - 0.1, upper[1] - 0.1, "radius", color="tab:blue", fontsize=10,
              ha="right")
    for point, name in [(enter, "t = tClosest − halfChord"),
                        (leave, "tClosest + halfChord")]:
        axis.plot(*point, "o", color="tab:purple", markersize=5, zorder=5)
        axis.text(point[0], point[1] - 0.36, name, ha="center", fontsize=8,
                  color="tab:purple")
    axis.plot(*center, "o", color="tab:blue", markersize=4)
    axis.text(center[0] + 0.07, center[1] + 0.07, "centre", color="tab:blue", fontsize=9)
    axis.plot(*closest, "o", color="tab:green", markersize=4, zorder=5)
    axis.text(-0.2, 1.3, "halfChord² + missBy² = radius²", fontsize=10,
              bbox=dict(facecolor="white", edgecolor="0.8"))

    axis.set_aspect("equal")
    axis.set_xlim(-0.3, 5.6)
    axis.set_ylim(-0.9, 1.1 + miss_by)
    axis.axis("off")
    figure.tight_layout()
    figure.savefig(path, bbox_inches="tight")
    plt.close(figure)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--figure", required=True, help="write the figure to this file")
    parser.add_argument("--miss-by", type=float, default=0.6,
                        help="how far the ray passes from the centre (radius 1)")
    args = parser.parse_args(argv)
    draw(args.figure, args.miss_by)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
