"""The images chapter 17's scenes and tests use, made at build time into
build/assets/textures/ (cmake/Assets.cmake), so no binary file is committed:

    test_pattern.png   8 x 4 texels, each a different sRGB colour known exactly
                       (pattern_texel): read-back and filtering tests
    uv_grid.png        256 x 256: red grows with u, green with v, an 8 x 8 grid of
                       cells and a black letter F upright near vt (0, 0), so that an
                       image turned or mirrored on a surface is plain to see

The build has numpy only, so the PNG files are written here with zlib and struct: a
signature, an IHDR chunk (size, 8-bit RGB), one IDAT chunk (the rows, each behind a
filter byte 0, deflated) and IEND; each chunk is length, type, data, CRC-32.

    python python_prototypes/texture_images.py --out build/assets/textures
"""

from __future__ import annotations

import argparse
import os
import struct
import sys
import zlib
from pathlib import Path

import numpy as np

TEST_PATTERN_SIZE = (8, 4)  # width, height
UV_GRID_SIZE = 256


def png_bytes(rgb: np.ndarray) -> bytes:
    """An 8-bit RGB image (H, W, 3) uint8, row 0 the top, as PNG file contents."""
    height, width, _ = rgb.shape

    def chunk(kind: bytes, data: bytes) -> bytes:
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data)))

    # Width, height, bit depth 8, colour type 2 (RGB), deflate, filters, no interlace.
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    rows = np.concatenate([np.zeros((height, 1), np.uint8),  # filter byte 0: none
                           np.ascontiguousarray(rgb, np.uint8).reshape(height, -1)], axis=1)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
            + chunk(b"IDAT", zlib.compress(rows.tobytes(), 9)) + chunk(b"IEND", b""))


def write_png(path: Path, rgb: np.ndarray) -> None:
    """Under a temporary name first, so that a stopped build leaves no half image."""
    partial = path.with_name(path.name + ".partial")
    partial.write_bytes(png_bytes(rgb))
    os.replace(partial, path)


def pattern_texel(row, column):
    """The 8-bit sRGB values of test_pattern.png's texel (row from the top, column):
    red and green tell the column and row; blue runs through 0 and 8, in the linear
    part of the sRGB curve (below 0.04045 * 255 = 10.3), up to 248."""
    row, column = np.asarray(row), np.asarray(column)
    return np.stack([16 + 32 * column, 32 + 64 * row, 8 * (8 * row + column)], axis=-1)


def make_test_pattern() -> np.ndarray:
    width, height = TEST_PATTERN_SIZE
    rows, columns = np.meshgrid(np.arange(height), np.arange(width), indexing="ij")
    return pattern_texel(rows, columns).astype(np.uint8)


def make_uv_grid(size: int = UV_GRID_SIZE) -> np.ndarray:
    """Drawn in (u, v) at each texel's centre, v up, as a surface shows it."""
    u = (np.arange(size) + 0.5) / size
    v = 1.0 - (np.arange(size) + 0.5) / size
    u, v = np.meshgrid(u, v)  # (size, size), row 0 at the top (v near 1)
    cells = 8
    dim = ((np.floor(u * cells) + np.floor(v * cells)) % 2) * 0.25  # alternate cells
    rgb = np.stack([0.15 + 0.85 * u, 0.15 + 0.85 * v, 0.6 - 0.4 * u * v], axis=-1)
    rgb *= (1.0 - dim)[..., None]
    line = 1.5 / size  # grid lines about 3 texels wide
    on_line = (np.abs(u * cells - np.round(u * cells)) < line * cells) | \
        (np.abs(v * cells - np.round(v * cells)) < line * cells)
    rgb[on_line] = 1.0

    def box(u0, u1, v0, v1):
        return (u >= u0) & (u < u1) & (v >= v0) & (v < v1)
    letter_f = (box(0.08, 0.14, 0.08, 0.42) | box(0.08, 0.34, 0.36, 0.42)
                | box(0.08, 0.28, 0.22, 0.28))
    rgb[letter_f] = 0.0
    return np.round(rgb * 255).astype(np.uint8)


IMAGES = {"test_pattern.png": make_test_pattern, "uv_grid.png": make_uv_grid}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", required=True, help="folder for the PNG files")
    args = parser.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for name, make in IMAGES.items():
        image = make()
        write_png(out / name, image)
        print(f"wrote {out / name} ({image.shape[1]} x {image.shape[0]})")


if __name__ == "__main__":
    sys.exit(main())
