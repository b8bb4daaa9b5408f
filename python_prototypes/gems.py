"""Faceted gems as OBJ meshes, for the Cornell box scene "gems" (chapter 11).

Three cuts, each a closed convex solid of flat facets, wound counter-clockwise seen
from outside (so cross(b - a, c - a) points out), standing on the plane y = 0 about
the y axis, the girdle (the widest outline) reaching x = +-1:

    brilliant    a round brilliant, simplified: a table of k sides; a crown of 2k
                 triangles between the table and a k-sided girdle turned half a step;
                 a short girdle band; a pavilion of k triangles down to a point (the
                 culet), which rests on y = 0. (k = 12: 70 triangles.)
    octahedron   a rough diamond crystal: 8 triangles, stretched along y, on one tip.
    emerald      a step cut, 2 long (x) and 1.4 wide (z): an octagon (a rectangle
                 with cut corners) for the table, one ring of step facets down to the
                 girdle, the girdle band, one ring of step facets below it, and a keel
                 (a ridge, not a point) at y = 0. (64 triangles.)

Each facet is one OBJ face (a polygon where the facet has more than three corners) with
its own `vn` normal, so the gems stay faceted under chapter 08's interpolated normals.

    python python_prototypes/gems.py --out build/assets/meshes
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path

import numpy as np

CUTS = ("brilliant", "octahedron", "emerald")


def ring(count, radius, height, turn=0.0):
    """`count` points on a horizontal circle, counter-clockwise seen from above (+y)."""
    angles = -(np.arange(count) + turn) * 2 * math.pi / count  # -: x towards -z is CCW
    return np.stack([radius * np.cos(angles), np.full(count, height),
                     radius * np.sin(angles)], axis=1)


# ---------------------------------------------------------------------------------------
# The cuts: each returns (vertices (V, 3), faces [list of vertex indices]), every face
# counter-clockwise seen from outside.
# ---------------------------------------------------------------------------------------

def brilliant(sides=12, table_radius=0.57, crown_height=0.30, girdle_height=0.03,
              pavilion_depth=0.86):
    """Proportions of a round brilliant: crown angle about 35, pavilion about 41 degrees."""
    girdle_low = pavilion_depth
    girdle_high = girdle_low + girdle_height
    table = ring(sides, table_radius, girdle_high + crown_height, turn=0.5)
    upper = ring(sides, 1.0, girdle_high)
    lower = ring(sides, 1.0, girdle_low)
    culet = np.array([[0.0, 0.0, 0.0]])
    vertices = np.concatenate([table, upper, lower, culet])
    t, u, l, c = 0, sides, 2 * sides, 3 * sides  # where each group starts

    faces = [[t + i for i in range(sides)]]  # the table, CCW seen from above
    for i in range(sides):
        j = (i + 1) % sides
        # Crown: table corner i lies above the middle of girdle edge (i, i + 1).
        faces.append([u + i, u + j, t + i])          # a main facet's lower triangle
        faces.append([t + i, u + j, t + j])          # between two table corners
        faces.append([l + i, l + j, u + j, u + i])   # girdle band
        faces.append([l + j, l + i, c])              # pavilion, down to the culet
    return vertices, faces


def octahedron(height=1.3):
    """Tips on the y axis at 0 and 2 * height, the girdle square at y = height."""
    square = ring(4, 1.0, height)
    vertices = np.concatenate([square, [[0.0, 2 * height, 0.0], [0.0, 0.0, 0.0]]])
    top, bottom = 4, 5
    faces = []
    for i in range(4):
        j = (i + 1) % 4
        faces.append([i, j, top])
        faces.append([j, i, bottom])
    return vertices, faces


def octagon(half_length, half_width, corner, height):
    """A rectangle along x with its corners cut by `corner`, CCW seen from above."""
    a, b, c = half_length, half_width, corner
    points = [(a, -(b - c)), (a, b - c), (a - c, b), (-(a - c), b),
              (-a, b - c), (-a, -(b - c)), (-(a - c), -b), (a - c, -b)]
    # CCW seen from above (+y): with x right and z down the page, that is -z before +z.
    points = [(x, -z) for x, z in points]
    return np.array([[x, height, z] for x, z in points])


def emerald(half_length=1.0, half_width=0.7, corner=0.22, table_scale=0.62,
            crown_height=0.22, girdle_height=0.05, step_scale=0.62, step_depth=0.36,
            keel_depth=0.30):
    """Rings scaled evenly about the y axis keep their edges parallel, so the step
    facets between them are flat trapezoids; the keel runs along x."""
    def scaled(scale, height):
        return octagon(half_length * scale, half_width * scale, corner * scale, height)

    girdle_low = keel_depth + step_depth
    girdle_high = girdle_low + girdle_height
    rings = [scaled(table_scale, girdle_high + crown_height), scaled(1.0, girdle_high),
             scaled(1.0, girdle_low), scaled(step_scale, keel_depth)]
    keel_half = (half_length - half_width) * step_scale  # shorter than the step ring
    keel = np.array([[keel_half, 0.0, 0.0], [-keel_half, 0.0, 0.0]])
    vertices = np.concatenate(rings + [keel])
    start = [8 * r for r in range(4)]
    front, back = 32, 33  # keel ends: +x and -x

    faces = [[start[0] + i for i in range(8)]]  # the table
    for r in range(3):  # crown steps, girdle band, pavilion steps
        upper, lower = start[r], start[r + 1]
        for i in range(8):
            j = (i + 1) % 8
            faces.append([lower + i, lower + j, upper + j, upper + i])
    # The keel: ring 3's corners on the +x half (0, 1, 2, 7) slope down to the keel's
    # front end, the others to its back end. An edge whose corners go to one end makes a
    # triangle; the two long sides, whose corners go to both ends, make trapezoids.
    last = start[3]

    def keel_end(corner):
        return front if corner in (0, 1, 2, 7) else back

    for i in range(8):
        j = (i + 1) % 8
        if keel_end(i) == keel_end(j):
            faces.append([last + j, last + i, keel_end(i)])
        else:
            faces.append([last + j, last + i, keel_end(i), keel_end(j)])
    return vertices, faces


def make_gem(cut: str, **parameters):
    if cut == "brilliant":
        return brilliant(**parameters)
    if cut == "octahedron":
        return octahedron(**parameters)
    if cut == "emerald":
        return emerald(**parameters)
    raise ValueError(f"unknown cut {cut!r}; the cuts are {', '.join(CUTS)}")


# ---------------------------------------------------------------------------------------
# Checks and output
# ---------------------------------------------------------------------------------------

def face_normal(vertices, face):
    """Newell's normal of a polygon: the area-weighted normal, unit length."""
    points = vertices[face]
    following = np.roll(points, -1, axis=0)
    normal = np.sum(np.cross(points, following), axis=0)
    return normal / np.linalg.norm(normal)


def triangles(faces):
    """Fan triangulation (0, i, i + 1), as the course's OBJ loaders do."""
    return [(face[0], face[i], face[i + 1]) for face in faces for i in range(1, len(face) - 1)]


def signed_volume(vertices, faces):
    return sum(np.dot(vertices[a], np.cross(vertices[b], vertices[c]))
               for a, b, c in triangles(faces)) / 6.0


def check_gem(vertices, faces, tolerance=1e-9):
    """Raises ValueError unless the gem is closed, wound outwards, flat-faceted and convex."""
    edges = {}
    for face in faces:
        for a, b in zip(face, face[1:] + face[:1]):
            if (a, b) in edges:
                raise ValueError(f"edge {a}-{b} used twice in the same direction")
            edges[(a, b)] = True
    for a, b in edges:
        if (b, a) not in edges:
            raise ValueError(f"edge {a}-{b} has no neighbour: the mesh is not closed")
    for face in faces:
        normal = face_normal(vertices, face)
        offsets = (vertices[face] - vertices[face[0]]) @ normal
        if np.abs(offsets).max() > tolerance:
            raise ValueError(f"face {face} is not flat")
        # Convex and outward: every vertex on the inner side of every facet's plane.
        if ((vertices - vertices[face[0]]) @ normal).max() > tolerance:
            raise ValueError(f"face {face} does not face outwards, or the gem is not convex")
    if signed_volume(vertices, faces) <= 0:
        raise ValueError("negative volume: the faces are wound inwards")


def obj_text(name, vertices, faces):
    lines = [f"# {name}: {len(triangles(faces))} triangles in {len(faces)} flat facets, "
             "written by python_prototypes/gems.py",
             "# Each facet has its own normal, so the gem stays faceted."]
    lines += [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in vertices]
    normals = [face_normal(vertices, face) for face in faces]
    lines += [f"vn {x:.9g} {y:.9g} {z:.9g}" for x, y, z in normals]
    for n, face in enumerate(faces, start=1):
        lines.append("f " + " ".join(f"{v + 1}//{n}" for v in face))
    return "\n".join(lines) + "\n"


def write_gem(path: Path, cut: str):
    """Writes one gem, under a temporary name first so that no half file is left."""
    vertices, faces = make_gem(cut)
    check_gem(vertices, faces)
    partial = path.with_name(path.name + ".partial")
    partial.write_text(obj_text(path.stem, vertices, faces))
    os.replace(partial, path)
    return len(triangles(faces))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", required=True, help="folder for gem_<cut>.obj")
    parser.add_argument("--cuts", nargs="+", choices=CUTS, default=list(CUTS))
    args = parser.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for cut in args.cuts:
        path = out / f"gem_{cut}.obj"
        count = write_gem(path, cut)
        print(f"wrote {path} ({count} triangles)")


if __name__ == "__main__":
    sys.exit(main())
