"""Which joint is under the mouse: projection and nearest-point picking (pure numpy).

The view hands over the camera's combined view-projection matrix and the viewport size;
:func:`project_points` turns world points into pixel coordinates (origin at the top left,
as Qt counts) and depths, and :func:`pick_point` takes the nearest projected point within a
radius of the click, preferring the one closer to the camera when two overlap. Neither needs
a window, so both are tested on their own.
"""

from __future__ import annotations

import numpy as np


def project_points(points: np.ndarray, view_projection: np.ndarray, viewport: tuple[int, int]) -> np.ndarray:
    """Screen coordinates of world points.

    Parameters
    ----------
    points : (N, 3) world coordinates (NaN rows stay NaN).
    view_projection : (4, 4) matrix taking homogeneous world points (column vectors) to
        clip coordinates (OpenGL conventions: visible points have x, y, z in [-w, w]).
    viewport : (width, height) in pixels.

    Returns
    -------
    (N, 3) float64: x and y in pixels from the top-left corner, and the normalised depth
    z/w in [-1, 1] (smaller is nearer); rows behind the camera (w <= 0) are NaN.
    """
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    homogeneous = np.concatenate([points, np.ones((len(points), 1))], axis=1)
    clip = homogeneous @ np.asarray(view_projection, dtype=np.float64).T
    w = clip[:, 3]
    with np.errstate(invalid="ignore", divide="ignore"):
        ndc = clip[:, :3] / w[:, None]
    ndc[~(w > 0)] = np.nan
    width, height = viewport
    x = (ndc[:, 0] + 1.0) * 0.5 * width
    y = (1.0 - ndc[:, 1]) * 0.5 * height
    return np.stack([x, y, ndc[:, 2]], axis=1)


def pick_point(click: tuple[float, float], screen: np.ndarray, radius: float) -> int | None:
    """Index of the projected point nearest the click, within ``radius`` pixels, or None.

    Parameters
    ----------
    click : (x, y) pixels from the top left.
    screen : (N, 3) from :func:`project_points` (x, y, depth); NaN rows are never picked.
    radius : pick tolerance in pixels.

    Among points within the radius, the nearest on screen wins; points closer on screen than
    a quarter of the radius to that one count as overlapping and the one nearest the camera
    wins among them.
    """
    screen = np.asarray(screen, dtype=np.float64).reshape(-1, 3)
    if not len(screen):
        return None
    distance = np.hypot(screen[:, 0] - click[0], screen[:, 1] - click[1])
    distance[~np.isfinite(distance)] = np.inf
    nearest = int(np.argmin(distance))
    if not distance[nearest] <= radius:
        return None
    overlapping = np.flatnonzero(distance <= distance[nearest] + radius / 4)
    return int(overlapping[np.argmin(screen[overlapping, 2])])
