"""A small, strict OBJ reader: the independent Python reference for the course's parser.

read_obj(path) -> (positions (N, 3), normals (K, 3) or None,
                   triangle_positions (M, 3), triangle_normals (M, 3) or None)
Triangle indices are zero-based. Polygons are fan-triangulated: (0, i, i + 1).
Any problem raises ObjError("file:line: message"); line 0 means the file as a whole.
"""

import math
import re

import numpy as np

IGNORED_KEYWORDS = {"vt", "g", "o", "s", "usemtl", "mtllib"}
CONTROL_BYTES = re.compile(rb"[\x00-\x08\x0b\x0c\x0e-\x1f\x7f]")  # all but \t \n \r


class ObjError(ValueError):
    """A problem in an OBJ file; the message starts with 'file:line: '."""


def parse_numbers(words):
    values = []
    for word in words:
        try:
            value = float(word)
        except ValueError:
            raise ObjError(f"'{word}' is not a number") from None
        if not math.isfinite(value):
            raise ObjError(f"'{word}' is not a finite number")  # quotes the nan / inf
        values.append(value)
    return values


def resolve_index(word, count, kind):
    """1-based, or negative (relative to the `count` elements so far) -> 0-based."""
    try:
        index = int(word)
    except ValueError:
        raise ObjError(f"bad face vertex: {kind} index '{word}' is not an integer") from None
    if index == 0:
        raise ObjError(f"{kind} index 0 is invalid: OBJ indices start at 1")
    resolved = index - 1 if index > 0 else count + index
    if not 0 <= resolved < count:
        plural = "vertices" if kind == "vertex" else kind + "s"
        raise ObjError(f"{kind} index {index} out of range ({count} {plural} so far)")
    return resolved


def parse_face_vertex(token, position_count, normal_count):
    """'v', 'v/vt', 'v//vn' or 'v/vt/vn' -> (position index, normal index or None)."""
    parts = token.split("/")  # the vt part is not used, so it is not checked
    if len(parts) > 3 or parts[0] == "" or (len(parts) == 3 and parts[2] == ""):
        raise ObjError(f"bad face vertex '{token}'")
    position = resolve_index(parts[0], position_count, "vertex")
    if len(parts) == 3:
        return position, resolve_index(parts[2], normal_count, "normal")
    return position, None


def parse_line(words, positions, normals, faces):
    """Handle one non-empty line, appending to the lists it fills."""
    keyword, args = words[0], words[1:]
    if keyword == "v":
        if len(args) < 3:
            raise ObjError(f"'v' needs 3 numbers, got {len(args)}")
        positions.append(parse_numbers(args)[:3])  # a 4th w or r g b colour is ignored
    elif keyword == "vn":
        if len(args) != 3:
            raise ObjError(f"'vn' needs 3 numbers, got {len(args)}")
        normals.append(parse_numbers(args))
    elif keyword == "f":
        if len(args) < 3:
            raise ObjError(f"a face needs at least 3 vertices, got {len(args)}")
        corners = [parse_face_vertex(t, len(positions), len(normals)) for t in args]
        with_normals = {normal is not None for _, normal in corners}
        if len(with_normals) > 1 or (faces and with_normals != {faces[0][0][1] is not None}):
            raise ObjError("face mixes corners with and without normals")
        faces.append(corners)
    elif keyword not in IGNORED_KEYWORDS:
        raise ObjError(f"unknown keyword '{keyword}'")


def read_obj(path):
    data = open(path, "rb").read()
    if not data:
        raise ObjError(f"{path}:0: empty file")
    positions, normals, faces = [], [], []
    for line_number, line in enumerate(data.split(b"\n"), start=1):
        try:
            if CONTROL_BYTES.search(line):
                raise ObjError("binary data (control bytes) in a text file")
            words = line.decode("latin-1").split()  # split() also drops a CRLF's \r
            if words and not words[0].startswith("#"):
                parse_line(words, positions, normals, faces)
        except ObjError as error:
            raise ObjError(f"{path}:{line_number}: {error}") from None
    if not faces:
        raise ObjError(f"{path}:0: no faces")

    triangles = np.array([(face[0], face[i], face[i + 1])
                          for face in faces for i in range(1, len(face) - 1)])
    return (np.array(positions, dtype=np.float64),
            np.array(normals, dtype=np.float64) if normals else None,
            triangles[:, :, 0].astype(np.int64),
            triangles[:, :, 1].astype(np.int64) if faces[0][0][1] is not None else None)
