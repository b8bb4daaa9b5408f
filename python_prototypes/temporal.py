"""Chapter 29 in numpy: where the last frame saw what this frame sees, and what it did
not see at all. Everything is exact here (float64, scene_cast's rays against every
shape): each pixel's first surface is found through a point of the pixel, moved into
the last frame's camera, and looked for there.

- disoccluded(): the pixels whose point the last frame could not see (something was in
  front of it, or it lay outside the picture). There the history is another surface's,
  and a blend that takes it shows a ghost; the chapter's checks look at these pixels.
- same_surface_rates(): how often a test of "the same surface" keeps a history tap that
  did see it, with one sample a pixel landing anywhere in the pixel: comparing depth
  with depth turns walls seen at a slant away; the point against the tap's plane does not.

    python3 python_prototypes/temporal.py --figure temporal.png

draws the page's figure (the boxes painted blue, the camera stepping 10 cm right and up:
the pixels it uncovers)."""

from __future__ import annotations

import argparse
import dataclasses
import re
from pathlib import Path

import numpy as np

from python_prototypes import camera_rays, scene_cast, scene_io
from python_prototypes.figure_file import new_figure, save_figure_file

BLUE = "material blue albedo 0.1 0.12 0.8\n"
CORNELL_BOX = Path(__file__).resolve().parents[1] / "assets" / "scenes" / "cornell_box.scene"


def moved(camera: scene_io.SceneCamera, step) -> scene_io.SceneCamera:
    """The camera stepped by `step` (metres), looking the same way: the chapter's --move."""
    return dataclasses.replace(camera, eye=tuple(np.add(camera.eye, step)))


def painted_blue(scene_text: str) -> str:
    """The Cornell box with its two boxes blue: a ghost of them on the white wall shows."""
    text = re.sub(r"^(quad .*) white (name (small|large)_box)$", r"\1 blue \2", scene_text,
                  flags=re.M)
    return text.replace("material light ", BLUE + "material light ", 1)


def first_hits(scene, camera, size: int, offset=(0.5, 0.5)):
    """Each pixel's first hit through the point `offset` of the pixel (an array of
    offsets per pixel, or one for all): the points (size, size, 3), their distances,
    the materials' indices."""
    eye, directions = scene_cast.pixel_rays(camera, size, size)
    if np.ndim(offset) == 3:  # a point of its own in each pixel
        forward, right, up = camera_rays.camera_basis(camera.look, camera.up)
        across = (np.arange(size)[None, :] + offset[..., 0]) / size - 0.5
        upwards = 0.5 - (np.arange(size)[:, None] + offset[..., 1]) / size
        directions = camera_rays.normalize(
            forward * camera.focal_length + right[None, None] * (across * camera.sensor_width)
            [..., None] + up[None, None] * (upwards * camera.sensor_width)[..., None])
    hits = scene_cast.nearest_hits(scene, eye, directions)
    return eye + hits.t[..., None] * directions, hits.t, hits.material


def in_picture(camera, points, size: int):
    """Where points appear in the camera's picture, in pixel coordinates (pixel (i, j)
    spans i..i+1 across and j..j+1 down), and whether they lie in front of it."""
    forward, right, up = camera_rays.camera_basis(camera.look, camera.up)
    from_eye = points - np.asarray(camera.eye)
    ahead = from_eye @ forward
    across = (from_eye @ right) / camera.sensor_width * camera.focal_length / ahead
    upwards = -(from_eye @ up) / camera.sensor_width * camera.focal_length / ahead
    return (np.stack([across, upwards], axis=-1) + 0.5) * size, ahead > 0


def disoccluded(scene, before, now, size: int) -> np.ndarray:
    """The pixels of `now` whose first surface (through their centres) `before` did not
    see: outside its picture, or behind something nearer to its eye."""
    points, t, _ = first_hits(scene, now, size)
    seen = np.isfinite(t)  # a pixel that sees nothing has nothing to uncover
    points = np.where(seen[..., None], points, 0.0)
    where, ahead = in_picture(before, points, size)
    outside = ~ahead | np.any((where < 0) | (where >= size), axis=-1)
    towards = points - np.asarray(before.eye)
    distance = np.linalg.norm(towards, axis=-1)
    hits = scene_cast.nearest_hits(scene, np.asarray(before.eye), towards / distance[..., None])
    hidden = hits.t < distance * (1.0 - 1e-6)
    return seen & (outside | hidden)


def same_surface_rates(scene, camera, step, size: int, tolerance: float = 0.02,
                       seed: int = 1):
    """With one sample a pixel landing anywhere in it, in both frames: of the pixels
    whose point and its nearest history tap lie on the same flat surface (the same
    quad, seen away from edges), the share each test keeps. The depth test compares the
    tap's depth with the point's distance from the last frame's eye; the plane test
    puts the tap's point (its centre ray, at its depth) and the tap's normal against
    the point. Both within `tolerance` times the tap's depth."""
    random = np.random.default_rng(seed)
    now = moved(camera, step)
    points, _, _ = first_hits(scene, now, size, random.random((size, size, 2)))
    taps_points, depths, _ = first_hits(scene, camera, size, random.random((size, size, 2)))
    seen = np.isfinite(distance_of(points, now)) & np.isfinite(depths)
    points = np.where(seen[..., None], points, 0.0)
    taps_points = np.where(seen[..., None], taps_points, 0.0)
    where, _ = in_picture(camera, points, size)
    tap = np.clip(np.floor(where).astype(int), 0, size - 1)
    depth = depths[tap[..., 1], tap[..., 0]]
    eye, centres = scene_cast.pixel_rays(camera, size, size)
    tap_point = eye + centres[tap[..., 1], tap[..., 0]] * depth[..., None]
    quad = shape_of(scene, points)
    same = seen & (quad >= 0) & (quad == shape_of(scene, taps_points)[tap[..., 1], tap[..., 0]])
    normal = np.asarray([quad_normal(scene.quads[i]) for i in range(len(scene.quads))])
    tap_normal = normal[np.maximum(quad, 0)]
    distance = np.linalg.norm(points - np.asarray(camera.eye), axis=-1)
    by_depth = np.abs(distance - depth) <= tolerance * depth
    by_plane = np.abs(np.einsum("...i,...i", points - tap_point, tap_normal)) <= \
        tolerance * depth
    return by_depth[same].mean(), by_plane[same].mean()


def distance_of(points, camera) -> np.ndarray:
    return np.linalg.norm(points - np.asarray(camera.eye), axis=-1)


def quad_normal(quad) -> np.ndarray:
    n = np.cross(quad.edge1, quad.edge2)
    return n / np.linalg.norm(n)


def shape_of(scene, points) -> np.ndarray:
    """The index of the quad each point lies on (within 1e-6 of its plane, inside it),
    -1 for none."""
    found = np.full(points.shape[:-1], -1)
    for index, quad in enumerate(scene.quads):
        origin, e1, e2 = (np.asarray(v, dtype=np.float64) for v in (quad.origin, quad.edge1,
                                                                  quad.edge2))
        local = points - origin
        off = np.abs(local @ quad_normal(quad))
        a = local @ e1 / (e1 @ e1)
        b = local @ e2 / (e2 @ e2)
        on = (off < 1e-6) & (a >= 0) & (a <= 1) & (b >= 0) & (b <= 1)
        found = np.where(on & (found < 0), index, found)
    return found


def draw_figure(path: str, size: int = 96, step=(0.1, 0.1, 0.0)) -> None:
    """The painted boxes seen by the last frame and by this one, and the pixels this
    one uncovers."""
    scene = scene_io.parse_scene(painted_blue(CORNELL_BOX.read_text()), CORNELL_BOX)
    before = scene.camera
    now = moved(before, step)
    figure = new_figure(figsize=(9, 3.2), dpi=80)
    colours = np.array([scene.materials[name].albedo for name in scene.materials])
    for index, (camera, title) in enumerate([(before, "the last frame"),
                                             (now, "this frame, 10 cm right and up")]):
        _, _, material = first_hits(scene, camera, size)
        axes = figure.add_subplot(1, 3, index + 1)
        axes.imshow(np.clip(colours[material], 0, 1))
        axes.set_title(title)
        axes.axis("off")
    _, _, material = first_hits(scene, now, size)
    picture = np.clip(colours[material], 0, 1) * 0.4
    picture[disoccluded(scene, before, now, size)] = (1.0, 0.2, 0.1)
    axes = figure.add_subplot(1, 3, 3)
    axes.imshow(picture)
    axes.set_title("uncovered: no history")
    axes.axis("off")
    save_figure_file(figure, path)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--figure", required=True, help="the PNG to write")
    args = parser.parse_args(argv)
    draw_figure(args.figure)
    print(args.figure)


if __name__ == "__main__":
    main()
