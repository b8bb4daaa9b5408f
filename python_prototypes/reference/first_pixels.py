"""Chapter 02's test pattern, computed with numpy on whole arrays at once instead of
one invocation per pixel: red grows to the right, green downwards, and blue is 1.0
on odd 32-pixel squares and 0.25 on even ones. Linear colours, row 0 at the top."""

import numpy as np


def first_pixels_pattern(width: int, height: int) -> np.ndarray:
    rows, columns = np.mgrid[0:height, 0:width]
    red = (columns + 0.5) / width
    green = (rows + 0.5) / height
    odd_square = ((columns // 32 + rows // 32) % 2) == 1
    blue = np.where(odd_square, 1.0, 0.25)
    return np.stack([red, green, blue], axis=-1)
