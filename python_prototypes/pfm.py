"""PFM, the portable float map: linear RGB floats, as the chapters write with --out
x.pfm and the prototypes read and write (Mitsuba 3's renders, the sky map).

Header "PF", then "width height", then a scale whose sign is the byte order (negative:
little-endian); then the rows from the bottom of the image up, as the format says."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np


def write_pfm(path, image) -> None:
    """Writes (height, width, 3+) linear RGB, row 0 at the top, as little-endian float32.
    Under a temporary name and renamed, so that no reader ever sees half a file."""
    path = Path(path)
    height, width = image.shape[:2]
    rows = np.ascontiguousarray(np.asarray(image)[::-1, :, :3], dtype="<f4")
    partial = path.with_name(path.name + ".partial")
    with open(partial, "wb") as file:
        file.write(f"PF\n{width} {height}\n-1.0\n".encode("ascii"))
        file.write(rows.tobytes())
    os.replace(partial, path)


def read_pfm(path) -> np.ndarray:
    """An RGB PFM as float64 (height, width, 3), row 0 at the top."""
    data = Path(path).read_bytes()
    header = data.split(b"\n", 3)
    if header[0] != b"PF":
        raise ValueError(f"{path}: not an RGB PFM")
    width, height = map(int, header[1].split())
    dtype = "<f4" if float(header[2]) < 0 else ">f4"
    pixels = np.frombuffer(header[3], dtype=dtype, count=width * height * 3)
    return pixels.reshape(height, width, 3)[::-1].astype(np.float64)
