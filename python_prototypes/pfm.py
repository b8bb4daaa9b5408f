"""PFM, the portable float map: linear RGB floats, as the chapters write with --out
x.pfm and the prototypes read and write (Mitsuba 3's renders, the sky map).

Header "PF", then "width height", then a scale whose sign is the byte order (negative:
little-endian); then the rows from the bottom of the image up, as the format says.
"Pf" is the same with one float per pixel (greyscale).

read_pfm is the quick reader of files we wrote ourselves; decode_pfm is the strict one
for files a user names (an environment map in a scene file): every way the bytes can
fail to be a PFM gets its own reason."""

from __future__ import annotations

import os
import re
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


class PfmError(ValueError):
    """Why some bytes are not a PFM image (a reason, without the file's name)."""


# Magic, width, height and scale, each followed by whitespace; the single whitespace
# byte after the scale (normally a newline) is the last byte of the header.
PFM_HEADER = re.compile(rb"(P[Ff])\s+(\S+)\s+(\S+)\s+(\S+)\s", re.DOTALL)


def decode_pfm(data: bytes) -> np.ndarray:
    """A PFM's pixels as float32 (height, width, 3), row 0 at the top; a greyscale
    "Pf" is repeated into R, G and B. Raises PfmError with the reason otherwise."""
    if data[:2] not in (b"PF", b"Pf"):
        raise PfmError("it does not start with 'PF' (RGB) or 'Pf' (greyscale)")
    header = PFM_HEADER.match(data)
    if header is None:
        raise PfmError("its header (PF or Pf, the width, the height, the scale) is cut "
                       "short")
    magic, width_word, height_word, scale_word = header.groups()
    width_text, height_text = width_word.decode("latin-1"), height_word.decode("latin-1")
    if not (width_word.isdigit() and height_word.isdigit()
            and int(width_word) > 0 and int(height_word) > 0):
        raise PfmError(f"its size '{width_text}' x '{height_text}' is not two whole "
                       "numbers above 0")
    scale_text = scale_word.decode("latin-1")
    try:
        scale = float(scale_text)
    except ValueError:
        scale = float("nan")
    if not (scale != 0 and abs(scale) < float("inf")):
        raise PfmError(f"its scale '{scale_text}' is not a number other than 0 (its sign "
                       "gives the byte order)")
    width, height = int(width_word), int(height_word)
    channels = 3 if magic == b"PF" else 1
    pixels = data[header.end():]
    needed = width * height * channels * 4
    if len(pixels) != needed:
        raise PfmError(f"{width} x {height} pixels of {channels} float"
                       f"{'s' if channels > 1 else ''} need {needed} bytes after the "
                       f"header, and it has {len(pixels)}")
    values = np.frombuffer(pixels, dtype="<f4" if scale < 0 else ">f4")
    image = values.reshape(height, width, channels)[::-1].astype(np.float32)
    return np.repeat(image, 3, axis=2) if channels == 1 else image
