"""The two classic camera mistakes of chapter 03, drawn next to the right camera.

Each panel shows the ray directions as colours (the chapter's picture) with two kinds
of lines drawn over it: circles of rays at 5, 10, 15, ... degrees from the forward
direction, and the horizon (rays with y = 0), dashed. A correct camera keeps the circles
round and the horizon above the middle (the camera looks slightly down).

    python python_prototypes/reference/camera_mistakes.py --figure mistakes.png
"""

import argparse

import numpy as np

from python_prototypes import camera_rays
from python_prototypes import srgb


def directions_with_sensor(camera, width, height, sensor_height):
    """Like camera_rays.camera_rays(), but with the sensor height given explicitly."""
    forward, right, true_up = camera_rays.camera_basis(camera.look_direction, camera.up)
    across = ((np.arange(width) + 0.5) / width - 0.5) * camera.sensor_width
    upwards = (0.5 - (np.arange(height) + 0.5) / height) * sensor_height
    eye_to_pixel = (forward * camera.focal_length
                    + right * across[np.newaxis, :, np.newaxis]
                    + true_up * upwards[:, np.newaxis, np.newaxis])
    return camera_rays.normalize(eye_to_pixel)


def panels(camera, width, height):
    right = camera_rays.camera_rays(camera, width, height)
    return [
        ("right", right),
        ("upside down: row 0 is not the top", right[::-1]),
        ("square sensor for a 4:3 image",
         directions_with_sensor(camera, width, height, camera.sensor_width)),
    ]


def draw(path, width, height):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    camera = camera_rays.Camera()
    forward, _, _ = camera_rays.camera_basis(camera.look_direction, camera.up)
    figure, axes = plt.subplots(1, 3, figsize=(11, 3.1), dpi=110)
    figure.subplots_adjust(left=0.01, right=0.99, top=0.9, bottom=0.1, wspace=0.05)
    for axis, (title, directions) in zip(axes, panels(camera, width, height)):
        axis.imshow(srgb.encode(camera_rays.ray_colors(directions)),  # as the PNGs are
                    interpolation="nearest")
        degrees_from_forward = np.degrees(np.arccos(np.clip(directions @ forward, -1, 1)))
        lines = axis.contour(degrees_from_forward, levels=[5, 10, 15, 20, 25],
                             colors="white", linewidths=0.8)
        axis.clabel(lines, fmt="%d°", fontsize=7)
        axis.contour(directions[..., 1], levels=[0.0], colors="black",
                     linestyles="dashed", linewidths=1.2)
        axis.set_title(title, fontsize=10)
        axis.set_xticks([])
        axis.set_yticks([])
    figure.text(0.5, 0.03, "White: rays 5°, 10°, ... from forward. Dashed: the horizon "
                "(ray direction y = 0).", ha="center", fontsize=9, color="0.3")
    figure.savefig(path, bbox_inches="tight")
    plt.close(figure)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--figure", required=True, help="write the figure to this file")
    parser.add_argument("--width", type=int, default=160, help="pixels per panel row")
    parser.add_argument("--height", type=int, default=120, help="pixel rows per panel")
    args = parser.parse_args(argv)
    draw(args.figure, args.width, args.height)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
