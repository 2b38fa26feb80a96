"""Pictures of the scene: PNG screenshots and mp4 videos of the playback (imageio-ffmpeg).

Both work on any plotter the :class:`~app.scene.SkeletonScene` draws into: the window's
interactor or an off-screen plotter (``gmr-studio FILE --screenshot OUT.png`` without a
display). The video samples the motion at the video's frame rate by time, as playback
does, so it lasts as long as the motion (divided by the speed), or as the range of frames
asked for. The dialogs suggest a file name from the motion's and the folder the last
picture or video went to.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from gmr_studio.app.scene.scene import SkeletonScene
from gmr_studio.core.atomic import atomic_write_bytes
from gmr_studio.core.timebase.clock import duration_seconds

VIDEO_FPS = 30.0


def scene_image(scene: SkeletonScene) -> np.ndarray:
    """(H, W, 3) uint8 RGB image of the scene as drawn now."""
    scene.render(now=True)
    return np.asarray(scene.plotter.screenshot(return_img=True, transparent_background=False))[..., :3]


def image_pixels(image) -> np.ndarray:
    """(H, W, 3) uint8 RGB copy of a QImage's pixels (any format; the copy outlives it)."""
    from PyQt6.QtGui import QImage

    rgb = image.convertToFormat(QImage.Format.Format_RGB888)
    bits = rgb.constBits()
    bits.setsize(rgb.sizeInBytes())
    rows = np.frombuffer(bits, np.uint8).reshape(rgb.height(), rgb.bytesPerLine())
    return rows[:, : 3 * rgb.width()].reshape(rgb.height(), rgb.width(), 3).copy()


def save_png(image: np.ndarray, path: str | Path) -> None:
    """Write an (H, W, 3) uint8 image as PNG, atomically."""
    from PyQt6.QtCore import QBuffer, QByteArray, QIODevice
    from PyQt6.QtGui import QImage

    image = np.ascontiguousarray(image[..., :3], dtype=np.uint8)
    height, width = image.shape[:2]
    qimage = QImage(image.data, width, height, 3 * width, QImage.Format.Format_RGB888)
    data = QByteArray()
    buffer = QBuffer(data)
    buffer.open(QIODevice.OpenModeFlag.WriteOnly)
    if not qimage.save(buffer, "PNG"):
        raise OSError(f"could not encode {path} as PNG")
    buffer.close()
    atomic_write_bytes(path, bytes(data))


def window_image(window, interactor) -> np.ndarray:
    """(H, W, 3) uint8 image of a whole window with the 3D view painted in (a plain grab of
    the window leaves the OpenGL view blank on some platforms)."""
    from PyQt6.QtCore import QPoint
    from PyQt6.QtGui import QImage, QPainter

    picture = window.grab().toImage().convertToFormat(QImage.Format.Format_RGB888)
    view = np.ascontiguousarray(np.asarray(interactor.screenshot(return_img=True))[..., :3])
    ratio = picture.width() / max(window.width(), 1)
    height, width = view.shape[:2]
    patch = QImage(view.data, width, height, 3 * width, QImage.Format.Format_RGB888)
    corner = interactor.mapTo(window, QPoint(0, 0))
    painter = QPainter(picture)
    target = patch.scaled(round(interactor.width() * ratio), round(interactor.height() * ratio))
    painter.drawImage(round(corner.x() * ratio), round(corner.y() * ratio), target)
    painter.end()
    return image_pixels(picture)


def save_screenshot(scene: SkeletonScene, path: str | Path) -> tuple[int, int]:
    """Save the scene as a PNG; returns (width, height)."""
    image = scene_image(scene)
    save_png(image, path)
    return image.shape[1], image.shape[0]


def video_frames(
    n_frames: int, rate: float, fps: float = VIDEO_FPS, speed: float = 1.0, first: int = 0, last: int | None = None
) -> np.ndarray:
    """(N,) motion frames shown by a video at ``fps`` of frames ``first`` to ``last``
    (both included; default the whole take) of a motion at ``rate`` played at ``speed``."""
    last = n_frames - 1 if last is None else min(int(last), n_frames - 1)
    first = max(0, int(first))
    span = last - first + 1
    if n_frames <= 0 or span <= 0:
        return np.zeros(0, np.int64)
    duration = duration_seconds(span, 1.0 / rate) / speed  # the core's one definition (core.timebase.clock)
    times = np.arange(max(1, int(np.floor(duration * fps + 1e-9)))) / fps
    return first + np.minimum((times * rate * speed + 1e-9).astype(np.int64), span - 1)


def suggested_name(motion_path: str | Path | None, suffix: str, first: int, last: int | None = None) -> str:
    """A file name for a picture (``walk_frame00150.png``) or video (``walk.mp4`` for the
    whole take, ``walk_frames100-299.mp4`` for a range) of the motion at ``motion_path``."""
    stem = Path(motion_path).stem if motion_path else "motion"
    if suffix == ".png":
        return f"{stem}_frame{first:05d}.png"
    return f"{stem}{suffix}" if last is None else f"{stem}_frames{first}-{last}{suffix}"


EXPORT_FOLDER_KEY = "export/last_folder"


def export_folder(settings, fallback: str = "") -> str:
    """The folder the last screenshot or video went to (else ``fallback``)."""
    return str(settings.value(EXPORT_FOLDER_KEY, "") or fallback)


def remember_export_folder(settings, path: str | Path) -> None:
    settings.setValue(EXPORT_FOLDER_KEY, str(Path(path).parent))


def ask_frame_range(parent, n_frames: int, first: int = 0, last: int | None = None) -> tuple[int, int] | None:
    """A dialog asking which frames (first, last, both included) a video shows; None if
    cancelled. Defaults: the whole take."""
    from PyQt6.QtWidgets import QDialog, QDialogButtonBox, QFormLayout, QSpinBox

    dialog = QDialog(parent)
    dialog.setWindowTitle("Export video: frames")
    layout = QFormLayout(dialog)
    boxes = []
    for label, value in (("From frame", first), ("To frame", n_frames - 1 if last is None else last)):
        box = QSpinBox(dialog)
        box.setRange(0, max(0, n_frames - 1))
        box.setValue(int(value))
        layout.addRow(label, box)
        boxes.append(box)
    boxes[0].valueChanged.connect(lambda v: boxes[1].setValue(max(v, boxes[1].value())))
    boxes[1].valueChanged.connect(lambda v: boxes[0].setValue(min(v, boxes[0].value())))
    buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel, dialog)
    buttons.accepted.connect(dialog.accept)
    buttons.rejected.connect(dialog.reject)
    layout.addRow(buttons)
    if dialog.exec() != QDialog.DialogCode.Accepted:
        return None
    return boxes[0].value(), boxes[1].value()


def export_video(
    scene: SkeletonScene,
    path: str | Path,
    *,
    fps: float = VIDEO_FPS,
    speed: float = 1.0,
    progress: Callable[[int, int], bool] | None = None,
    first: int = 0,
    last: int | None = None,
) -> int:
    """Write an H.264 mp4 of the scene playing frames ``first`` to ``last`` of its motion
    (default the whole take); returns the frames written.

    ``progress(done, total)`` is called after each frame; when it returns False the export
    stops and the partial file is removed. The scene is left on the frame it showed.
    """
    import imageio_ffmpeg

    if scene.snapshot is None:
        raise ValueError("no motion to export")
    motion = scene.snapshot.motion
    frames = video_frames(motion.n_frames, motion.frame_rate, fps, speed, first, last)
    shown = scene.frame
    target = Path(path)
    partial = target.with_name(f".{target.name}.partial.mp4")
    first = scene_image(scene)
    height, width = (first.shape[0] // 2) * 2, (first.shape[1] // 2) * 2
    writer = imageio_ffmpeg.write_frames(
        str(partial),
        (width, height),
        fps=fps,
        codec="libx264",
        pix_fmt_out="yuv420p",
        macro_block_size=2,
        quality=7,
        ffmpeg_log_level="error",
    )
    writer.send(None)
    written = 0
    try:
        for done, frame in enumerate(frames, start=1):
            scene.show_frame(int(frame), render=False)
            image = scene_image(scene)[:height, :width]
            writer.send(np.ascontiguousarray(image))
            written = done
            if progress is not None and progress(done, len(frames)) is False:
                break
    finally:
        writer.close()
        scene.show_frame(shown)
    if written < len(frames):
        partial.unlink(missing_ok=True)
        return 0
    partial.replace(target)
    return written
