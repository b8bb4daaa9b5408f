"""PFM, the portable float map: linear RGB floats, as the chapters write with --out
x.pfm and the prototypes read and write (Mitsuba 3's renders, the sky map).

Header "PF", then "width height", then a scale whose sign is the byte order (negative:
little-endian); then the rows from the bottom of the image up, as the format says.
"Pf" is the same with one float per pixel (greyscale).

One reader for the whole course (the checks, the grader, the benches, the prototypes):
decode_pfm reads the bytes as the C++ reader does, and every way they can fail to be a
PFM gets its own reason; read_pfm and parse_pfm are it for an RGB image, as float64,
with the file's name in the reason (a grader's report shows it to a student)."""

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


class PfmError(ValueError):
    """Why some bytes are not a PFM image we read, worded as common/image_read.cpp's
    pfmProblem words it (after "is "): "not a PFM image (...)", "too big: ...",
    "not a whole PFM image (...)"."""


NOT_PFM = "not a PFM image (it does not start with PF or Pf)"
BAD_HEADER = "not a PFM image (a bad width, height or scale line)"
CUT_SHORT = "not a whole PFM image (the file ends before its last row)"
TOKEN = re.compile(rb"\s*(\S+)")
WHOLE_NUMBER = re.compile(rb"[+-]?[0-9]+\Z")


def decode_pfm(data: bytes, most_side: int | None = None) -> np.ndarray:
    """A PFM's pixels as float32 (height, width, 3), row 0 at the top; a greyscale "Pf"
    is repeated into R, G and B. The header is read as the C++ reader reads it: "PF" or
    "Pf", the width, the height and the scale (its sign the byte order) as words
    separated by white space, then one white-space byte, then the floats (more bytes
    after them are ignored). most_side: the largest width or height accepted. Raises
    PfmError with the C++ reader's reason otherwise."""
    position, words = 0, []
    for _ in range(4):
        token = TOKEN.match(data, position)
        if token is None:
            break
        words.append(token.group(1))
        position = token.end()
    if not words or words[0] not in (b"PF", b"Pf"):
        raise PfmError(NOT_PFM)
    if len(words) < 4 or not (WHOLE_NUMBER.match(words[1]) and WHOLE_NUMBER.match(words[2])):
        raise PfmError(BAD_HEADER)
    width, height = int(words[1]), int(words[2])
    try:
        scale = float(words[3])
    except ValueError:
        raise PfmError(BAD_HEADER) from None
    if width <= 0 or height <= 0 or scale == 0 or not np.isfinite(scale):
        raise PfmError(BAD_HEADER)
    if most_side is not None and (width > most_side or height > most_side):
        raise PfmError(f"too big: {width} x {height} texels: at most {most_side} a side")
    channels = 3 if words[0] == b"PF" else 1
    start = position + 1  # the one white-space byte after the scale
    needed = width * height * channels * 4
    if len(data) - start < needed:
        raise PfmError(CUT_SHORT)
    values = np.frombuffer(data, dtype="<f4" if scale < 0 else ">f4",
                           count=width * height * channels, offset=start)
    image = values.reshape(height, width, channels)[::-1].astype(np.float32)
    return np.repeat(image, 3, axis=2) if channels == 1 else image


def parse_pfm(data: bytes, name: str = "image") -> np.ndarray:
    """The bytes of an RGB PFM ("PF") as float64 (height, width, 3), row 0 at the top.
    Raises PfmError (a ValueError) naming `name` and what is wrong: a greyscale "Pf" is
    refused here, since every picture the course writes is RGB."""
    if data[:2] != b"PF" or data[2:3].isalnum():
        raise PfmError(f"{name} is not an RGB PFM")
    try:
        return decode_pfm(data).astype(np.float64)
    except PfmError as problem:
        raise PfmError(f"{name} is {problem}") from None


def read_pfm(path) -> np.ndarray:
    """An RGB PFM file as float64 (height, width, 3), row 0 at the top (parse_pfm)."""
    return parse_pfm(Path(path).read_bytes(), Path(path).name)
