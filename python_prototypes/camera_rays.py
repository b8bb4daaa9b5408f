"""The pinhole camera of the course: one ray per pixel, from the eye through the pixel.

The convention (the C++ and GLSL chapters implement exactly this):

    forward = normalize(look_direction)
    right   = normalize(cross(forward, up))
    true_up = cross(right, forward)
    sensor_height = sensor_width * height / width          # square pixels
    # pixel (px, py), py = 0 is the TOP row of the image; through the pixel centre:
    pixel_center = eye + forward * focal_length
                 + right   * ((px + 0.5) / width  - 0.5) * sensor_width
                 + true_up * (0.5 - (py + 0.5) / height) * sensor_height
    direction = normalize(pixel_center - eye)

The sensor sits in front of the eye (a "virtual" sensor), so the image is not upside
down as in a real pinhole camera.

    python python_prototypes/camera_rays.py --figure camera.png
    python python_prototypes/camera_rays.py --width 640 --height 480 --out-npy rays.npy
"""

import argparse
import os
import sys
from dataclasses import dataclass

import numpy as np


@dataclass
class Camera:
    """A pinhole camera; lengths in metres (a 35 mm lens on a 36 mm full-frame sensor)."""
    eye: tuple = (0.0, 1.0, 4.0)
    look_direction: tuple = (0.0, -0.25, -1.0)
    up: tuple = (0.0, 1.0, 0.0)
    focal_length: float = 0.035
    sensor_width: float = 0.036


def normalize(vector):
    return vector / np.linalg.norm(vector, axis=-1, keepdims=True)


def camera_basis(look_direction, up):
    """(forward, right, true_up): orthonormal, right-handed, true_up close to up."""
    forward = normalize(np.asarray(look_direction, dtype=np.float64))
    side = np.cross(forward, np.asarray(up, dtype=np.float64))
    if np.linalg.norm(side) < 1e-12:
        raise ValueError("up must not be parallel to look_direction")
    right = normalize(side)
    true_up = np.cross(right, forward)  # already unit length: right is perpendicular
    return forward, right, true_up


def pixel_centers(width, height, eye, look_direction, up, focal_length, sensor_width):
    """World-space position of every pixel centre on the sensor: (height, width, 3)."""
    forward, right, true_up = camera_basis(look_direction, up)
    sensor_height = sensor_width * height / width  # square pixels
    # Offsets from the sensor centre, in sensor units; row 0 is the top of the image.
    across = ((np.arange(width) + 0.5) / width - 0.5) * sensor_width
    down_to_up = (0.5 - (np.arange(height) + 0.5) / height) * sensor_height
    sensor_center = np.asarray(eye, dtype=np.float64) + forward * focal_length
    return (sensor_center
            + right * across[np.newaxis, :, np.newaxis]
            + true_up * down_to_up[:, np.newaxis, np.newaxis])


def camera_ray_directions(width, height, eye, look_direction, up, focal_length,
                          sensor_width):
    """Unit ray direction through every pixel centre: float64 (height, width, 3)."""
    centers = pixel_centers(width, height, eye, look_direction, up, focal_length,
                            sensor_width)
    return normalize(centers - np.asarray(eye, dtype=np.float64))


def camera_rays(camera, width, height):
    """camera_ray_directions() for a Camera."""
    return camera_ray_directions(width, height, camera.eye, camera.look_direction,
                                 camera.up, camera.focal_length, camera.sensor_width)


def ray_colors(directions):
    """Chapter 03's picture: each ray direction in [-1, 1] shown as a linear RGB colour."""
    return 0.5 * directions + 0.5


# ---------------------------------------------------------------------------------------
# The figure for the book
# ---------------------------------------------------------------------------------------

FIGURE_COLUMNS, FIGURE_ROWS = 8, 6  # a coarse pixel grid, so the rays stay readable
RAY_LENGTH = 2.6  # in focal lengths, so the rays visibly go on past the sensor
LABEL_BOX = dict(facecolor="white", alpha=0.75, edgecolor="none", pad=1.0)


def draw_camera_figure(camera, path=None, elev=20, azim=70):
    """Draw eye, camera axes, sensor, pixel grid and rays; save to path or show."""
    import matplotlib
    if path is not None:
        matplotlib.use("Agg")  # no window needed to write a file
    import matplotlib.pyplot as plt

    # Draw in units of one focal length, with the eye at the origin: a real 36 mm sensor
    # would be invisible next to a scene metres wide. Scaling focal length and sensor
    # together keeps the rays' directions, which depend only on their ratio.
    eye = np.zeros(3)
    forward, right, true_up = camera_basis(camera.look_direction, camera.up)
    sensor_width = camera.sensor_width / camera.focal_length
    sensor_height = sensor_width * FIGURE_ROWS / FIGURE_COLUMNS  # square pixels
    centers = pixel_centers(FIGURE_COLUMNS, FIGURE_ROWS, eye, camera.look_direction,
                            camera.up, 1.0, sensor_width)
    directions = normalize(centers - eye)

    figure = plt.figure(figsize=(8, 6), dpi=120)
    axes = figure.add_axes((0.0, 0.1, 1.0, 0.85), projection="3d")  # room for a caption
    axes.computed_zorder = False  # draw in call order: labels and arrows over the rays
    draw_rays(axes, eye, centers, directions)
    draw_sensor(axes, eye + forward, right, true_up, sensor_width, sensor_height)
    draw_pixel_centers(axes, centers, true_up)
    draw_axes(axes, eye, forward, right, true_up)
    ray_ends = (eye + directions * RAY_LENGTH).reshape(-1, 3)
    frame_view(axes, np.concatenate([[eye, eye + true_up * 0.7, eye + right * 0.7],
                                     ray_ends]))
    axes.view_init(elev=elev, azim=azim, vertical_axis="y")

    axes.set_title("Pinhole camera: one ray from the eye through each pixel centre")
    figure.text(0.5, 0.01,
                f"{FIGURE_COLUMNS} x {FIGURE_ROWS} pixels. Lengths in focal lengths: "
                f"a {camera.sensor_width * 1000:g} mm wide sensor "
                f"{camera.focal_length * 1000:g} mm in front of the eye.\n"
                "Eye at the origin; solid: eye to pixel centre, dashed: on into the scene.",
                ha="center", fontsize=9, color="0.3")
    if path is not None:
        figure.savefig(path, bbox_inches="tight")
        plt.close(figure)
    else:
        plt.show()


def draw_rays(axes, eye, centers, directions):
    """Solid from the eye to the pixel centre, dashed beyond (where the scene is)."""
    ends = eye + directions * RAY_LENGTH
    for center, end in zip(centers.reshape(-1, 3), ends.reshape(-1, 3)):
        segment = np.stack([eye, center])
        axes.plot(*segment.T, color="tab:orange", linewidth=0.6, alpha=0.8)
        beyond = np.stack([center, end])
        axes.plot(*beyond.T, color="tab:orange", linewidth=0.6, alpha=0.5, linestyle="--")


def draw_sensor(axes, sensor_center, right, true_up, sensor_width, sensor_height):
    """Outline, pixel grid lines and a faint fill for the sensor rectangle."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    def sensor_point(x, y):  # x, y in [-0.5, 0.5] across and up the sensor
        return sensor_center + right * x * sensor_width + true_up * y * sensor_height

    corners = np.array([sensor_point(x, y) for x, y in
                        [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]])
    axes.add_collection3d(Poly3DCollection([corners], facecolor="tab:blue", alpha=0.12))
    def grid_line(start, end, on_edge):  # pixel borders thin, the sensor outline bold
        line = np.stack([sensor_point(*start), sensor_point(*end)])
        axes.plot(*line.T, color="tab:blue", linewidth=1.6 if on_edge else 0.6)

    for column in range(FIGURE_COLUMNS + 1):
        x = column / FIGURE_COLUMNS - 0.5
        grid_line((x, -0.5), (x, 0.5), column in (0, FIGURE_COLUMNS))
    for row in range(FIGURE_ROWS + 1):
        y = row / FIGURE_ROWS - 0.5
        grid_line((-0.5, y), (0.5, y), row in (0, FIGURE_ROWS))
    label_at = sensor_point(0.5, -0.5)
    axes.text(*label_at, "  sensor\n  (image plane)", color="tab:blue", fontsize=9,
              va="top", bbox=LABEL_BOX)


def draw_pixel_centers(axes, centers, true_up):
    """Pixel centres as dots; mark pixel (0, 0), the top-left one."""
    points = centers.reshape(-1, 3)
    axes.scatter(*points.T, color="black", s=6, depthshade=False)
    axes.scatter(*centers[0, 0], color="tab:red", s=24, depthshade=False)
    axes.text(*(centers[0, 0] + 0.08 * true_up), "pixel (0, 0): top left", color="tab:red",
              fontsize=9, ha="left", va="bottom", bbox=LABEL_BOX)


def draw_axes(axes, eye, forward, right, true_up):
    """The eye and the camera's three unit axes as arrows."""
    axes.scatter(*eye, color="black", s=30, depthshade=False)
    axes.text(*(eye - 0.12 * true_up), "eye", fontsize=10, ha="right", va="top",
              bbox=LABEL_BOX)
    for direction, name, color in [(forward, "forward", "tab:green"),
                                   (right, "right", "tab:red"),
                                   (true_up, "true_up", "tab:purple")]:
        length = 0.6
        axes.quiver(*eye, *(direction * length), color=color, linewidth=1.8,
                    arrow_length_ratio=0.2)
        axes.text(*(eye + direction * length * 1.1), name, color=color, fontsize=10,
                  bbox=LABEL_BOX)


def frame_view(axes, points):
    """Fit the axes tightly around points, with the same scale on all three axes."""
    low, high = points.min(axis=0), points.max(axis=0)
    margin = 0.05 * (high - low).max()
    low, high = low - margin, high + margin
    axes.set_xlim(low[0], high[0])
    axes.set_ylim(low[1], high[1])
    axes.set_zlim(low[2], high[2])
    axes.set_box_aspect(high - low)  # box sides in proportion to the data ranges
    axes.set_xlabel("x")
    axes.set_ylabel("y")
    axes.set_zlabel("z")


# ---------------------------------------------------------------------------------------
# Command line
# ---------------------------------------------------------------------------------------

def parse_args(argv):
    defaults = Camera()
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--figure", help="save the 3D camera figure to this file")
    parser.add_argument("--width", type=int, default=640, help="image width in pixels")
    parser.add_argument("--height", type=int, default=480, help="image height in pixels")
    parser.add_argument("--out-npy", help="write the ray directions, float32 (h, w, 3)")
    parser.add_argument("--eye", type=float, nargs=3, default=defaults.eye)
    parser.add_argument("--look-direction", type=float, nargs=3,
                        default=defaults.look_direction)
    parser.add_argument("--up", type=float, nargs=3, default=defaults.up)
    parser.add_argument("--focal-length", type=float, default=defaults.focal_length,
                        help="metres (default 0.035)")
    parser.add_argument("--sensor-width", type=float, default=defaults.sensor_width,
                        help="metres (default 0.036)")
    return parser.parse_args(argv)


def has_display():
    return sys.platform in ("win32", "darwin") or bool(
        os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def main(argv=None):
    args = parse_args(argv)
    if args.width < 1 or args.height < 1:
        sys.exit("camera_rays.py: --width and --height must be at least 1")
    camera = Camera(tuple(args.eye), tuple(args.look_direction), tuple(args.up),
                    args.focal_length, args.sensor_width)

    if args.out_npy:
        directions = camera_rays(camera, args.width, args.height)
        np.save(args.out_npy, directions.astype(np.float32))
        print(f"wrote {args.width} x {args.height} ray directions to {args.out_npy}")
    if args.figure:
        draw_camera_figure(camera, args.figure)
        print(f"wrote {args.figure}")
    elif not args.out_npy:
        if has_display():
            draw_camera_figure(camera)
        else:
            print("no display: use --figure FILE.png or --out-npy FILE.npy")


if __name__ == "__main__":
    main()
