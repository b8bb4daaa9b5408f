"""The sRGB transfer curve, both ways: one copy for the prototypes, the checks, the
grader and the benches. The chapters write PNGs through the same curve (common/'s image
writer) and decode sRGB textures with it (chapter 17)."""

from __future__ import annotations

import numpy as np


def encode(linear):
    """Linear values in [0, 1] to sRGB-encoded ones: straight near black, then a
    2.4 power (IEC 61966-2-1). Values outside [0, 1] are clipped, NaN read as 0."""
    x = np.clip(np.nan_to_num(np.asarray(linear, dtype=np.float64)), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def encode_8bit(linear) -> np.ndarray:
    """encode, then rounded to 8 bits (0..255, as float64): what a PNG holds."""
    return np.round(encode(linear) * 255.0)


def decode(encoded):
    """sRGB-encoded values in [0, 1] back to linear ones (encode's inverse)."""
    c = np.asarray(encoded, dtype=np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
