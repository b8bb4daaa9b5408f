"""Chapter 08's shadow terminator problem, up close: a detail of the smooth-shaded teapot
where the lit side turns into the dark side, and beside it the pixels where the smooth
normal faces the light but the flat triangle under it does not.

There the shading says "lit", but the light is behind the flat triangle's plane. The
shadow ray starts just off the triangle on the side the camera sees, so on its way to
the light it crosses that plane at once and hits the triangle itself (or, near an
edge, its neighbour): the pixel drops to ambient light, one triangle-shaped patch at a
time.

Rendered by mesh_scene.py, the numpy reference that chapter 08's picture is checked
against (at the picture size tested, it agrees with the chapter pixel for pixel).

    python python_prototypes/reference/shadow_terminator.py \\
        --obj build/assets/meshes/teapot_552.obj --figure terminator.png
"""

import argparse
import sys
from pathlib import Path

import numpy as np

from python_prototypes import obj_io
from python_prototypes.reference import mesh_scene

WIDTH, HEIGHT = 640, 480          # the picture the detail is cut from
WINDOW = (180, 200, 400, 365)     # left, top, right, bottom: the teapot's dark side
HIGHLIGHT = np.array([0.9, 0.1, 0.1])


def detail(obj_path):
    """(the smooth-shaded detail, the mask of pixels with the mismatch)."""
    positions, normals, triangles, normal_triangles = obj_io.read_obj(obj_path)
    trace = mesh_scene.trace_mesh(positions, triangles, normals, normal_triangles, WIDTH,
                                  HEIGHT, smooth=True, window=WINDOW)
    to_light = trace.light_position - trace.position
    on_mesh = (trace.triangle >= 0) & (trace.triangle < len(triangles))
    smooth_says_lit = np.sum(trace.normal * to_light, axis=-1) > 0.0
    flat_faces_away = np.sum(trace.geometric_normal * to_light, axis=-1) <= 0.0
    return trace.image, on_mesh & smooth_says_lit & flat_faces_away


def draw(path, obj_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    image, mismatch = detail(obj_path)
    marked = np.where(mismatch[..., np.newaxis], HIGHLIGHT, image)
    figure, axes = plt.subplots(1, 2, figsize=(8.6, 3.4), dpi=110)
    figure.subplots_adjust(left=0.01, right=0.99, top=0.9, bottom=0.02, wspace=0.04)
    titles = ["smooth shading, the dark side close up",
              "red: smooth normal faces the light, flat triangle does not"]
    for axis, title, picture in zip(axes, titles, (image, marked)):
        axis.imshow(mesh_scene.srgb_8bit(picture), interpolation="nearest")
        axis.set_title(title, fontsize=9)
        axis.set_xticks([])
        axis.set_yticks([])
    figure.savefig(path, bbox_inches="tight")
    plt.close(figure)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--obj", required=True, type=Path, help="OBJ mesh to render")
    parser.add_argument("--figure", required=True, help="write the figure to this file")
    args = parser.parse_args(argv)
    try:
        draw(args.figure, args.obj)
    except (OSError, obj_io.ObjError) as error:
        print(f"shadow_terminator.py: {error}", file=sys.stderr)
        sys.exit(3)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
