"""Chapter 06's picture, computed independently: spheres (quadratic formula) and
triangles, in float64 on whole arrays of rays. The shader uses Moller-Trumbore; here a
ray meets a triangle's plane first, and the hit point is inside when it lies on the
inner side of all three edges (edge functions). Triangles are two-sided: the normal
faces the ray. Lambert shading and shadow rays as in chapter 05 (reference/shading.py).

The scenes mirror chapters/06_triangles/scene.cpp; if the two drift apart, the image
checks fail.
"""

from __future__ import annotations


import numpy as np

from python_prototypes import camera_rays
from python_prototypes.reference.shading import SHADOW_OFFSET, shade
from python_prototypes.reference.spheres import sky, sphere_distances

FLOOR_ALBEDO = (0.75, 0.75, 0.75)
PYRAMID_ALBEDO = (0.85, 0.8, 0.7)
LIGHT = (3.0, 5.0, 4.0)


def floor(half_size, albedo):
    """Two triangles, the square |x|, |z| <= half_size at y = 0 (normals down)."""
    a, b = (-half_size, 0, -half_size), (half_size, 0, -half_size)
    c, d = (half_size, 0, half_size), (-half_size, 0, half_size)
    return [(a, b, c, albedo), (a, c, d, albedo)]


def pyramid(base_center, radius, height, albedo):
    """Four triangles from the base corners (on the x and z axes) to the apex."""
    x, y, z = base_center
    apex = (x, y + height, z)
    corners = [(x, y, z + radius), (x + radius, y, z), (x, y, z - radius),
               (x - radius, y, z)]
    return [(corners[i], corners[(i + 1) % 4], apex, albedo) for i in range(4)]


SPHERES = [((0.0, 0.5, 0.0), 0.5, (0.8, 0.3, 0.25)),
           ((-0.4, 0.3, 0.85), 0.3, (0.3, 0.7, 0.35)),
           ((0.62, 0.35, 0.65), 0.35, (0.3, 0.45, 0.85)),
           ((0.05, 0.2, 1.35), 0.2, (0.9, 0.75, 0.3))]

# name: spheres [(centre, radius, albedo)], triangles [(p0, p1, p2, albedo)], light
SCENES = {
    "spheres": dict(spheres=SPHERES,
                    triangles=floor(20.0, FLOOR_ALBEDO)
                    + pyramid((-1.1, 0.0, -0.6), 0.5, 0.9, PYRAMID_ALBEDO),
                    light=LIGHT),
    "single": dict(spheres=SPHERES[:1], triangles=floor(20.0, FLOOR_ALBEDO), light=LIGHT),
    "pyramid": dict(spheres=[],
                    triangles=floor(20.0, FLOOR_ALBEDO)
                    + pyramid((0.0, 0.0, 0.0), 0.8, 1.0, PYRAMID_ALBEDO),
                    light=LIGHT),
}


def triangle_distances(origins, directions, corners) -> np.ndarray:
    """Distance t > 0 to every triangle along every ray, inf for a miss: (..., triangles).
    corners: (triangles, 3, 3)."""
    origins = np.asarray(origins, dtype=np.float64)[..., np.newaxis, :]   # (..., 1, 3)
    p0, p1, p2 = corners[:, 0], corners[:, 1], corners[:, 2]
    normals = np.cross(p1 - p0, p2 - p0)                                  # not unit
    approach = np.sum(directions[..., np.newaxis, :] * normals, axis=-1)  # (..., T)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.sum((p0 - origins) * normals, axis=-1) / approach
    points = origins + t[..., np.newaxis] * directions[..., np.newaxis, :]
    inside = np.ones(t.shape, dtype=bool)
    for a, b in [(p0, p1), (p1, p2), (p2, p0)]:
        # Edge function: positive when the point is on the inner side of edge a -> b,
        # which is the side of the normal's counter-clockwise winding.
        inside &= np.sum(np.cross(b - a, points - a) * normals, axis=-1) >= 0.0
    return np.where(np.isfinite(t) & (t > 0.0) & inside, t, np.inf)


class Surfaces:
    """A scene's spheres and triangles as arrays (the interface reference.shading uses)."""

    def __init__(self, scene: dict):
        spheres, triangles = scene["spheres"], scene["triangles"]
        self.centers = np.array([s[0] for s in spheres], dtype=np.float64).reshape(-1, 3)
        self.radii = np.array([s[1] for s in spheres], dtype=np.float64)
        self.sphere_albedos = np.array([s[2] for s in spheres],
                                       dtype=np.float64).reshape(-1, 3)
        self.corners = np.array([t[:3] for t in triangles], dtype=np.float64)
        self.triangle_albedos = np.array([t[3] for t in triangles], dtype=np.float64)
        edges = np.cross(self.corners[:, 1] - self.corners[:, 0],
                         self.corners[:, 2] - self.corners[:, 0])
        self.triangle_normals = edges / np.linalg.norm(edges, axis=-1, keepdims=True)
        self.light = np.array(scene["light"], dtype=np.float64)

    def distances(self, origins, directions) -> np.ndarray:
        """t > 0 to every surface (spheres first, then triangles), inf for a miss."""
        return np.concatenate([
            sphere_distances(origins, directions, self.centers, self.radii),
            triangle_distances(origins, directions, self.corners)], axis=-1)

    def surface_at(self, index, points, directions):
        """Normal (facing the ray) and albedo of surface `index` at points."""
        spheres = len(self.radii)
        on_sphere = (index < spheres)[..., np.newaxis]
        triangle = np.clip(index - spheres, 0, len(self.corners) - 1)
        normals = self.triangle_normals[triangle]
        albedos = self.triangle_albedos[triangle]
        if spheres:
            sphere = np.minimum(index, spheres - 1)
            sphere_normals = (points - self.centers[sphere]) / self.radii[sphere][
                ..., np.newaxis]
            normals = np.where(on_sphere, sphere_normals, normals)
            albedos = np.where(on_sphere, self.sphere_albedos[sphere], albedos)
        # Two-sided triangles: turn the normal towards where the ray came from.
        facing_away = np.sum(normals * directions, axis=-1, keepdims=True) > 0.0
        normals = np.where(facing_away & ~on_sphere, -normals, normals)
        return normals, albedos


def render_shaded(scene: str, width: int, height: int, camera=None,
                  shadow_offset=SHADOW_OFFSET) -> np.ndarray:
    """The chapter's image: (height, width, 3) linear colours."""
    camera = camera or camera_rays.Camera()
    surfaces = Surfaces(SCENES[scene])
    directions = camera_rays.camera_rays(camera, width, height)
    distances = surfaces.distances(camera.eye, directions)
    index = np.argmin(distances, axis=-1)
    t = np.min(distances, axis=-1, keepdims=True)
    hit = np.isfinite(t)
    points = np.asarray(camera.eye) + np.where(hit, t, 0.0) * directions
    normals, albedos = surfaces.surface_at(index, points, directions)
    colors = shade(surfaces, points, normals, albedos, shadow_offset)
    return np.where(hit, colors, sky(directions))


def render_barycentrics(scene: str, width: int, height: int, camera=None) -> np.ndarray:
    """A debugging view: (u, v, 0) of the triangle each ray hits, the weights of its
    corners p1 and p2; black on spheres, sky where rays miss. Areas of the
    sub-triangles, not Moller-Trumbore: P - p0 = u (p1 - p0) + v (p2 - p0)."""
    camera = camera or camera_rays.Camera()
    surfaces = Surfaces(SCENES[scene])
    directions = camera_rays.camera_rays(camera, width, height)
    distances = surfaces.distances(camera.eye, directions)
    index = np.argmin(distances, axis=-1)
    t = np.min(distances, axis=-1, keepdims=True)
    hit = np.isfinite(t)
    points = np.asarray(camera.eye) + np.where(hit, t, 0.0) * directions
    triangle = np.clip(index - len(surfaces.radii), 0, len(surfaces.corners) - 1)
    p0, p1, p2 = (surfaces.corners[triangle, k] for k in range(3))
    normal = np.cross(p1 - p0, p2 - p0)
    area = np.sum(normal * normal, axis=-1)
    u = np.sum(np.cross(points - p0, p2 - p0) * normal, axis=-1) / area
    v = np.sum(np.cross(p1 - p0, points - p0) * normal, axis=-1) / area
    on_triangle = (index >= len(surfaces.radii))[..., np.newaxis]
    colors = np.where(on_triangle, np.stack([u, v, np.zeros_like(u)], axis=-1), 0.0)
    return np.where(hit, colors, sky(directions))
