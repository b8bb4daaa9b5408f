"""Barycentric coordinates, as Moller-Trumbore computes them in chapter 06: a point of
the triangle's plane is p0 + u (p1 - p0) + v (p2 - p0), and it is inside the triangle
when u >= 0, v >= 0 and u + v <= 1.

    python python_prototypes/reference/triangles_diagram.py --figure barycentric.png
"""

import argparse

import numpy as np


def draw(path, u, v):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    p0, p1, p2 = np.array([0.0, 0.0]), np.array([3.0, 0.4]), np.array([0.9, 2.4])
    e1, e2 = p1 - p0, p2 - p0

    def at(a, b):  # the plane point with coordinates (u, v) = (a, b)
        return p0 + a * e1 + b * e2

    figure, axis = plt.subplots(figsize=(6.4, 4.4), dpi=120)
    # Lines of constant u and constant v, beyond the triangle too.
    for value in np.arange(-0.5, 1.51, 0.25):
        for line in (np.stack([at(value, -0.5), at(value, 1.5)]),
                     np.stack([at(-0.5, value), at(1.5, value)])):
            axis.plot(*line.T, color="0.88", linewidth=0.8, zorder=0)
    axis.fill(*np.stack([p0, p1, p2]).T, color="tab:blue", alpha=0.15)
    axis.plot(*np.stack([p0, p1, p2, p0]).T, color="tab:blue", linewidth=2)
    for point, name, offset in [(p0, "p0", (-0.25, -0.2)), (p1, "p1", (0.08, -0.15)),
                                (p2, "p2", (-0.1, 0.12))]:
        axis.text(point[0] + offset[0], point[1] + offset[1], name, fontsize=11,
                  color="tab:blue")
    for edge, name, color in [(e1, "edge1", "tab:green"), (e2, "edge2", "tab:purple")]:
        axis.annotate("", xy=p0 + edge, xytext=p0,
                      arrowprops=dict(arrowstyle="->", color=color, linewidth=1.8))
        axis.text(*(p0 + 0.5 * edge + np.array([0.08, -0.2] if name == "edge1"
                                               else [-0.55, 0.0])),
                  name, color=color, fontsize=10)
    point = at(u, v)
    axis.plot(*np.stack([p0, p0 + u * e1, point]).T, color="0.3", linestyle="--",
              linewidth=1)
    axis.plot(*point, "o", color="tab:red", markersize=7)
    axis.text(point[0] + 0.1, point[1] + 0.05,
              f"hit: p0 + {u:g}·edge1 + {v:g}·edge2", color="tab:red", fontsize=10)
    for (a, b), label in [((1.05, -0.3), "v < 0"), ((-0.45, 0.55), "u < 0"),
                          ((0.85, 0.75), "u + v > 1")]:
        axis.text(*at(a, b), label, fontsize=10, color="0.35", ha="center")
    axis.set_aspect("equal")
    axis.set_xlim(-1.0, 4.2)
    axis.set_ylim(-0.9, 3.0)
    axis.axis("off")
    axis.set_title("Barycentric coordinates (u, v): inside when u ≥ 0, v ≥ 0, u + v ≤ 1",
                   fontsize=10)
    figure.tight_layout()
    figure.savefig(path, bbox_inches="tight")
    plt.close(figure)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--figure", required=True, help="write the figure to this file")
    parser.add_argument("--u", type=float, default=0.45, help="the marked point's u")
    parser.add_argument("--v", type=float, default=0.3, help="the marked point's v")
    args = parser.parse_args(argv)
    draw(args.figure, args.u, args.v)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
