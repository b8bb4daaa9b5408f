"""Tessellate the Newell teapot into a triangle mesh and write it as an OBJ file.

The teapot is 32 bicubic Bezier patches. We evaluate each patch on an (N+1) x (N+1) grid
of (u, v) parameters, take positions and analytic normals there, weld the vertices that
neighbouring patches share, drop the zero-area triangles of the degenerate patches, and
write `v`, `vn` and `f` lines. With --uv, also `vt` lines: each patch's own (u, v), so
every patch shows a whole texture, [0, 1]^2 (textures.py); a vertex that two patches
share keeps one position and normal but has a `vt` in each.

    python python_prototypes/teapot.py --segments 3 --out teapot_n3.obj
    python python_prototypes/teapot.py --triangles 1000000 --out teapot_1m.obj
    python python_prototypes/teapot.py --segments 10 --uv --out teapot_6320_uv.obj

Each patch gives 2 * N * N triangles, less N for each of the 8 patches with a squeezed
edge. So N = 3 gives 552 triangles, about 500 (the classic flat-versus-smooth shading
comparison). N = 10 gives 6 320, N = 40 gives 102 080 and N = 126 gives 1 015 056.
"""

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

# The patch data ships with the course (public domain), so a fresh clone has it.
DEFAULT_PATCH_FILE = Path(__file__).resolve().parents[1] / "assets/data/newell_teapot.txt"
# Of the standard data set; --triangles uses them to pick N.
PATCH_COUNT = 32
DEGENERATE_PATCH_COUNT = 8  # 4 at the lid knob + 4 at the bottom centre
WELD_TOLERANCE = 1e-6  # positions closer than this (per axis) become one vertex


# ---------------------------------------------------------------------------------------
# Reading the patch file
# ---------------------------------------------------------------------------------------

def load_patches(path=DEFAULT_PATCH_FILE):
    """Read the patch file; return (patches (M, 16) int, control_points (V, 3) float64).

    The file is z-up; we return y-up control points (x, z, -y) so the teapot stands on
    y = 0, the convention of the rest of the course. That map is a rotation (determinant
    +1), so it keeps the patches' orientation and hence which way the normals point.
    """
    lines = [line.split() for line in Path(path).read_text().splitlines()]
    lines = [words for words in lines if words and not words[0].startswith("#")]

    if lines[0][0] != "vertices":
        raise ValueError(f"{path}: expected 'vertices N' first")
    vertex_count = int(lines[0][1])
    control_points_z_up = np.array(lines[1:1 + vertex_count], dtype=np.float64)

    patch_header = lines[1 + vertex_count]
    if patch_header[0] != "patches":
        raise ValueError(f"{path}: expected 'patches M' after the vertices")
    patch_count = int(patch_header[1])
    first_patch = 2 + vertex_count
    patches = np.array(lines[first_patch:first_patch + patch_count], dtype=np.int64)

    if patches.shape != (patch_count, 16) or patches.min() < 0 or \
            patches.max() >= vertex_count:
        raise ValueError(f"{path}: patches must be 16 indices into the vertex list")
    x, y, z = control_points_z_up.T
    return patches, np.stack([x, z, -y], axis=1)


# ---------------------------------------------------------------------------------------
# Evaluating bicubic Bezier patches
# ---------------------------------------------------------------------------------------

def bernstein(t):
    """Cubic Bernstein basis at parameters t: shape (len(t), 4)."""
    s = 1.0 - t
    return np.stack([s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t], axis=-1)


def bernstein_derivative(t):
    """d/dt of the cubic Bernstein basis: shape (len(t), 4)."""
    s = 1.0 - t
    return np.stack([-3.0 * s * s,
                     3.0 * s * s - 6.0 * t * s,
                     6.0 * t * s - 3.0 * t * t,
                     3.0 * t * t], axis=-1)


def evaluate_grid(control_nets, t):
    """Positions, unnormalised normals, d/du and d/dv of every patch on the grid t x t.

    control_nets has shape (M, 4, 4, 3), indexed [patch, row (v), column (u)]. The
    results have shape (M, len(t), len(t), 3), indexed [patch, v step, u step].
    """
    basis, basis_dt = bernstein(t), bernstein_derivative(t)
    positions = combine_control_points(control_nets, basis, basis)
    d_du = combine_control_points(control_nets, basis, basis_dt)
    d_dv = combine_control_points(control_nets, basis_dt, basis)
    return positions, np.cross(d_du, d_dv), d_du, d_dv


def combine_control_points(control_nets, weights_v, weights_u):
    """sum_j sum_i weights_v[a, j] * weights_u[b, i] * control_nets[p, j, i].

    Done as two small contractions (columns first, then rows) because that is much
    faster than one three-operand einsum on a million grid points.
    """
    rows = np.einsum("bi,pjic->pjbc", weights_u, control_nets)
    return np.einsum("aj,pjbc->pabc", weights_v, rows)


def evaluate_normals_at(control_nets, u, v):
    """Unnormalised normals of control_nets[k] at (u[k], v[k]), one point per net."""
    bu, bv = bernstein(u), bernstein(v)
    d_du = np.einsum("kj,ki,kjic->kc", bv, bernstein_derivative(u), control_nets)
    d_dv = np.einsum("kj,ki,kjic->kc", bernstein_derivative(v), bu, control_nets)
    return np.cross(d_du, d_dv)


def repair_degenerate_normals(control_nets, t, normals, d_du, d_dv):
    """Replace normals where d/du x d/dv vanishes (a patch edge squeezed to a point).

    At the lid knob and the bottom centre a whole patch edge is one point, so one
    derivative is zero there. The surface is still smooth, so we take the normal a tiny
    step towards the patch centre, where both derivatives are non-zero.
    """
    scale = np.sum(d_du * d_du, axis=-1) + np.sum(d_dv * d_dv, axis=-1)
    degenerate = np.linalg.norm(normals, axis=-1) <= 1e-10 * scale
    patch, v_step, u_step = np.nonzero(degenerate)
    if patch.size == 0:
        return normals
    nudge = 1e-4
    u = t[u_step] + (0.5 - t[u_step]) * nudge
    v = t[v_step] + (0.5 - t[v_step]) * nudge
    repaired = normals.copy()
    repaired[degenerate] = evaluate_normals_at(control_nets[patch], u, v)
    return repaired


def normalize_rows(vectors):
    return vectors / np.linalg.norm(vectors, axis=-1, keepdims=True)


# ---------------------------------------------------------------------------------------
# Building the triangle mesh
# ---------------------------------------------------------------------------------------

def grid_triangles(patch_count, segments):
    """Two triangles per grid cell, indices into the flattened (M, N+1, N+1) grid.

    Counter-clockwise when seen from the side d/du x d/dv points to, so the winding
    agrees with the normals: (u, v) -> (u+1, v) -> (u+1, v+1), and the other half.
    """
    side = segments + 1
    grid = np.arange(patch_count * side * side).reshape(patch_count, side, side)
    corner = grid[:, :-1, :-1]          # (u, v)
    next_u = grid[:, :-1, 1:]           # (u + 1, v)
    next_uv = grid[:, 1:, 1:]           # (u + 1, v + 1)
    next_v = grid[:, 1:, :-1]           # (u, v + 1)
    first = np.stack([corner, next_u, next_uv], axis=-1)
    second = np.stack([corner, next_uv, next_v], axis=-1)
    # Keep a cell's two triangles next to each other in the file, patch by patch.
    return np.stack([first, second], axis=-2).reshape(-1, 3)


def weld_vertices(positions, normals):
    """Merge vertices at the same position (to WELD_TOLERANCE); average their normals.

    Returns (welded positions, welded unit normals, old-to-new index map).
    """
    keys = np.round(positions / WELD_TOLERANCE).astype(np.int64)
    _, first_index, old_to_new = np.unique(keys, axis=0, return_index=True,
                                           return_inverse=True)
    old_to_new = old_to_new.reshape(-1)
    welded_positions = positions[first_index]
    normal_sums = np.zeros_like(welded_positions)
    np.add.at(normal_sums, old_to_new, normals)
    return welded_positions, normalize_rows(normal_sums), old_to_new


def proper_triangles(triangles, positions):
    """True for the triangles that neither repeat a vertex nor have (numerically) zero
    area."""
    repeats = ((triangles[:, 0] == triangles[:, 1]) | (triangles[:, 1] == triangles[:, 2])
               | (triangles[:, 2] == triangles[:, 0]))
    a, b, c = (positions[triangles[:, k]] for k in range(3))
    twice_area = np.linalg.norm(np.cross(b - a, c - a), axis=-1)
    return ~repeats & (twice_area > 1e-12)


def drop_degenerate_triangles(triangles, positions):
    """Remove triangles that repeat a vertex or have (numerically) zero area."""
    return triangles[proper_triangles(triangles, positions)]


def tessellate(patches, control_points, segments, with_uv=False):
    """Tessellate all patches with segments x segments cells each.

    Returns (positions (V, 3) float64, unit normals (V, 3) float64,
    triangles (T, 3) int64 zero-based, counter-clockwise seen from outside); with_uv
    adds (texcoords (K, 2) float64, triangle_texcoords (T, 3) int64): every patch has
    the same (N+1)^2 grid of (u, v), so K = (N+1)^2, shared by all patches.
    """
    if segments < 1:
        raise ValueError("segments must be at least 1")
    control_nets = control_points[patches].reshape(-1, 4, 4, 3)
    t = np.linspace(0.0, 1.0, segments + 1)
    positions, normals, d_du, d_dv = evaluate_grid(control_nets, t)
    normals = repair_degenerate_normals(control_nets, t, normals, d_du, d_dv)

    positions = positions.reshape(-1, 3)
    normals = normalize_rows(normals.reshape(-1, 3))
    triangles = grid_triangles(len(patches), segments)

    positions, normals, old_to_new = weld_vertices(positions, normals)
    kept = proper_triangles(old_to_new[triangles], positions)
    if not with_uv:
        return positions, normals, old_to_new[triangles][kept]
    # Grid point (patch, v step, u step) has (u, v) = (t[u step], t[v step]).
    v_grid, u_grid = np.meshgrid(t, t, indexing="ij")
    texcoords = np.stack([u_grid.ravel(), v_grid.ravel()], axis=1)
    triangle_texcoords = triangles[kept] % len(texcoords)
    return positions, normals, old_to_new[triangles][kept], texcoords, triangle_texcoords


def expected_triangle_count(segments):
    """Triangles tessellate() keeps: each degenerate patch loses one row of N."""
    return PATCH_COUNT * 2 * segments * segments - DEGENERATE_PATCH_COUNT * segments


def segments_for_triangles(target):
    """The smallest segment count whose mesh has at least `target` triangles."""
    segments = max(1, math.isqrt(max(target, 0) // (2 * PATCH_COUNT)))
    while segments > 1 and expected_triangle_count(segments - 1) >= target:
        segments -= 1
    while expected_triangle_count(segments) < target:
        segments += 1
    return segments


# ---------------------------------------------------------------------------------------
# Writing the OBJ file
# ---------------------------------------------------------------------------------------

def format_rows(template, rows, chunk=200_000):
    """Format each row of `rows` with `template`, e.g. 'v %.6f %.6f %.6f\\n'.

    One big %-format per chunk runs in C, which is much faster than a Python loop
    (np.savetxt formats row by row); chunks keep the temporary tuples small.
    """
    pieces = []
    for start in range(0, len(rows), chunk):
        block = rows[start:start + chunk]
        pieces.append((template * len(block)) % tuple(block.ravel().tolist()))
    return "".join(pieces)


def write_obj(path, positions, normals, triangles, header_lines=(), texcoords=None,
              triangle_texcoords=None):
    """Write an OBJ file. normals may be None; otherwise one normal per position.
    texcoords (K, 2), if given, are indexed by triangle_texcoords (T, 3)."""
    one_based = triangles + 1
    if texcoords is not None:
        # "f a/t/a ...": position and normal share an index, the vt has its own.
        corners = [one_based, triangle_texcoords + 1] + ([] if normals is None
                                                        else [one_based])
        corner = "%d/%d/%d" if normals is not None else "%d/%d"
        faces = format_rows("f " + " ".join([corner] * 3) + "\n",
                            np.stack(corners, axis=-1).reshape(len(triangles), -1))
    elif normals is None:
        faces = format_rows("f %d %d %d\n", one_based)
    else:
        # Vertex and normal share the index: "f a//a b//b c//c".
        faces = format_rows("f %d//%d %d//%d %d//%d\n", np.repeat(one_based, 2, axis=1))
    with open(path, "w", newline="\n") as obj:
        for line in header_lines:
            obj.write(f"# {line}\n")
        obj.write(f"# {len(positions)} vertices, {len(triangles)} triangles\n")
        obj.write(format_rows("v %.6f %.6f %.6f\n", positions))
        if normals is not None:
            obj.write(format_rows("vn %.6f %.6f %.6f\n", normals))
        if texcoords is not None:
            obj.write(format_rows("vt %.6f %.6f\n", texcoords))
        obj.write(faces)


# ---------------------------------------------------------------------------------------
# Command line
# ---------------------------------------------------------------------------------------

def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    size = parser.add_mutually_exclusive_group(required=True)
    size.add_argument("--segments", type=int, help="grid cells per patch side (N)")
    size.add_argument("--triangles", type=int,
                      help="pick the smallest N giving at least this many triangles")
    parser.add_argument("--out", required=True, type=Path, help="OBJ file to write")
    parser.add_argument("--no-normals", action="store_true", help="omit vn lines")
    parser.add_argument("--uv", action="store_true",
                        help="write vt lines: each patch's (u, v) over [0, 1]^2")
    parser.add_argument("--patches", type=Path, default=DEFAULT_PATCH_FILE,
                        help=f"patch file (default: {DEFAULT_PATCH_FILE})")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    if args.segments is not None:
        segments = args.segments
    else:
        segments = segments_for_triangles(args.triangles)
    if segments < 1:
        sys.exit("teapot.py: --segments must be at least 1")

    patches, control_points = load_patches(args.patches)
    started = time.perf_counter()
    positions, normals, triangles, *uv = tessellate(patches, control_points, segments,
                                                    with_uv=args.uv)
    tessellated = time.perf_counter()
    header = [f"Newell teapot, y-up, standing on y = 0, {segments} x {segments} cells "
              "per patch" + (", vt: each patch's (u, v)" if args.uv else ""),
              f"generated by python_prototypes/teapot.py --segments {segments}"
              + (" --uv" if args.uv else "")]
    write_obj(args.out, positions, None if args.no_normals else normals, triangles,
              header, *uv)
    written = time.perf_counter()
    print(f"{len(triangles)} triangles, {len(positions)} vertices, N = {segments} -> "
          f"{args.out} (tessellate {tessellated - started:.2f} s, "
          f"write {written - tessellated:.2f} s)")


if __name__ == "__main__":
    main()
