"""Pictures of every rig, before and after each edit kind, and what a test reads in them.

``python -m gmr_studio.app.tools.gallery OUT_DIR [--size WxH]`` renders the demo (with its
markers), every motion file in ``../shared/data`` and the rigs of :mod:`core.rigs`, each as
opened and after a shift root, a split and a join (split all, then one joint joined back),
made through the app's undoable commands at the joint with the most descendants, to
``OUT_DIR/CASE__EDIT.png`` and one ``contact_sheet.png``: look at them all at once.

The pixel masks below sort a picture of the 3D view into background, ground grid and
figure (everything else: joints, bones, root cubes, soft links, markers) by colour; the
scene draws the background and the grid in flat, unlit colours, so the sort is exact up to
antialiasing of the grid's edges against the figure.
"""

from __future__ import annotations

import dataclasses
import os
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from gmr_studio.app.arguments import has_display
from gmr_studio.app.media.video import image_pixels, save_png, scene_image
from gmr_studio.app.model import commands
from gmr_studio.app.model.loading import load_markers, load_snapshot, motion_suffixes
from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.app.scene.scene import BACKGROUND, GROUND_COLOR, SkeletonScene
from gmr_studio.core.demo import MARKERS_FILE, MOTION_FILE, demo_folder
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rigs import RIGS, make_rig
from gmr_studio.core.shared_data import shared_data_dir

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


# ---------------------------------------------------------------------------- cases
EDITS = ("as opened", "shift root", "split", "join")
THUMBNAIL = (320, 240)


@dataclasses.dataclass
class Case:
    """A motion to picture: a file of the shared data, the demo or a generated rig."""

    name: str
    load: Callable[[], Snapshot]
    markers: Callable[[], MarkerSet] | None = None
    path: str | None = None


@dataclasses.dataclass
class Picture:
    """One rendered state: the image, each joint's pixel position and what was drawn."""

    case: str
    edit: str
    image: np.ndarray  # (H, W, 3) uint8
    joints: np.ndarray  # (J, 3) pixel x, y from the top left, depth
    markers: np.ndarray  # (M, 3) likewise, NaN where a marker is missing
    marker_labels: tuple[str, ...]
    names: tuple[str, ...]
    anchors: np.ndarray  # (J,) bool
    up_axis: int
    joint_radius: float  # pixels
    applied: bool  # the edit was made (False: refused, e.g. a single joint)


def file_cases(folder: Path | None = None) -> list[Case]:
    """Every motion file the core reads (.bvh, .amc, .asf, .gmr, glTF, .fbx...) under the
    shared data folder, sorted."""
    folder = shared_data_dir() if folder is None else folder
    if not folder.is_dir():
        return []
    files = sorted(p for p in folder.rglob("*") if p.suffix.lower() in motion_suffixes())
    return [
        Case(str(p.relative_to(folder)).replace("/", "_"), lambda p=p: load_snapshot(p), path=str(p)) for p in files
    ]


def rig_cases(names: Sequence[str] | None = None) -> list[Case]:
    """The generated convention rigs (:mod:`core.rigs`)."""
    return [
        Case(f"rig_{name}", lambda name=name: Snapshot.of(pre_from_post(make_rig(name))))
        for name in (RIGS if names is None else names)
    ]


def demo_case() -> Case:
    folder = demo_folder()
    return Case(
        "demo",
        lambda: load_snapshot(folder / MOTION_FILE),
        markers=lambda: load_markers(folder / MARKERS_FILE),
        path=str(folder / MOTION_FILE),
    )


def all_cases() -> list[Case]:
    return [demo_case(), *file_cases(), *rig_cases()]


def edit_joint(motion: Motion) -> int | None:
    """The joint the gallery edits at: the non-root joint with the most descendants (the
    spine on a humanoid), or None for a single joint."""
    order = motion.topological_order[::-1]
    count = np.ones(motion.n_joints, np.int64)
    for j in order:
        if motion.parents[j] >= 0:
            count[motion.parents[j]] += count[j]
    candidates = np.flatnonzero((motion.parents >= 0) & ~motion.anchors)
    if not len(candidates):
        return None
    return int(candidates[np.argmax(count[candidates])])


def _apply_edit(state: StudioState, edit: str, joint: int | None) -> bool:
    if edit == "as opened":
        return True
    if joint is None:
        return False
    if edit == "shift root":
        return commands.shift_root_to(state, joint)
    if edit == "split":
        return commands.split_here(state, joint)
    return commands.split_everything(state) and commands.join_to_parent(state, joint)


def render_case(case: Case, size: tuple[int, int] = THUMBNAIL, frame: int | None = None) -> list[Picture]:
    """The case as opened and after each edit kind (each from the file as opened, through
    the app's undoable commands), drawn the way the window's view draws them."""
    import pyvista as pv

    state = StudioState()
    state.open_document(case.load(), case.path)
    if case.markers is not None:
        state.set_markers(case.markers())
    motion = state.motion
    plotter = pv.Plotter(off_screen=True, window_size=size)
    pictures = []
    try:
        scene = SkeletonScene(plotter)
        state.motion_changed.connect(lambda: scene.set_snapshot(state.snapshot, reset_camera=False))
        scene.frame = motion.n_frames // 2 if frame is None else frame
        scene.overlays = dict(state.overlays)
        scene.set_snapshot(state.snapshot, reset_camera=True)
        scene.set_markers(state.marker_overlay)
        joint = edit_joint(motion)
        for edit in EDITS:
            state.undo_stack.setIndex(0)
            applied = _apply_edit(state, edit, joint)
            image = scene_image(scene)
            markers = scene.marker_screen_positions()
            labels = state.marker_overlay.markers.labels if state.marker_overlay is not None else ()
            pictures.append(
                Picture(
                    case.name,
                    edit,
                    image,
                    scene.joint_screen_positions(),
                    markers,
                    tuple(labels),
                    state.motion.names,
                    state.motion.anchors,
                    scene.up_axis,
                    scene.joint_radius_pixels(),
                    applied,
                )
            )
    finally:
        plotter.close()
    return pictures


# ----------------------------------------------------------------------- the sheet
def contact_sheet(rows: list[list[Picture]]) -> np.ndarray:
    """(H, W, 3) uint8: one row per case, one column per edit, each labelled."""
    from PyQt6.QtCore import QRect, Qt
    from PyQt6.QtGui import QColor, QImage, QPainter

    height, width = rows[0][0].image.shape[:2]
    label = 22
    sheet = QImage(width * len(EDITS), (height + label) * len(rows), QImage.Format.Format_RGB888)
    sheet.fill(QColor(20, 20, 24))
    painter = QPainter(sheet)
    painter.setPen(QColor(230, 230, 230))
    for r, row in enumerate(rows):
        for c, picture in enumerate(row):
            image = np.ascontiguousarray(picture.image)
            patch = QImage(image.data, image.shape[1], image.shape[0], 3 * image.shape[1], QImage.Format.Format_RGB888)
            top = r * (height + label)
            painter.drawImage(c * width, top + label, patch)
            text = f"{picture.case}: {picture.edit}" + ("" if picture.applied else " (refused)")
            painter.drawText(QRect(c * width + 4, top, width - 8, label), Qt.AlignmentFlag.AlignVCenter, text)
    painter.end()
    return image_pixels(sheet)


def main(argv: Sequence[str] | None = None) -> int:
    import argparse

    parser = argparse.ArgumentParser(prog="python -m gmr_studio.app.tools.gallery", description=__doc__.splitlines()[0])
    parser.add_argument("out_dir", help="folder for the PNGs and contact_sheet.png")
    parser.add_argument("--size", default="320x240", help="size of each picture, WxH")
    args = parser.parse_args(argv)
    width, height = (int(v) for v in args.size.lower().split("x"))
    if not has_display():
        os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    from PyQt6.QtWidgets import QApplication

    _app = QApplication.instance() or QApplication(sys.argv[:1])
    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for case in all_cases():
        started = time.perf_counter()
        pictures = render_case(case, (width, height))
        for picture in pictures:
            save_png(picture.image, out / f"{case.name}__{picture.edit.replace(' ', '_')}.png")
        rows.append(pictures)
        print(f"{case.name}: {time.perf_counter() - started:.1f} s", flush=True)
    save_png(contact_sheet(rows), out / "contact_sheet.png")
    print(f"wrote {len(rows) * len(EDITS)} pictures and {out / 'contact_sheet.png'}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
