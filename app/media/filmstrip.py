"""Filmstrips: several poses of a motion in one picture, for papers and bug reports.

``gmr-studio FILE --filmstrip OUT.png --frames A:B:STEP [--layout path|side] [--size WxH]``
renders frames ``A, A+STEP, ...`` up to B (exclusive, as a Python slice) either where they
are along the path (``path``: the motion's own positions, later poses more opaque) or side by
side (``side``: each pose moved along the direction of travel so that none overlaps), coloured
from blue (first) through violet to orange (last), each labelled with its frame. The last pose is drawn as the
app draws a figure (joints and bones), on the app's ground grid, with the app's camera.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from gmr_studio.app.model.state import Snapshot
from gmr_studio.app.scene.onion import pose_lines, pose_points
from gmr_studio.core.library.drawing import side_by_side, side_view
from gmr_studio.core.space.heading import travel_axis
from gmr_studio.core.space.up_axis import axis_index, up_axis_of

__all__ = ["filmstrip_command", "parse_frame_steps", "pose_colors", "render_filmstrip", "side_by_side", "travel_axis"]

FIRST_HUE, LAST_HUE = 0.58, 1.08  # blue through violet and red to orange: saturated all the way
LABEL_GAP = 8.0  # pixels between the frame labels of poses that stand close, laid side by side


def parse_frame_steps(text: str, n_frames: int) -> np.ndarray:
    """Frames (K,) of ``"A:B:STEP"`` (Python slice rules: B exclusive, parts may be left out,
    negative counts from the end) within ``n_frames``; ValueError when the text is not a slice
    or selects no frame."""
    parts = text.split(":")
    if not 1 <= len(parts) <= 3:
        raise ValueError(f"--frames {text!r}: expected A:B:STEP")
    try:
        values = [int(p) if p.strip() else None for p in parts]
    except ValueError:
        raise ValueError(f"--frames {text!r}: A, B and STEP must be whole numbers") from None
    if len(values) == 1:
        values = [values[0], None if values[0] is None else values[0] + 1]
    if len(values) == 3 and values[2] is not None and values[2] <= 0:
        raise ValueError(f"--frames {text!r}: STEP must be positive")
    frames = np.arange(n_frames)[slice(*values)]
    if len(frames) == 0:
        raise ValueError(f"--frames {text!r} selects no frame of the {n_frames}")
    return frames


def pose_colors(count: int) -> np.ndarray:
    """(count, 3) colours from the first pose's blue through violet to the last one's orange."""
    import colorsys

    hues = np.linspace(FIRST_HUE, LAST_HUE, count) if count > 1 else np.array([LAST_HUE])
    return np.array([colorsys.hsv_to_rgb(h % 1.0, 0.65, 1.0) for h in hues])


def render_filmstrip(
    snapshot: Snapshot,
    frames: np.ndarray,
    out: str | Path,
    size: tuple[int, int],
    layout: str = "path",
    drawn: dict | None = None,
) -> tuple[int, int]:
    """Render ``frames`` of ``snapshot`` to the PNG ``out`` (atomically); returns its size.
    ``drawn``, when given, receives ``labels``: (K, 4) each frame label's box in pixels
    (left, bottom, width, height; y up from the bottom)."""
    import pyvista as pv

    from gmr_studio.app.media.video import save_screenshot
    from gmr_studio.app.scene import vtk_parts as parts
    from gmr_studio.app.scene.labels import GAP, label_part, labels_in_a_row
    from gmr_studio.app.scene.scene import SkeletonScene

    if layout not in ("path", "side"):
        raise ValueError(f"unknown filmstrip layout {layout!r}: expected path or side")
    up = axis_index(up_axis_of(snapshot.motion))
    figure = ~snapshot.motion.anchors  # an anchor at the origin is no part of the picture
    positions = np.asarray(snapshot.positions[frames])
    if layout == "side":
        positions = side_by_side(positions, up, figure=figure)
    held = np.asarray(snapshot.rotations[frames]) if snapshot.holds_rotations else None
    strip = Snapshot(snapshot.motion.frame_slice(frames), positions, held)
    plotter = pv.Plotter(off_screen=True, window_size=size)
    try:
        scene = SkeletonScene(plotter)
        scene.frame = len(frames) - 1
        scene.set_snapshot(strip, reset_camera=True)  # the app's ground grid under every pose
        for name, part in scene.parts.items():
            part.set_visible(name == "ground")
        # each pose drawn as the view draws the figure: soft links and bones from an anchor dashed
        pairs, links, n_points = pose_lines(snapshot.motion)
        colors = pose_colors(len(frames))
        opacity = np.ones(len(frames)) if layout == "side" else np.linspace(0.35, 1.0, len(frames))
        for k in range(len(frames)):
            part = parts.segments_part(n_points, pairs, color=tuple(colors[k]), width=3.0)
            part.set_points(pose_points(positions[k], links))
            part.actor.GetProperty().SetOpacity(float(opacity[k]))
            plotter.renderer.AddActor(part.actor)
        shown = positions[:, figure]
        below = shown.min(axis=(0, 1))[up] - 0.08 * snapshot.motion.size
        anchors = shown.mean(axis=1)
        anchors[:, up] = below
        _side_camera(plotter, shown, up, anchors)
        # every pose labelled (screen-space labels never hide one another as VTK's placer does)
        labels = label_part([f"{f}" for f in frames], size=14)
        plotter.renderer.AddViewProp(labels.actor)
        plotter.render()
        centres = scene.display_positions(anchors)
        centres[:, 0] -= labels.widths() / 2 + GAP[0]  # centred under the pose ...
        width = scene.display_size()[0]  # ... or beside the others where poses stand close
        centres[:, 0] = labels_in_a_row(centres[:, 0] + GAP[0], labels.widths(), LABEL_GAP, width) - GAP[0]
        labels.place(centres, scene.display_size())
        if drawn is not None:
            drawn["labels"] = np.column_stack([labels.corners[:, 0], labels.widths(), labels.heights()])
        return save_screenshot(scene, out)
    finally:
        plotter.close()


def _side_camera(plotter, positions: np.ndarray, up: int, labels: np.ndarray) -> None:
    """A parallel projection from the side of the travel, a little from above, with the
    travel running left to right and every pose and ``labels`` (K, 3) in the picture, the
    poses filling it (a tenth of it for margins and labels): :func:`core.library.drawing.side_view`."""
    flat = np.concatenate([positions.reshape(-1, 3), labels])  # the frame labels must show too
    width, height = plotter.window_size
    view = side_view(flat, up, travel_axis(positions, up), width, height)
    low, high = flat.min(axis=0), flat.max(axis=0)
    plotter.enable_parallel_projection()
    plotter.camera_position = [tuple(view.centre + view.direction), tuple(view.centre), tuple(np.eye(3)[up])]
    plotter.reset_camera(bounds=np.column_stack([low, high]).ravel())
    plotter.camera.parallel_scale = view.half_height


def filmstrip_command(motion_path: str, out: str, frames_text: str | None, layout: str, size: tuple[int, int]) -> int:
    """``gmr-studio FILE --filmstrip OUT.png --frames A:B:STEP``: 0 when written, 2 when the
    file cannot be read or the frames are wrong (the reason on stderr)."""
    import sys

    from gmr_studio.app.model.loading import load_snapshot
    from gmr_studio.core.errors import MotionFileError

    try:
        snapshot = load_snapshot(motion_path)
        if frames_text is None:
            step = max(1, snapshot.motion.n_frames // 8)
            frames = np.arange(0, snapshot.motion.n_frames, step)
        else:
            frames = parse_frame_steps(frames_text, snapshot.motion.n_frames)
    except (MotionFileError, ValueError) as exc:
        print(f"gmr-studio: {exc}", file=sys.stderr)
        return 2
    width, height = render_filmstrip(snapshot, frames, out, size, layout)
    print(f"wrote {out} ({width}x{height}, {len(frames)} poses: frames {frames[0]} to {frames[-1]})")
    return 0
