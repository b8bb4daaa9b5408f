"""Chapter 10 in numpy: what the camera sees of a scene file. Every ray is tested
against every sphere, quad and lone triangle in float64, the nearest hit wins, and the
front of a surface is the side its normal points to: a sphere's outside, the side
cross(edge1, edge2) points to for a quad, the side from which a triangle's corners run
counter-clockwise. The checks compare chapter 10's GPU preview with what this finds.

    python3 python_prototypes/scene_cast.py assets/scenes/cornell_spheres.scene

prints what the centre pixel of a 64 x 64 picture sees. Meshes are not read here
(chapter 07's checks cover the OBJ loader): a scene with one is refused."""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from python_prototypes import camera_rays
from python_prototypes import scene_io

MISS = -1


@dataclass
class Hits:
    """What each ray found, in the rays' shape: t (inf for a miss), the material's
    index in scene.materials (MISS for a miss) and whether it is the front."""
    t: np.ndarray
    material: np.ndarray
    front: np.ndarray


def sphere_t(center, radius, origins, directions):
    """The nearest t > 0 where each ray meets the sphere; inf if none. A direction may
    have any length: a ray carried into an instance's object space keeps the length its
    placement gives it, so that t stays the world's distance (chapter 26)."""
    to_origin = origins - np.asarray(center, dtype=np.float64)
    a = np.einsum("...i,...i", directions, directions)
    half_b = np.einsum("...i,...i", to_origin, directions)
    c = np.einsum("...i,...i", to_origin, to_origin) - radius * radius
    discriminant = half_b * half_b - a * c
    root = np.sqrt(np.maximum(discriminant, 0.0))
    near, far = (-half_b - root) / a, (-half_b + root) / a
    t = np.where(near > 1e-9, near, np.where(far > 1e-9, far, np.inf))
    return np.where(discriminant >= 0.0, t, np.inf)


def parallelogram_t(origin, edge1, edge2, origins, directions, triangle=False):
    """Where each ray meets the parallelogram origin + a edge1 + b edge2, a and b in
    [0, 1] (or the triangle a, b >= 0, a + b <= 1); inf if it misses."""
    origin, edge1, edge2 = (np.asarray(v, dtype=np.float64) for v in (origin, edge1, edge2))
    normal = np.cross(edge1, edge2)
    facing = directions @ normal
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((origin - origins) @ normal) / facing
        point = origins + t[..., None] * directions - origin
        w = normal / normal.dot(normal)
        a = np.cross(point, edge2) @ w
        b = np.cross(edge1, point) @ w
    inside = (a >= 0) & (b >= 0) & ((a + b <= 1) if triangle else (a <= 1) & (b <= 1))
    return np.where(inside & (t > 0) & (np.abs(facing) > 0), t, np.inf)


def nearest_hits(scene: scene_io.Scene, origins, directions) -> Hits:
    if scene.meshes:
        raise ValueError("scene_cast reads spheres, quads and triangles, not meshes")
    shape = directions.shape[:-1]
    origins = np.broadcast_to(np.asarray(origins, dtype=np.float64), directions.shape)
    best = np.full(shape, np.inf)
    material = np.full(shape, MISS)
    front = np.zeros(shape, dtype=bool)
    names = list(scene.materials)  # in file order, as the GPU numbers them
    for sphere in scene.spheres:
        t = sphere_t(sphere.center, sphere.radius, origins, directions)
        nearer = t < best
        points = origins + np.where(np.isfinite(t), t, 0.0)[..., None] * directions
        outward = points - np.asarray(sphere.center)
        is_front = np.einsum("...i,...i", outward, directions) < 0
        best = np.where(nearer, t, best)
        material = np.where(nearer, names.index(sphere.material), material)
        front = np.where(nearer, is_front, front)
    flat = [(q.origin, q.edge1, q.edge2, q.material, False) for q in scene.quads]
    flat += [(t.p0, np.subtract(t.p1, t.p0), np.subtract(t.p2, t.p0), t.material, True)
             for t in scene.triangles]
    for origin, edge1, edge2, name, triangle in flat:
        t = parallelogram_t(origin, edge1, edge2, origins, directions, triangle)
        nearer = t < best
        is_front = directions @ np.cross(edge1, edge2) < 0
        best = np.where(nearer, t, best)
        material = np.where(nearer, names.index(name), material)
        front = np.where(nearer, is_front, front)
    return Hits(best, material, front)


def pixel_rays(camera: scene_io.SceneCamera, width: int, height: int, offset=(0.5, 0.5)):
    """(origin, unit directions (height, width, 3)) through the point `offset` of each
    pixel, (0, 0) its top-left corner: the GPU's primaryRay()."""
    forward, right, up = camera_rays.camera_basis(camera.look, camera.up)
    sensor_height = camera.sensor_width * height / width
    x = ((np.arange(width) + offset[0]) / width - 0.5) * camera.sensor_width
    y = (0.5 - (np.arange(height) + offset[1]) / height) * sensor_height
    points = (forward * camera.focal_length + right * x[None, :, None]
              + up * y[:, None, None])
    return np.asarray(camera.eye, dtype=np.float64), camera_rays.normalize(points)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", type=Path)
    args = parser.parse_args(argv)
    scene = scene_io.load_scene(args.scene)
    origin, directions = pixel_rays(scene.camera, 64, 64)
    hits = nearest_hits(scene, origin, directions)
    index = hits.material[32, 32]
    what = "nothing" if index == MISS else list(scene.materials)[index]
    print(f"centre pixel: {what} at t = {hits.t[32, 32]:.4f}, front: {hits.front[32, 32]}")


if __name__ == "__main__":
    main()
