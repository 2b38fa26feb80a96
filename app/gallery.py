"""Pictures of every rig, before and after each edit kind, and what a test reads in them.

The pixel masks below sort a picture of the 3D view into background, ground grid and
figure (everything else: joints, bones, root cubes, soft links, markers) by colour; the
scene draws the background and the grid in flat, unlit colours, so the sort is exact up to
antialiasing of the grid's edges against the figure.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.app.scene import BACKGROUND, GROUND_COLOR

COLOR_TOLERANCE = 6  # of 255 per channel: the flat colours as the renderer quantises them


def _near(image: np.ndarray, rgb) -> np.ndarray:
    target = np.rint(np.asarray(rgb) * 255)
    return (np.abs(image[..., :3].astype(np.int16) - target) <= COLOR_TOLERANCE).all(axis=-1)


def background_mask(image: np.ndarray) -> np.ndarray:
    """(H, W) bool: pixels of the background colour in an (H, W, 3) uint8 picture."""
    return _near(image, BACKGROUND)


def ground_mask(image: np.ndarray) -> np.ndarray:
    """(H, W) bool: pixels of the ground grid's colour."""
    return _near(image, GROUND_COLOR)


def figure_mask(image: np.ndarray) -> np.ndarray:
    """(H, W) bool: pixels that are neither background nor grid, nor a blend of the two
    (the grid's antialiased edges lie between its colour and the background's)."""
    pixels = image[..., :3].astype(np.float64) / 255
    back, grid = np.asarray(BACKGROUND), np.asarray(GROUND_COLOR)
    direction = grid - back
    t = np.clip(((pixels - back) @ direction) / (direction @ direction), 0.0, 1.0)
    blend = back + t[..., None] * direction
    return np.abs(pixels - blend).max(axis=-1) * 255 > COLOR_TOLERANCE


def dilate(mask: np.ndarray, pixels: int) -> np.ndarray:
    """(H, W) bool: ``mask`` grown by a square of ``pixels`` on each side."""
    out = mask.copy()
    for axis in (0, 1):
        grown = out.copy()
        for shift in range(1, pixels + 1):
            for sign in (1, -1):
                moved = np.roll(out, sign * shift, axis=axis)
                edge = [slice(None)] * 2
                edge[axis] = slice(0, shift) if sign > 0 else slice(-shift, None)
                moved[tuple(edge)] = False
                grown |= moved
        out = grown
    return out
