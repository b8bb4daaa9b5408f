"""Chapter 16's figure of the side rule, rendered by the real program (build/bin/16_glass):

    python python_prototypes/shading_normal_figure.py --figure 16_normal_side.png

A glass teapot of 552 triangles with smooth (interpolated) normals in the Cornell room,
rendered twice: with the chapter's shaders, where the flat normal decides which side a
ray is on and a path ends where the smooth normal disagrees; and with a copy of the
shaders with one line edited (triangle.glsl: the flat normal replaced by the smooth one),
so that the smooth normal decides. A third panel shows where the two differ."""

from __future__ import annotations

import argparse
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from python_prototypes.figure_file import new_figure, save_figure_file
from python_prototypes.pfm import read_pfm

ROOT = Path(__file__).resolve().parent.parent
PROGRAM = ROOT / "build" / "bin" / "16_glass"
SHADERS = ROOT / "shaders" / "16_glass"
TEAPOT = ROOT / "build" / "assets" / "meshes" / "teapot_552.obj"

# The one edit: the smooth normal takes the flat one's place, so it decides the side.
RIGHT = "    vec3 normal = smoothNormal(normalsOf(triangle), barycentric, geometricNormal);\n"
WRONG = RIGHT.rstrip("\n") + " geometricNormal = normal;\n"


def scene_text() -> str:
    """cornell_teapot.scene's room with the coarse teapot made of glass, seen closer."""
    lines = []
    for line in (ROOT / "assets" / "scenes" / "cornell_teapot.scene").read_text().splitlines():
        words = line.split()
        if words[:1] == ["camera"]:
            line = "camera eye 0 -0.3 3.9 look 0.01 -0.09 -1 up 0 1 0 focal 0.055 sensor 0.025"
        elif words[:2] == ["material", "teapot"]:
            line = "material teapot dielectric ior 1.5"
        elif words[:1] == ["mesh"]:
            line = " ".join(["mesh", str(TEAPOT), *words[2:]])
        lines.append(line)
    return "\n".join(lines) + "\n"


def render(folder: Path, name: str, shader_dir: Path, size, spp) -> np.ndarray:
    out = folder / f"{name}.pfm"
    subprocess.run([str(PROGRAM), "--headless", "--out", str(out), "--scene",
                    str(folder / "teapot.scene"), "--width", str(size[0]), "--height",
                    str(size[1]), "--spp", str(spp), "--shader-dir", str(shader_dir)],
                   check=True, stdout=subprocess.DEVNULL)
    return read_pfm(str(out))[..., :3]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--figure", required=True, help="write the figure (PNG) here")
    parser.add_argument("--spp", type=int, default=128)
    args = parser.parse_args(argv)
    for needed in (PROGRAM, TEAPOT):
        if not needed.exists():
            parser.error(f"{needed} is missing: build the course first (./course build)")
    with tempfile.TemporaryDirectory() as work:
        folder = Path(work)
        (folder / "teapot.scene").write_text(scene_text())
        wrong = folder / "shaders"
        shutil.copytree(SHADERS, wrong)
        text = (wrong / "triangle.glsl").read_text()
        assert text.count(RIGHT) == 1, "triangle.glsl's smooth-normal line has changed"
        (wrong / "triangle.glsl").write_text(text.replace(RIGHT, WRONG))
        size = (240, 150)
        images = [render(folder, "right", SHADERS, size, args.spp),
                  render(folder, "wrong", wrong, size, args.spp)]
    difference = np.abs(images[0] - images[1]).mean(axis=-1)
    figure = new_figure(figsize=(12, 2.9), dpi=100)
    titles = ["right: the flat normal decides the side", "wrong: the smooth normal decides",
              "where they differ (×4)"]
    shown = [np.clip(image, 0, 1) ** (1 / 2.2) for image in images]
    shown.append(np.clip(4 * difference, 0, 1) ** (1 / 2.2))
    for index, (image, title) in enumerate(zip(shown, titles), start=1):
        axes = figure.add_subplot(1, 3, index)
        axes.imshow(image, cmap="gray" if image.ndim == 2 else None, vmin=0, vmax=1,
                    interpolation="nearest")
        axes.set_title(title, fontsize=10)
        axes.set_axis_off()
    save_figure_file(figure, args.figure)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
