"""Chapter 07's other classic mistake, drawn next to the right picture: OBJ face indices
count from 1, arrays from 0. A reader that forgets the "- 1" gives every triangle corner
the vertex after the one the file meant.

Both panels are rendered by mesh_scene.py, the numpy reference of chapter 07. The one
index that lands past the end of the array (the last vertex's, plus one) is wrapped
round to the first vertex here; a GPU would read whatever lies beyond the buffer.

    python python_prototypes/reference/obj_off_by_one.py \\
        --obj build/assets/meshes/teapot_552.obj --figure off_by_one.png
"""

import argparse
import sys
from pathlib import Path

import numpy as np

from python_prototypes import obj_io
from python_prototypes.reference import mesh_scene


def panels(obj_path, width, height):
    positions, _, triangles, _ = obj_io.read_obj(obj_path)  # 0-based, as they should be
    as_written = (triangles + 1) % len(positions)            # 1-based, used as 0-based
    return [("indices − 1: right", mesh_scene.render_mesh(positions, triangles,
                                                          width=width, height=height)),
            ("indices as written: off by one",
             mesh_scene.render_mesh(positions, as_written, width=width, height=height))]


def draw(path, obj_path, width, height):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(1, 2, figsize=(8, 3.2), dpi=110)
    figure.subplots_adjust(left=0.01, right=0.99, top=0.9, bottom=0.02, wspace=0.04)
    for axis, (title, image) in zip(axes, panels(obj_path, width, height)):
        axis.imshow(mesh_scene.srgb_8bit(image), interpolation="nearest")
        axis.set_title(title, fontsize=10)
        axis.set_xticks([])
        axis.set_yticks([])
    figure.savefig(path, bbox_inches="tight")
    plt.close(figure)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--obj", required=True, type=Path, help="OBJ mesh to render")
    parser.add_argument("--figure", required=True, help="write the figure to this file")
    parser.add_argument("--width", type=int, default=240, help="pixels per panel row")
    parser.add_argument("--height", type=int, default=180, help="pixel rows per panel")
    args = parser.parse_args(argv)
    if args.width < 1 or args.height < 1:
        sys.exit("obj_off_by_one.py: --width and --height must be at least 1")
    try:
        draw(args.figure, args.obj, args.width, args.height)
    except (OSError, obj_io.ObjError) as error:
        print(f"obj_off_by_one.py: {error}", file=sys.stderr)
        sys.exit(3)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
