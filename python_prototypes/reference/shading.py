"""Chapter 05's picture, computed independently: spheres (quadratic formula) and planes
on whole arrays of rays in float64, Lambert shading from a point light, and shadow rays
that start SHADOW_OFFSET off the surface, as the shader's do.

    colour = albedo * (AMBIENT + (1 - AMBIENT) * visible * max(0, N . L))

The scenes mirror chapters/05_shading_shadows/scene.cpp; if the two drift apart, the
image checks fail.
"""

from __future__ import annotations


import numpy as np

from python_prototypes import camera_rays
from python_prototypes.reference.spheres import sky, sphere_distances

AMBIENT = 0.1
SHADOW_OFFSET = 1e-3
FLOOR = ((0.0, 1.0, 0.0), 0.0, (0.75, 0.75, 0.75))  # normal, offset, albedo

# name: spheres [(centre, radius, albedo)], planes [(normal, offset, albedo)], light
SCENES = {
    "spheres": dict(
        spheres=[((0.0, 0.5, 0.0), 0.5, (0.8, 0.3, 0.25)),
                 ((-0.4, 0.3, 0.85), 0.3, (0.3, 0.7, 0.35)),
                 ((0.62, 0.35, 0.65), 0.35, (0.3, 0.45, 0.85)),
                 ((0.05, 0.2, 1.35), 0.2, (0.9, 0.75, 0.3))],
        planes=[FLOOR], light=(3.0, 5.0, 4.0)),
    "single": dict(spheres=[((0.0, 0.5, 0.0), 0.5, (0.8, 0.3, 0.25))],
                   planes=[FLOOR], light=(3.0, 5.0, 4.0)),
}


class Surfaces:
    """A scene's surfaces as arrays: what every function below works on."""

    def __init__(self, scene: dict):
        spheres, planes = scene["spheres"], scene["planes"]
        self.centers = np.array([s[0] for s in spheres], dtype=np.float64).reshape(-1, 3)
        self.radii = np.array([s[1] for s in spheres], dtype=np.float64)
        self.sphere_albedos = np.array([s[2] for s in spheres], dtype=np.float64)
        self.normals = np.array([p[0] for p in planes], dtype=np.float64).reshape(-1, 3)
        self.offsets = np.array([p[1] for p in planes], dtype=np.float64)
        self.plane_albedos = np.array([p[2] for p in planes], dtype=np.float64)
        self.light = np.array(scene["light"], dtype=np.float64)

    def distances(self, origins, directions) -> np.ndarray:
        """t > 0 to every surface (spheres first, then planes), inf for a miss."""
        return np.concatenate([
            sphere_distances(origins, directions, self.centers, self.radii),
            plane_distances(origins, directions, self.normals, self.offsets)], axis=-1)

    def surface_at(self, index, points):
        """Normal and albedo of surface `index` (as numbered by distances()) at points."""
        spheres = len(self.radii)
        sphere = np.minimum(index, spheres - 1)
        plane = np.clip(index - spheres, 0, len(self.offsets) - 1)
        on_sphere = (index < spheres)[..., np.newaxis]
        sphere_normals = (points - self.centers[sphere]) / self.radii[sphere][..., np.newaxis]
        normals = np.where(on_sphere, sphere_normals, self.normals[plane])
        albedos = np.where(on_sphere, self.sphere_albedos[sphere], self.plane_albedos[plane])
        return normals, albedos


def plane_distances(origins, directions, normals, offsets) -> np.ndarray:
    """Distance t > 0 to every plane dot(n, p) = offset along every ray, inf for a miss:
    (..., planes)."""
    origins = np.asarray(origins, dtype=np.float64)
    approach = directions @ normals.T                              # (..., planes)
    height = offsets - origins @ normals.T                         # (..., planes)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = height / approach
    return np.where(np.isfinite(t) & (t > 0.0), t, np.inf)


def light_visible(surfaces: Surfaces, points, normals, shadow_offset=SHADOW_OFFSET):
    """Per point: does a shadow ray from shadow_offset above the surface reach the light?
    Also the direction to the light from where the shadow ray starts."""
    origins = points + normals * shadow_offset
    to_light = surfaces.light - origins
    light_distance = np.linalg.norm(to_light, axis=-1, keepdims=True)
    light_directions = to_light / light_distance
    blockers = surfaces.distances(origins, light_directions)
    return ~np.any(blockers < light_distance, axis=-1, keepdims=True), light_directions


def shade(surfaces: Surfaces, points, normals, albedos, shadow_offset=SHADOW_OFFSET):
    """Lambert shading with a shadow ray per point."""
    visible, light_directions = light_visible(surfaces, points, normals, shadow_offset)
    cosine = np.maximum(0.0, np.sum(normals * light_directions, axis=-1, keepdims=True))
    return albedos * (AMBIENT + (1.0 - AMBIENT) * visible * cosine)


def primary_hits(surfaces: Surfaces, camera, width, height):
    """For every pixel: ray direction, hit mask, hit point, normal and albedo."""
    directions = camera_rays.camera_rays(camera, width, height)
    distances = surfaces.distances(camera.eye, directions)
    index = np.argmin(distances, axis=-1)
    t = np.min(distances, axis=-1, keepdims=True)
    hit = np.isfinite(t)
    points = np.asarray(camera.eye) + np.where(hit, t, 0.0) * directions
    normals, albedos = surfaces.surface_at(index, points)
    return directions, hit, points, normals, albedos


def render_shaded(scene: str, width: int, height: int, camera=None,
                  shadow_offset=SHADOW_OFFSET) -> np.ndarray:
    """The chapter's image: (height, width, 3) linear colours."""
    surfaces = Surfaces(SCENES[scene])
    directions, hit, points, normals, albedos = primary_hits(
        surfaces, camera or camera_rays.Camera(), width, height)
    colors = shade(surfaces, points, normals, albedos, shadow_offset)
    return np.where(hit, colors, sky(directions))
