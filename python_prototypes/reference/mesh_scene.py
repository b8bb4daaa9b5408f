"""Chapters 07 and 08's picture, computed independently: a triangle mesh standing on a
floor, framed automatically from its bounds, lit by one point light with hard shadows.
Chapter 07 shades each triangle flat; chapter 08 interpolates normals across it.

The shader tests one ray against one triangle at a time with Moller-Trumbore. Here every
ray meets a chunk of triangles at once, in float64, a different way: the ray first meets
the triangle's plane, then three edge functions (sub-triangle areas divided by the
triangle's area) say whether that point is inside and give its barycentric coordinates.

The scene, which the GLSL implements exactly:

  camera    camera_rays.py's pinhole: focal length 0.035, sensor width 0.036, up (0, 1, 0)
  framing   lo, hi = bounds of the positions; c = (lo + hi) / 2; r = |hi - lo| / 2
            look = normalize(0, -0.35, -1); sensor_height = 0.036 * height / width
            half_fov = min(atan(0.036 / 2 / 0.035), atan(sensor_height / 2 / 0.035))
            eye = c - look * r / sin(half_fov): the bounding sphere just fits the view
  floor     2 triangles in the plane y = lo.y over [c.x - 20r, c.x + 20r] x
            [c.z - 20r, c.z + 20r]: (x0,y,z0) (x1,y,z0) (x1,y,z1) and (x0,y,z0) (x1,y,z1)
            (x0,y,z1); albedo 0.7
  mesh      albedo (0.9, 0.55, 0.25)
  hits      the nearest mesh or floor triangle with t > 0
  normals   Ng = normalize(cross(p1 - p0, p2 - p0)), the geometric normal
            flat (07): N = Ng
            smooth (08): N = normalize(w n0 + u n1 + v n2), u for p1, v for p2,
            w = 1 - u - v, with the file's normals or, without them, area-weighted
            vertex normals; the floor's N is its Ng
            two-sided: when dot(Ng, dir) > 0, both Ng and N are flipped (the geometric
            normal decides which side the ray sees)
  light     point light L = c + r * (2, 4, 3); ambient 0.1
            shadow ray from O = P + Ng * 1e-4 * (1 + r), direction normalize(L - O):
            lit when it hits nothing with t in (0, |L - O|)
            colour = albedo * (0.1 + 0.9 * lit * max(0, dot(N, normalize(L - O))))
  sky       on a miss: mix((1, 1, 1), (0.5, 0.7, 1), 0.5 * (dir.y + 1)), linear

    python python_prototypes/reference/mesh_scene.py --obj build/assets/meshes/teapot_552.obj \\
        --out teapot_flat.png [--smooth] [--width 320 --height 240]
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np

from python_prototypes import camera_rays
from python_prototypes import obj_io
from python_prototypes import srgb

FOCAL_LENGTH = 0.035
SENSOR_WIDTH = 0.036
UP = (0.0, 1.0, 0.0)
LOOK_DIRECTION = (0.0, -0.35, -1.0)  # from the front, a little from above
FLOOR_HALF_SIZE = 20.0     # in mesh radii
LIGHT_OFFSET = (2.0, 4.0, 3.0)  # in mesh radii from the centre: right, above, in front
AMBIENT = 0.1
MESH_ALBEDO = (0.9, 0.55, 0.25)
FLOOR_ALBEDO = (0.7, 0.7, 0.7)
HIT_T_MIN = 0.0
SHADOW_OFFSET = 1e-4       # times (1 + r), along Ng: the shadow ray must not hit its start
INSIDE_TOLERANCE = 1e-9    # barycentrics this far below 0 still hit: no cracks at edges
PAIRS_PER_CHUNK = 1 << 16  # ray-triangle pairs tested at once: arrays that stay in cache
RAYS_PER_BLOCK = 4096     # rays traced together, against chunks of triangles


class Framing(NamedTuple):
    eye: np.ndarray
    look: np.ndarray
    light_position: np.ndarray
    center: np.ndarray
    radius: float
    floor_y: float


class Trace(NamedTuple):
    image: np.ndarray     # (height, width, 3) linear colours, row 0 at the top
    triangle: np.ndarray  # (height, width) what each pixel shows: -1 sky, 0 .. T - 1 the
                          # mesh's triangles, T and T + 1 the floor's
    # Where the pixel's ray hit, and the normals there, both facing the ray (0 for sky):
    position: np.ndarray          # (height, width, 3)
    normal: np.ndarray            # (height, width, 3) the one shaded with
    geometric_normal: np.ndarray  # (height, width, 3) the flat triangle's
    light_position: np.ndarray    # (3,)


def normalize(vectors: np.ndarray) -> np.ndarray:
    return vectors / np.linalg.norm(vectors, axis=-1, keepdims=True)


# ---------------------------------------------------------------------------------------
# The scene around a mesh
# ---------------------------------------------------------------------------------------

def mesh_bounds(positions: np.ndarray):
    """(lo, hi, centre, radius) of the positions' axis-aligned bounding box."""
    lo, hi = positions.min(axis=0), positions.max(axis=0)
    return lo, hi, 0.5 * (lo + hi), 0.5 * float(np.linalg.norm(hi - lo))


def light_position(positions: np.ndarray) -> np.ndarray:
    _, _, center, radius = mesh_bounds(np.asarray(positions, dtype=np.float64))
    return center + radius * np.array(LIGHT_OFFSET)


def frame_camera(positions, width: int, height: int) -> Framing:
    """Eye and look direction that fit the mesh's bounding sphere in the picture."""
    positions = np.asarray(positions, dtype=np.float64)
    lo, _, center, radius = mesh_bounds(positions)
    look = normalize(np.array(LOOK_DIRECTION))
    sensor_height = SENSOR_WIDTH * height / width
    half_fov = min(math.atan(SENSOR_WIDTH / 2 / FOCAL_LENGTH),
                   math.atan(sensor_height / 2 / FOCAL_LENGTH))
    # The lines from the eye that graze the sphere make half_fov with the line to its
    # centre: sin(half_fov) = radius / distance.
    distance = radius / math.sin(half_fov)
    return Framing(center - look * distance, look, light_position(positions), center,
                   radius, float(lo[1]))


def floor_triangles(framing: Framing) -> np.ndarray:
    """The floor's two triangles, (2, 3, 3), in the plane y = lo.y under the mesh."""
    half = FLOOR_HALF_SIZE * framing.radius
    x0, x1 = framing.center[0] - half, framing.center[0] + half
    z0, z1 = framing.center[2] - half, framing.center[2] + half
    y = framing.floor_y
    return np.array([[(x0, y, z0), (x1, y, z0), (x1, y, z1)],
                     [(x0, y, z0), (x1, y, z1), (x0, y, z1)]])


def sky(directions: np.ndarray) -> np.ndarray:
    """White below, blending to light blue straight up (linear colours)."""
    blend = 0.5 * (directions[..., 1:2] + 1.0)
    return (1.0 - blend) * np.array([1.0, 1.0, 1.0]) + blend * np.array([0.5, 0.7, 1.0])


# ---------------------------------------------------------------------------------------
# Rays against triangles: plane, then edge functions
# ---------------------------------------------------------------------------------------

class TriangleSet(NamedTuple):
    """What the hit test needs of each triangle, computed once."""
    normal: np.ndarray        # (T, 3) cross(p1 - p0, p2 - p0), not normalised
    plane_offset: np.ndarray  # (T,) dot(normal, p0): the plane is dot(normal, x) = offset
    # Barycentric k of a point x on the plane is dot(edge_normal[k], x) - edge_offset[k]:
    # the area of the sub-triangle x makes with the edge opposite corner k, over the
    # triangle's area. All three are >= 0 exactly when x is inside.
    edge_normal: np.ndarray   # (3, T, 3)
    edge_offset: np.ndarray   # (3, T)


def prepare_triangles(corners: np.ndarray) -> TriangleSet:
    p0, p1, p2 = corners[:, 0], corners[:, 1], corners[:, 2]
    normal = np.cross(p1 - p0, p2 - p0)
    with np.errstate(divide="ignore", invalid="ignore"):  # zero-area: nan, never hit
        inverse_square = 1.0 / np.sum(normal * normal, axis=-1, keepdims=True)
    # The edge opposite corner k, from a to b. With m = cross(normal, b - a) / |normal|^2,
    # dot(normal, cross(b - a, x - a)) / |normal|^2 = dot(m, x) - dot(m, a).
    edges = [(p1, p2), (p2, p0), (p0, p1)]
    edge_normal = np.stack([np.cross(normal, b - a) * inverse_square for a, b in edges])
    edge_offset = np.stack([np.sum(m * a, axis=-1) for m, (a, _) in zip(edge_normal, edges)])
    return TriangleSet(normal, np.sum(normal * p0, axis=-1), edge_normal, edge_offset)


def nearest_hits(origins, directions, triangles: TriangleSet, t_min, t_max):
    """The nearest triangle each ray hits with t_min < t < t_max.

    origins: (3,) or (R, 3); directions: (R, 3); t_max: a number or (R,).
    Returns (t, triangle index or -1, u, v), each of shape (R,).
    """
    ray_count = len(directions)
    origins = np.broadcast_to(np.asarray(origins, dtype=np.float64), (ray_count, 3))
    t_max = np.broadcast_to(np.asarray(t_max, dtype=np.float64), (ray_count,))
    results = [_nearest_hits_block(origins[block], directions[block], triangles, t_min,
                                   t_max[block])
               for block in (slice(first, first + RAYS_PER_BLOCK)
                             for first in range(0, ray_count, RAYS_PER_BLOCK))]
    if not results:
        return np.zeros(0), np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros(0)
    return tuple(np.concatenate(parts) for parts in zip(*results))


def _nearest_hits_block(origins, directions, triangles: TriangleSet, t_min, t_max):
    ray_count = len(directions)
    best_t = np.array(t_max, dtype=np.float64)
    best_index = np.full(ray_count, -1)
    best_u, best_v = np.zeros(ray_count), np.zeros(ray_count)
    rows = np.arange(ray_count)
    chunk = max(1, PAIRS_PER_CHUNK // max(ray_count, 1))
    for first in range(0, len(triangles.normal), chunk):
        part = slice(first, first + chunk)
        with np.errstate(divide="ignore", invalid="ignore"):
            # 1. Where the ray meets the plane: dot(normal, o + t d) = offset.
            normal = triangles.normal[part].T
            t = (triangles.plane_offset[part] - origins @ normal) / (directions @ normal)
            # 2. Barycentrics of that point: linear in t, so no (R, T, 3) point array.
            w, u, v = (origins @ m.T + t * (directions @ m.T) - offset[part]
                       for m, offset in zip(triangles.edge_normal[:, part],
                                            triangles.edge_offset))
            inside = ((w >= -INSIDE_TOLERANCE) & (u >= -INSIDE_TOLERANCE)
                      & (v >= -INSIDE_TOLERANCE))
            t = np.where(inside & (t > t_min), t, np.inf)  # nan (parallel) goes too
        nearest = np.argmin(t, axis=1)
        nearest_t = t[rows, nearest]
        closer = nearest_t < best_t
        best_t[closer] = nearest_t[closer]
        best_index[closer] = first + nearest[closer]
        best_u[closer] = u[rows, nearest][closer]
        best_v[closer] = v[rows, nearest][closer]
    return best_t, best_index, best_u, best_v


# ---------------------------------------------------------------------------------------
# Normals
# ---------------------------------------------------------------------------------------

def vertex_normals(positions: np.ndarray, tri_pos_idx: np.ndarray) -> np.ndarray:
    """Area-weighted: each vertex sums cross(p1 - p0, p2 - p0) of its triangles, whose
    length is twice the triangle's area, and normalises the sum."""
    corners = positions[tri_pos_idx]
    face = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    sums = np.zeros_like(positions)
    for k in range(3):
        np.add.at(sums, tri_pos_idx[:, k], face)
    # Unused vertices, and those whose triangles' normals cancel, keep (0, 0, 0).
    lengths = np.linalg.norm(sums, axis=-1, keepdims=True)
    return np.divide(sums, lengths, out=np.zeros_like(sums), where=lengths > 0.0)


def corner_normals(positions, tri_pos_idx, normals, tri_nrm_idx) -> np.ndarray:
    """(T, 3, 3): the file's normal at each triangle corner, or area-weighted ones."""
    if normals is not None and tri_nrm_idx is not None:
        return np.asarray(normals, dtype=np.float64)[tri_nrm_idx]
    return vertex_normals(positions, tri_pos_idx)[tri_pos_idx]


# ---------------------------------------------------------------------------------------
# The picture
# ---------------------------------------------------------------------------------------

def trace_mesh(positions, tri_pos_idx, normals=None, tri_nrm_idx=None, width=160,
               height=120, smooth=False, window=None) -> Trace:
    """The picture and, per pixel, which triangle it shows.

    window: (left, top, right, bottom) traces only those pixels of the width x height
    picture (right and bottom excluded), e.g. to look at a detail closely."""
    positions = np.asarray(positions, dtype=np.float64)
    tri_pos_idx = np.asarray(tri_pos_idx, dtype=np.int64).reshape(-1, 3)
    framing = frame_camera(positions, width, height)
    directions = camera_rays.camera_ray_directions(
        width, height, framing.eye, framing.look, UP, FOCAL_LENGTH, SENSOR_WIDTH)
    if window is not None:
        left, top, right, bottom = window
        directions = directions[top:bottom, left:right]
    height, width = directions.shape[:2]
    directions = directions.reshape(-1, 3)

    mesh_corners = positions[tri_pos_idx]
    mesh_count = len(mesh_corners)
    scene = prepare_triangles(np.concatenate([mesh_corners, floor_triangles(framing)]))
    t, index, u, v = nearest_hits(framing.eye, directions, scene, HIT_T_MIN, np.inf)

    image = sky(directions)
    hit = index >= 0
    ray, shown = directions[hit], index[hit]
    points = framing.eye + t[hit, np.newaxis] * ray
    on_mesh = shown < mesh_count

    # The geometric normal of the triangle hit (the floor's too), and the normal used
    # for shading: the same when flat, interpolated from the corners when smooth.
    with np.errstate(divide="ignore", invalid="ignore"):
        geometric = normalize(scene.normal[shown])
    normal = geometric.copy()
    if smooth:
        corner = corner_normals(positions, tri_pos_idx, normals, tri_nrm_idx)
        mesh_shown = shown[on_mesh]
        u_hit, v_hit = u[hit][on_mesh, np.newaxis], v[hit][on_mesh, np.newaxis]
        blended = ((1.0 - u_hit - v_hit) * corner[mesh_shown, 0]
                   + u_hit * corner[mesh_shown, 1] + v_hit * corner[mesh_shown, 2])
        length = np.linalg.norm(blended, axis=-1, keepdims=True)
        usable = length[:, 0] > 1e-12  # opposite corner normals: keep the flat one
        smooth_normal = normal[on_mesh]
        smooth_normal[usable] = blended[usable] / length[usable]
        normal[on_mesh] = smooth_normal
    # Two-sided: the geometric normal says which side the ray sees; both turn to it.
    facing_away = np.sum(geometric * ray, axis=-1) > 0.0
    geometric[facing_away] *= -1.0
    normal[facing_away] *= -1.0

    # Direct light with a shadow ray from just off the surface, then ambient.
    shadow_origins = points + geometric * (SHADOW_OFFSET * (1.0 + framing.radius))
    to_light = framing.light_position - shadow_origins
    light_distance = np.linalg.norm(to_light, axis=-1)
    to_light /= light_distance[:, np.newaxis]
    lambert = np.maximum(0.0, np.sum(normal * to_light, axis=-1))
    visible = np.ones(len(points))
    lit = lambert > 0.0  # elsewhere the shadow ray cannot change the colour
    _, blocker, _, _ = nearest_hits(shadow_origins[lit], to_light[lit], scene, 0.0,
                                    light_distance[lit])
    visible[lit] = blocker < 0
    albedo = np.where(on_mesh[:, np.newaxis], MESH_ALBEDO, FLOOR_ALBEDO)
    image[hit] = albedo * (AMBIENT + (1.0 - AMBIENT) * (visible * lambert)[:, np.newaxis])
    def per_pixel(values):
        full = np.zeros((len(directions), 3))
        full[hit] = values
        return full.reshape(height, width, 3)
    return Trace(image.reshape(height, width, 3), index.reshape(height, width),
                 per_pixel(points), per_pixel(normal), per_pixel(geometric),
                 framing.light_position)


def render_mesh(positions, tri_pos_idx, normals=None, tri_nrm_idx=None, width=160,
                height=120, smooth=False) -> np.ndarray:
    """Linear float image (height, width, 3), row 0 at the top."""
    return trace_mesh(positions, tri_pos_idx, normals, tri_nrm_idx, width, height,
                      smooth).image


# ---------------------------------------------------------------------------------------
# Command line
# ---------------------------------------------------------------------------------------

def srgb_8bit(linear: np.ndarray) -> np.ndarray:
    """The sRGB transfer function and rounding to 8 bits, as a PNG viewer expects."""
    return srgb.encode_8bit(linear).astype(np.uint8)


def write_png(path: Path, image: np.ndarray):
    """Writes under a temporary name, then renames: never half a file."""
    from matplotlib import image as matplotlib_image
    partial = path.with_name(path.name + ".partial")
    matplotlib_image.imsave(partial, srgb_8bit(image), format="png")
    os.replace(partial, path)


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--obj", required=True, type=Path, help="OBJ mesh to render")
    parser.add_argument("--width", type=int, default=320)
    parser.add_argument("--height", type=int, default=240)
    parser.add_argument("--smooth", action="store_true",
                        help="interpolate normals (chapter 08) instead of flat shading")
    parser.add_argument("--out", required=True, type=Path, help="PNG file (8-bit sRGB)")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    if args.width < 1 or args.height < 1:
        sys.exit("mesh_scene.py: --width and --height must be at least 1")
    try:
        positions, normals, tri_pos_idx, tri_nrm_idx = obj_io.read_obj(args.obj)
    except (OSError, obj_io.ObjError) as error:
        print(f"mesh_scene.py: {error}", file=sys.stderr)
        sys.exit(3)  # a bad input file, as for the chapter programs
    started = time.perf_counter()
    image = render_mesh(positions, tri_pos_idx, normals, tri_nrm_idx, args.width,
                        args.height, args.smooth)
    write_png(args.out, image)
    print(f"{len(tri_pos_idx)} triangles, {args.width} x {args.height}, "
          f"{'smooth' if args.smooth else 'flat'} in {time.perf_counter() - started:.1f} s"
          f" -> {args.out}")


if __name__ == "__main__":
    main()
