"""A take's thumbnail: a strip of a few of its poses side by side, drawn with numpy, as PNG.

:func:`motion_thumbnail` draws a motion's bones, :func:`marker_thumbnail` a marker set's
points; both give an (H, W, 3) uint8 picture that :func:`png_bytes` encodes (zlib, no
imaging library). No renderer, no display: ``gmr library index`` draws them in its worker
processes.

What the picture shows is what the app's filmstrip (``--filmstrip --layout side``) shows,
small: ``poses`` frames spread evenly over the take (at the middles of equal parts, so a
T-pose at frame 0 is not one of them), set side by side along the direction of travel
(:func:`core.library.drawing.side_by_side`), seen from the side of the travel a little from
above with a parallel projection fitted to them (:func:`core.library.drawing.side_view`),
standing up the axis the view stands a figure up (:func:`core.space.up_axis.up_axis_of`).
Bones are anti-aliased lines in their tree's colour as the view first draws the motion,
soft links thinner in grey, over the view's background and a ground line under the lowest
point of the poses. An anchor (a root pinned at the origin, :attr:`core.model.motion.Motion.anchors`) is
left out, as the view leaves it out of the figure's framing.
"""

from __future__ import annotations

import struct
import zlib

import numpy as np

from gmr_studio.core.library.drawing import (
    BACKGROUND,
    GROUND_COLOR,
    MARKER_COLOR,
    first_tree_colors,
    side_by_side,
    side_view,
    travel_axis,
)
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.space.up_axis import axis_index, detect_up_axis, up_axis_of

#: (width, height) pixels of a thumbnail
SIZE = (160, 64)
#: poses in a thumbnail
POSES = 4
#: line widths in pixels: bones, soft links, the ground; the diameter of a marker's dot
BONE_WIDTH = 1.6
LINK_WIDTH = 0.8
GROUND_WIDTH = 1.0
MARKER_WIDTH = 1.6
LINK_COLOR = (0.75, 0.75, 0.78)


def pose_frames(n_frames: int, poses: int = POSES) -> np.ndarray:
    """(K,) int64 frames at the middles of ``poses`` equal parts of ``n_frames`` frames
    (K = ``min(poses, n_frames)``)."""
    count = max(1, min(poses, n_frames))
    return np.minimum(((np.arange(count) + 0.5) * n_frames / count).astype(np.int64), max(n_frames - 1, 0))


def motion_thumbnail(
    motion: Motion,
    positions: np.ndarray,
    size: tuple[int, int] = SIZE,
    poses: int = POSES,
) -> np.ndarray:
    """The thumbnail of a motion: (H, W, 3) uint8.

    motion : the motion (either convention; only its structure is read here).
    positions : (F, J, 3) world positions of every frame.
    """
    frames = pose_frames(motion.n_frames, poses)
    figure = ~motion.anchors
    up = axis_index(up_axis_of(motion))  # the view's rule
    placed = side_by_side(positions[frames], up, figure=figure)
    children = np.flatnonzero((motion.parents >= 0) & figure & figure[np.maximum(motion.parents, 0)])
    holders = np.flatnonzero((motion.soft_parents >= 0) & figure & figure[np.maximum(motion.soft_parents, 0)])
    colors = first_tree_colors(motion)
    segments = [
        (placed[:, children], placed[:, motion.parents[children]], colors[children], BONE_WIDTH),
        (placed[:, holders], placed[:, motion.soft_parents[holders]], np.array([LINK_COLOR]), LINK_WIDTH),
    ]
    if not children.size and not holders.size:  # single joints: dots
        shown = placed[:, figure]
        segments = [(shown, shown, colors[figure], MARKER_WIDTH * 1.5)]
    return _draw(placed[:, figure], up, segments, size)


def marker_thumbnail(positions: np.ndarray, size: tuple[int, int] = SIZE, poses: int = POSES) -> np.ndarray | None:
    """The thumbnail of a marker set (its markers as dots): (H, W, 3) uint8, or None when
    no marker is seen at every pose's frame.

    positions : (F, M, 3) marker positions, NaN in the gaps.
    """
    frames = pose_frames(positions.shape[0], poses)
    chosen = positions[frames]
    seen = np.isfinite(chosen).all(axis=(0, 2))
    if not seen.any():
        return None
    up = axis_index(detect_up_axis(positions[:, seen]))
    placed = side_by_side(chosen[:, seen], up)
    return _draw(placed, up, [(placed, placed, np.array([MARKER_COLOR]), MARKER_WIDTH)], size)


def _draw(points: np.ndarray, up: int, segments: list, size: tuple[int, int]) -> np.ndarray:
    """The picture of ``segments`` [(starts (K, N, 3), ends (K, N, 3), colours (N|1, 3),
    width)] framed on ``points`` (K, A, 3), with the ground line under them."""
    width, height = size
    view = side_view(points.reshape(-1, 3), up, travel_axis(points, up), width, height)
    image = np.empty((height, width, 3))
    image[:] = BACKGROUND
    lowest = view.pixels(points, width, height)[..., 1].max()  # the lowest point on the picture
    ground_row = min(np.floor(lowest) + 0.5, height - 0.5)  # on a row of pixels: a crisp line
    draw_lines(
        image, np.array([[0.0, ground_row]]), np.array([[width, ground_row]]), np.array([GROUND_COLOR]), GROUND_WIDTH
    )
    for starts, ends, colors, line_width in segments:
        count = starts.shape[1]
        if not count:
            continue
        colors = np.broadcast_to(colors, (count, 3))
        a = view.pixels(starts, width, height).reshape(-1, 2)
        b = view.pixels(ends, width, height).reshape(-1, 2)
        draw_lines(image, a, b, np.tile(colors, (starts.shape[0], 1)), line_width)
    return np.clip(np.rint(image * 255), 0, 255).astype(np.uint8)


def draw_lines(image: np.ndarray, starts: np.ndarray, ends: np.ndarray, colors: np.ndarray, width: float) -> None:
    """Draw anti-aliased lines with round ends into ``image`` (H, W, 3) float in [0, 1], in
    place: line ``n`` from ``starts[n]`` to ``ends[n]`` (pixel x, y; (N, 2) each) in
    ``colors[n]`` (N, 3), ``width`` pixels wide. A pixel's coverage is the part of it within
    the line (its centre's distance to the segment against half the width, a one-pixel ramp);
    the colour is laid over what is there by that coverage. A zero-length line is a dot."""
    height, width_px = image.shape[:2]
    half = width / 2
    reach = half + 1.0
    drawn = np.isfinite(starts).all(axis=1) & np.isfinite(ends).all(axis=1)
    low = np.floor(np.minimum(starts, ends) - reach).astype(np.int64)
    high = np.ceil(np.maximum(starts, ends) + reach).astype(np.int64)
    for n in np.flatnonzero(drawn):
        x0, y0 = max(int(low[n, 0]), 0), max(int(low[n, 1]), 0)
        x1, y1 = min(int(high[n, 0]), width_px), min(int(high[n, 1]), height)
        if x0 >= x1 or y0 >= y1:
            continue
        ax, ay = float(starts[n, 0]), float(starts[n, 1])
        bx, by = float(ends[n, 0]) - ax, float(ends[n, 1]) - ay
        dx = np.arange(x0 + 0.5 - ax, x1 - ax, 1.0)[None, :]
        dy = np.arange(y0 + 0.5 - ay, y1 - ay, 1.0)[:, None]
        length2 = bx * bx + by * by
        t = np.clip((dx * bx + dy * by) * (1.0 / length2), 0.0, 1.0) if length2 > 0 else 0.0
        coverage = np.clip(half + 0.5 - np.hypot(dx - t * bx, dy - t * by), 0.0, 1.0)[..., None]
        patch = image[y0:y1, x0:x1]
        patch += coverage * (colors[n] - patch)


def png_bytes(image: np.ndarray) -> bytes:
    """A PNG file of an (H, W, 3) uint8 RGB picture: 8 bits per channel, no interlace, every
    row unfiltered, the pixels deflated by zlib."""
    image = np.ascontiguousarray(image, dtype=np.uint8)
    height, width = image.shape[:2]
    rows = np.concatenate([np.zeros((height, 1), np.uint8), image.reshape(height, width * 3)], axis=1)

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", header)
        + chunk(b"IDAT", zlib.compress(rows.tobytes(), 6))
        + chunk(b"IEND", b"")
    )
