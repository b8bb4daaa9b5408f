"""Two diagrams for chapter 05: Lambert's cosine law, and why shadow rays start a
little off the surface (shadow acne). Schematic, not to scale.

    python python_prototypes/reference/shading_diagrams.py --figure shading.png
"""

import argparse

import numpy as np


def draw_lambert(axis, angle_degrees):
    """A beam of parallel light of width 1 covers 1 / cos(angle) of a tilted surface."""
    angle = np.radians(angle_degrees)
    to_light = np.array([np.sin(angle), np.cos(angle)])
    across = np.array([to_light[1], -to_light[0]])  # perpendicular to the beam
    footprint = 1.0 / np.cos(angle)
    axis.plot([-1.6, 1.6], [0, 0], color="0.3", linewidth=2)
    axis.fill_between([-1.6, 1.6], [0, 0], [-0.15, -0.15], color="0.85")
    for s in np.linspace(-0.5, 0.5, 6):  # rays of the beam, arriving at the surface
        start = 2.0 * to_light + s * across
        end = np.array([s * footprint, 0.0])  # where that ray meets the surface
        axis.annotate("", xy=end, xytext=start,
                      arrowprops=dict(arrowstyle="->", color="tab:orange", linewidth=1.2))
    # The beam's width, measured across it, and its footprint on the surface.
    beam_start = 2.0 * to_light
    a, b = beam_start - 0.5 * across, beam_start + 0.5 * across
    axis.plot(*np.stack([a, b]).T, color="tab:orange", linewidth=2.5)
    axis.text(*(b + [0.08, -0.05]), "beam of\nwidth 1", color="tab:orange", ha="left",
              fontsize=9)
    axis.plot([-0.5 * footprint, 0.5 * footprint], [-0.06, -0.06], color="tab:red",
              linewidth=3)
    axis.text(0.0, -0.38, f"lands on 1 / cos θ = {footprint:.2f}", color="tab:red",
              ha="center", fontsize=9)
    axis.annotate("", xy=(0, 1.1), xytext=(0, 0),
                  arrowprops=dict(arrowstyle="->", color="tab:blue", linewidth=2))
    axis.text(0.05, 1.1, "N", color="tab:blue", fontsize=11)
    axis.annotate("", xy=1.1 * to_light, xytext=(0, 0),
                  arrowprops=dict(arrowstyle="->", color="tab:green", linewidth=2))
    axis.text(*(1.15 * to_light), "L", color="tab:green", fontsize=11)
    arc = np.linspace(0, angle, 30)
    axis.plot(0.45 * np.sin(arc), 0.45 * np.cos(arc), color="0.3", linewidth=1)
    axis.text(0.22 * np.sin(angle / 2) + 0.02, 0.55 * np.cos(angle / 2), "θ", fontsize=11)
    axis.set_title("Lambert: light per area = cos θ = N · L", fontsize=10)
    axis.set_xlim(-1.7, 2.3)
    axis.set_ylim(-0.5, 2.4)


def draw_acne(axis):
    """A hit point rounded to just below the surface: its shadow ray finds the surface."""
    slope = 0.18
    xs = np.linspace(-1.6, 1.6, 2)
    axis.plot(xs, slope * xs, color="0.3", linewidth=2)
    axis.fill_between(xs, slope * xs, slope * xs - 0.25, color="0.85")
    axis.text(1.25, slope * 1.25 - 0.2, "inside", fontsize=8, color="0.4", ha="center")
    # The floats near the surface: a coarse grid, hugely magnified.
    grid = np.arange(-1.5, 1.6, 0.25)
    gx, gy = np.meshgrid(grid, np.arange(-0.5, 0.76, 0.25))
    axis.scatter(gx, gy, s=4, color="0.6", zorder=1)
    light_direction = np.array([0.45, 1.0]) / np.linalg.norm([0.45, 1.0])

    # Without the offset: the rounded hit point lies just inside.
    exact = np.array([-0.85, slope * -0.85])
    rounded = np.array([-0.75, -0.25])  # the nearest float, below the surface
    axis.plot(*exact, "x", color="0.2", markersize=7)
    axis.plot(*rounded, "o", color="tab:red", markersize=6, zorder=3)
    axis.annotate("", xy=rounded + 1.45 * light_direction, xytext=rounded,
                  arrowprops=dict(arrowstyle="->", color="tab:red", linewidth=1.6))
    # Where the shadow ray crosses the surface line y = slope * x.
    crossing_t = ((slope * rounded[0] - rounded[1])
                  / (light_direction[1] - slope * light_direction[0]))
    crossing = rounded + crossing_t * light_direction
    axis.plot(*crossing, "*", color="tab:red", markersize=11, zorder=4)
    axis.text(rounded[0] - 0.05, rounded[1] - 0.17, "hit point, rounded\n(just inside)",
              color="tab:red", fontsize=8, ha="center", va="top")
    axis.text(crossing[0] - 0.1, crossing[1] + 0.12, "meets its own surface\nat t ≈ 0: "
              "shadow", color="tab:red", fontsize=8, ha="right")

    # With the offset: start a little way out along the normal.
    normal = np.array([-slope, 1.0]) / np.linalg.norm([-slope, 1.0])
    hit = np.array([0.6, slope * 0.6])
    start = hit + 0.35 * normal
    axis.plot(*hit, "o", color="tab:green", markersize=6, zorder=3)
    axis.annotate("", xy=start, xytext=hit,
                  arrowprops=dict(arrowstyle="->", color="tab:blue", linewidth=1.6))
    axis.text(*(hit + 0.17 * normal + [0.06, 0.0]), "offset · N", color="tab:blue",
              fontsize=8)
    axis.annotate("", xy=start + 1.2 * light_direction, xytext=start,
                  arrowprops=dict(arrowstyle="->", color="tab:green", linewidth=1.6))
    axis.text(*(start + 1.25 * light_direction + [0.0, 0.05]), "reaches the light",
              color="tab:green", fontsize=8, ha="center")
    axis.set_title("Shadow acne, and the offset that cures it", fontsize=10)
    axis.set_xlim(-1.7, 1.7)
    axis.set_ylim(-0.75, 2.0)


def draw(path, angle_degrees):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(1, 2, figsize=(10, 3.9), dpi=110)
    draw_lambert(axes[0], angle_degrees)
    draw_acne(axes[1])
    for axis in axes:
        axis.set_aspect("equal")
        axis.axis("off")
    figure.tight_layout()
    figure.savefig(path, bbox_inches="tight")
    plt.close(figure)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--figure", required=True, help="write the figure to this file")
    parser.add_argument("--angle", type=float, default=50.0,
                        help="angle between the light and the normal, in degrees")
    args = parser.parse_args(argv)
    draw(args.figure, args.angle)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
