"""Textures as chapter 17's shaders look them up: the numpy reference the GPU images are
compared with, and which Mitsuba 3 is checked against (tests/python/
test_texture_prototypes.py).

Texture coordinates (u, v): a quad's are (a, b), the fractions along its first and
second edge from its origin corner; a mesh's are its OBJ `vt`, interpolated with the
hit's barycentric weights. v runs up the image, as in OBJ files:

    image W x H, texel (row r from the TOP of the file, column c)
    x = u W - 1/2,  y = (1 - v) H - 1/2       continuous texel coordinates: texel
                                              (r, c)'s centre is at x = c, y = r
    bilinear between the four texel centres around (x, y); indices wrap (mod W, H),
    so the image repeats beyond [0, 1]. vt (0, 0) is the image's bottom-left corner.

An image's 8-bit values are sRGB-encoded: each is decoded to linear before filtering
(as a GL SRGB8 texture does), unless the scene says `linear`. Alpha is ignored; a
grey image is repeated into R, G and B.

    checker:  (s, t) = S (u, v); colour0 where (frac(s) > 1/2) == (frac(t) > 1/2),
              else colour1 (Mitsuba's `checkerboard`, to_uv a scale by S).

Mitsuba 3 is checked against this. Its `bitmap` puts v = 0 on the image's top row and
its `obj` loader flips v on reading, so left alone it agrees for images on meshes but
shows them upside down on its `rectangle` (uv (a, b), as ours), and its checkerboard
upside down on meshes; mitsuba_reference.py maps the scene so that it agrees on all.
"""

from __future__ import annotations

import functools
import struct
from pathlib import Path

import numpy as np

from python_prototypes import srgb

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
JPEG_SIGNATURE = b"\xff\xd8\xff"
MOST_IMAGE_SIDE = 8192  # common/course/image_read.h's kMostImageSide


# The sRGB transfer function undone: encoded fractions in [0, 1] -> linear.
srgb_to_linear = srgb.decode


def image_problem(path) -> str:
    """'' for a PNG or JPEG file of a size the chapters read, else what is wrong with
    it. Reads the header only, as the C++ reader's imageProblem() does (a JPEG's size
    is left to the decoder)."""
    with open(path, "rb") as file:
        header = file.read(24)
    if header.startswith(JPEG_SIGNATURE):
        return ""
    if not (header.startswith(PNG_SIGNATURE) and header[12:16] == b"IHDR"):
        return "not a PNG or JPEG image"
    width, height = struct.unpack(">II", header[16:24])
    if width > MOST_IMAGE_SIDE or height > MOST_IMAGE_SIDE:
        return f"too big: {width} x {height} texels: at most {MOST_IMAGE_SIDE} a side"
    return ""


def read_image(path, linear: bool = False) -> np.ndarray:
    """(H, W, 3) float64 linear RGB, row 0 the top row of the file."""
    from PIL import Image  # the test layer's Pillow (matplotlib's); the build needs none
    with Image.open(path) as image:
        values = np.asarray(image.convert("RGB"), dtype=np.float64) / 255.0
    return values if linear else srgb_to_linear(values)


@functools.lru_cache(maxsize=16)
def cached_image(path, linear: bool) -> np.ndarray:
    """read_image once per file: a test looks up every pixel of several renders."""
    return read_image(path, linear)


def bilinear_repeat(image: np.ndarray, u, v) -> np.ndarray:
    """The image (H, W, C) at texture coordinates u, v (any matching shapes): (..., C)."""
    height, width = image.shape[:2]
    x = np.asarray(u, dtype=np.float64) * width - 0.5
    y = (1.0 - np.asarray(v, dtype=np.float64)) * height - 0.5
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]  # weights of the right, lower texels
    c0, r0 = x0.astype(np.int64) % width, y0.astype(np.int64) % height  # repeat
    c1, r1 = (c0 + 1) % width, (r0 + 1) % height
    top = image[r0, c0] * (1 - fx) + image[r0, c1] * fx
    bottom = image[r1, c0] * (1 - fx) + image[r1, c1] * fx
    return top * (1 - fy) + bottom * fy


def checker(color0, color1, scale: float, u, v) -> np.ndarray:
    """Squares of two colours, `scale` of each per unit of u and of v: (..., 3)."""
    s, t = scale * np.asarray(u, dtype=np.float64), scale * np.asarray(v, dtype=np.float64)
    first = (s - np.floor(s) > 0.5) == (t - np.floor(t) > 0.5)
    return np.where(first[..., None], np.asarray(color0, dtype=np.float64),
                    np.asarray(color1, dtype=np.float64))


def lookup(texture, u, v) -> np.ndarray:
    """A scene_io.Texture's linear RGB at (u, v): (..., 3)."""
    if texture.kind == "checker":
        return checker(texture.color0, texture.color1, texture.scale, u, v)
    return bilinear_repeat(cached_image(Path(texture.path), texture.linear), u, v)
