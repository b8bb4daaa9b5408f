"""A picture cut into n x n blocks, the way the grader's statistics and its diagnosis
both look at it: where the blocks' edges fall, and sums and means over each block."""

from __future__ import annotations

import numpy as np


def edges(size: int, parts: int) -> list[int]:
    """Where `parts` blocks begin along a side of `size` pixels, and its end."""
    return [size * i // parts for i in range(parts + 1)]


def block_sums(images: np.ndarray, level: int) -> np.ndarray:
    """Sums over each block of a level: images (..., H, W, C) -> (..., level, level, C)."""
    rows, columns = edges(images.shape[-3], level), edges(images.shape[-2], level)
    by_rows = np.add.reduceat(images, rows[:-1], axis=-3)
    return np.add.reduceat(by_rows, columns[:-1], axis=-2)


def block_sizes(height: int, width: int, level: int) -> np.ndarray:
    """Pixels in each block: (level, level, 1)."""
    rows, columns = np.diff(edges(height, level)), np.diff(edges(width, level))
    return np.outer(rows, columns)[..., None].astype(np.float64)


def block_means(values: np.ndarray, level: int) -> np.ndarray:
    """Means over each block of an (H, W) or (H, W, C) array (at most one block a
    pixel: a picture smaller than the level has as many blocks as pixels)."""
    channels = values if values.ndim == 3 else values[..., None]
    level = min(level, channels.shape[0], channels.shape[1])
    means = block_sums(channels, level) / block_sizes(*channels.shape[:2], level)
    return means if values.ndim == 3 else means[..., 0]
