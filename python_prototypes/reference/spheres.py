"""Chapter 04's picture, computed independently: the nearest sphere along every camera
ray, found with the quadratic formula for all rays and all spheres at once (the shader
uses the geometric construction, one ray at a time). A hit shows its surface normal as
a colour, 0.5 * N + 0.5; a miss shows the sky. Linear colours, row 0 at the top.

The scenes mirror chapters/04_spheres/scene.cpp; if the two drift apart, the image
checks fail.
"""

from __future__ import annotations


import numpy as np

from python_prototypes import camera_rays

# name: [(centre, radius), ...] in the order the chapter lists them.
SCENES = {
    # Four spheres resting on y = 0; from the camera, the front ones overlap the big one.
    "spheres": [((0.0, 0.5, 0.0), 0.5),
                ((-0.4, 0.3, 0.85), 0.3),
                ((0.62, 0.35, 0.65), 0.35),
                ((0.05, 0.2, 1.35), 0.2)],
    "single": [((0.0, 0.5, 0.0), 0.5)],
}


def sky(directions: np.ndarray) -> np.ndarray:
    """White at the horizon's nadir blending to light blue straight up (linear)."""
    blend = 0.5 * (directions[..., 1:2] + 1.0)
    return (1.0 - blend) * np.array([1.0, 1.0, 1.0]) + blend * np.array([0.5, 0.7, 1.0])


def sphere_distances(origins, directions, centers, radii) -> np.ndarray:
    """Distance t > 0 to every sphere along every ray, inf where a ray misses:
    shape (..., spheres). `origins` is one point (3,) or one per ray (..., 3).
    Solves |origin + t d - c|^2 = r^2 with |d| = 1:
    t^2 + 2 b t + c = 0 with b = (o - c).d, c = |o - c|^2 - r^2."""
    offset = np.asarray(origins, dtype=np.float64)[..., np.newaxis, :] - centers
    b = np.sum(directions[..., np.newaxis, :] * offset, axis=-1)   # (..., spheres)
    c = np.sum(offset * offset, axis=-1) - radii ** 2
    discriminant = b * b - c
    root = np.sqrt(np.maximum(discriminant, 0.0))
    near, far = -b - root, -b + root
    t = np.where(near > 0.0, near, far)  # from inside a sphere, the exit
    return np.where((discriminant >= 0.0) & (t > 0.0), t, np.inf)


def scene_arrays(scene: str):
    spheres = SCENES[scene]
    centers = np.array([center for center, _ in spheres], dtype=np.float64)
    radii = np.array([radius for _, radius in spheres], dtype=np.float64)
    return centers, radii


def hit_sphere_index(distances: np.ndarray, first_hit: bool = False) -> np.ndarray:
    """Per ray, the index of the sphere it shows, -1 for none. first_hit: the first
    sphere in the list that the ray hits at all (chapter 04's classic bug)."""
    hit = np.isfinite(distances)
    choice = np.argmax(hit, axis=-1) if first_hit else np.argmin(distances, axis=-1)
    return np.where(hit.any(axis=-1), choice, -1)


def render_normals(scene: str, width: int, height: int, camera=None,
                   first_hit: bool = False) -> np.ndarray:
    """The chapter's image: (height, width, 3) linear colours."""
    camera = camera or camera_rays.Camera()
    directions = camera_rays.camera_rays(camera, width, height)
    centers, radii = scene_arrays(scene)
    distances = sphere_distances(camera.eye, directions, centers, radii)
    index = hit_sphere_index(distances, first_hit)
    chosen = np.maximum(index, 0)
    t = np.take_along_axis(distances, chosen[..., np.newaxis], axis=-1)
    points = np.asarray(camera.eye) + t * directions
    normals = (points - centers[chosen]) / radii[chosen][..., np.newaxis]
    return np.where(index[..., np.newaxis] >= 0, 0.5 * normals + 0.5, sky(directions))
