"""The scene's environment light in numpy: its radiance map read strictly, and the
radiance it sends along any direction (the reference the renderer is checked against).

    environment PATH [scale S] [rotate_y DEGREES]

The map is a latitude-longitude PFM (or OpenEXR, read here through Mitsuba's reader)
in sky.py's orientation (Mitsuba 3's envmap at
identity to_world): u = atan2(x, -z) / 2π wrapped into [0, 1), v = acos(y) / π, and
pixel (row r from the image's top, column c) is the constant radiance of the patch
u in [c, c+1]/W, v in [r, r+1]/H: the nearest pixel, no filtering.

rotate_y DEGREES turns the map about +y counter-clockwise seen from above, as a mesh's
rotate_y turns a mesh: a world direction d is looked up at mapFromWorld d, the turn by
-DEGREES. With 90, what the file shows along +x is seen along -z. scale S multiplies
the radiance. Mitsuba's envmap with to_world = rotate([0, 1, 0], DEGREES) and scale S
is the same light (tests/python/prototypes/test_environment_light.py probes it).
"""

from __future__ import annotations

import functools
import math
import os
from pathlib import Path

import numpy as np

from python_prototypes import pfm
from python_prototypes import sky
from python_prototypes import textures


def map_from_world(rotate_y_degrees: float) -> np.ndarray:
    """3x3: a world direction into the map's frame, the turn by -DEGREES about y (the
    inverse of a mesh's worldFromMesh rotation by +DEGREES)."""
    angle = math.radians(rotate_y_degrees)
    c, s = math.cos(angle), math.sin(angle)
    world_from_map = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    return world_from_map.T


def first_bad_texel(image):
    """(row, column, what) of the first texel, reading from the top row, with a value
    that is NaN, infinite or negative (what: 'nan', 'inf' or 'negative', in that order
    of precedence within a texel); None if every value is finite and >= 0."""
    image = np.asarray(image)
    bad = ~np.isfinite(image) | (image < 0)
    if not bad.any():
        return None
    row, column = np.unravel_index(np.argmax(bad.any(axis=-1)), image.shape[:2])
    texel = image[row, column]
    what = "nan" if np.isnan(texel).any() else "inf" if np.isinf(texel).any() else "negative"
    return int(row), int(column), what


EXR_MAGIC = b"\x76\x2f\x31\x01"


def decode_map(path: str) -> np.ndarray:
    """The radiance map in a PFM or an EXR file: float32 (H, W, 3), row 0 at the top
    (greyscale repeated into RGB), at most textures.MOST_IMAGE_SIDE a side as the
    chapters read it. Raises pfm.PfmError if the file is not such a map, worded as
    common/image_read.cpp's radianceMapProblem; the values are not checked here
    (first_bad_texel does)."""
    data = Path(path).read_bytes()
    if data[:4] == EXR_MAGIC:
        return decode_exr(path)
    try:
        return pfm.decode_pfm(data, textures.MOST_IMAGE_SIDE)
    except pfm.PfmError as error:
        if str(error).startswith("not a PFM image (it does not start"):
            raise pfm.PfmError("not a PFM or OpenEXR image (it starts with neither PF, Pf "
                               "nor the EXR magic number)") from None
        raise


def decode_exr(path: str) -> np.ndarray:
    """An EXR's R, G, B (or Y) channels as float32, through Mitsuba's Bitmap (the test
    layer's OpenEXR reader; the renderer's is OpenEXR itself, common/exr_file.cpp). From
    the file, not from bytes in memory: Mitsuba 3.9's reader of a cut EXR in a
    MemoryStream never returns."""
    import mitsuba
    if mitsuba.variant() is None:
        mitsuba.set_variant("scalar_rgb")
    try:
        bitmap = mitsuba.Bitmap(str(path))
    except RuntimeError as error:  # OpenEXR's reason ends the message
        reason = str(error).strip().splitlines()[-1].strip()
        reason = reason.split(": ", 1)[-1] if reason.startswith('"') else reason
        raise pfm.PfmError(f"not a readable OpenEXR image ({reason})") from None
    channels = {field.name: i for i, field in enumerate(bitmap.struct_())}
    image = np.array(bitmap, dtype=np.float32).reshape(bitmap.height(), bitmap.width(), -1)
    if all(c in channels for c in "RGB"):
        image = image[..., [channels["R"], channels["G"], channels["B"]]]
    elif "Y" in channels:
        image = np.repeat(image[..., [channels["Y"]]], 3, axis=-1)
    else:
        names = ", ".join(channels) or "none"
        raise pfm.PfmError(f"an OpenEXR image without R, G and B (or Y) channels (it has: "
                           f"{names})")
    if max(image.shape[:2]) > textures.MOST_IMAGE_SIDE:
        raise pfm.PfmError(f"too big: {image.shape[1]} x {image.shape[0]} texels: at most "
                           f"{textures.MOST_IMAGE_SIDE} a side")
    return np.ascontiguousarray(image)


@functools.lru_cache(maxsize=8)
def _cached_map(path: str, modified_ns: int, size: int) -> np.ndarray:
    image = decode_map(path)
    image.setflags(write=False)  # shared by every caller: nobody may change it
    return image


def read_map(path) -> np.ndarray:
    """decode_map of the file, read once while the file stays unchanged. A file that
    cannot be read raises pfm.PfmError("not readable"), as the C++ reader says."""
    try:
        status = os.stat(path)
        return _cached_map(str(path), status.st_mtime_ns, status.st_size)
    except OSError:
        raise pfm.PfmError("not readable") from None


# --8<-- [start:lookup]
def lookup_nearest(image, directions, scale=1.0, rotate_y_degrees=0.0) -> np.ndarray:
    """RGB (..., 3) of the map along world directions (..., 3), any length but 0:
    turned into the map's frame, then the pixel whose (u, v) patch holds them, times
    scale."""
    directions = np.asarray(directions, dtype=np.float64)
    directions = directions / np.linalg.norm(directions, axis=-1, keepdims=True)
    in_map = directions @ map_from_world(rotate_y_degrees).T
    height, width = image.shape[:2]
    row, column = sky.pixel_of_direction(in_map, width, height)
    return np.asarray(image, dtype=np.float64)[row, column] * scale
# --8<-- [end:lookup]


def environment_radiance(environment, directions) -> np.ndarray:
    """The radiance (..., 3) that a scene's environment (scene_io.Environment: path,
    scale, rotate_y_degrees) sends towards the scene along each world direction
    (..., 3): what a ray travelling along d sees when it leaves the scene."""
    return lookup_nearest(read_map(environment.path), directions, environment.scale,
                          environment.rotate_y_degrees)
