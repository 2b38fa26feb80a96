"""Exports of the window's document: BVH (one file, or one per tree), glTF, a screenshot of
the view and a video, each from its File menu dialog or called directly (tests, scripts).

A failed export is reported (status bar, and a dialog unless the file controller is quiet)
and changes nothing else; the document and its undo history stay as they were.
"""

from __future__ import annotations

from pathlib import Path

from PyQt6.QtCore import Qt
from PyQt6.QtWidgets import QApplication, QFileDialog, QMessageBox, QProgressDialog

from gmr_studio.app.crash import describe_unexpected
from gmr_studio.app.media import video
from gmr_studio.app.media.video import export_video, save_screenshot
from gmr_studio.app.window.files import FileController
from gmr_studio.core.errors import OperationError


class Exports:
    """The File menu's exports for one window; shares the file controller's folder, settings,
    parent window and way of reporting."""

    def __init__(self, files: FileController) -> None:
        self.files = files
        self.state = files.state

    def export_bvh_dialog(self) -> None:
        motion = self.state.motion
        if motion is None:
            return
        stem = self.state.path.with_suffix(".bvh").name if self.state.path else "motion.bvh"
        path, _ = QFileDialog.getSaveFileName(
            self.files.window, "Export BVH", str(Path(self.files.folder()) / stem), "BVH (*.bvh)"
        )
        if not path:
            return
        per_tree = False
        if len(motion.roots) > 1:
            box = QMessageBox(
                QMessageBox.Icon.Question, "Export BVH", f"The motion is a forest of {len(motion.roots)} trees."
            )
            box.setInformativeText("Write one file with the trees under a World root, or one file per tree?")
            one = box.addButton("One file", QMessageBox.ButtonRole.AcceptRole)
            several = box.addButton("One file per tree", QMessageBox.ButtonRole.AcceptRole)
            box.addButton(QMessageBox.StandardButton.Cancel)
            box.exec()
            if box.clickedButton() not in (one, several):
                return
            per_tree = box.clickedButton() is several
        self.export_bvh(path if path.lower().endswith(".bvh") else path + ".bvh", per_tree=per_tree)

    def export_bvh(self, path: str | Path, *, per_tree: bool = False) -> bool:
        """Write the document as standard BVH (post-rotation; dummy joints where GMR siblings
        turn independently; a forest under a ``World`` root, or one file per tree)."""
        from gmr_studio.core.formats.bvh_export import bvh_export, bvh_export_trees, tree_file_name

        motion = self.state.motion
        try:
            if per_tree:
                written = []
                for root, export in bvh_export_trees(motion):
                    target = tree_file_name(path, root)
                    export.write(target)
                    written.append(target.name)
                text = f"Exported {len(written)} trees: {', '.join(written)}"
            else:
                export = bvh_export(motion)
                export.write(path)
                extra = [f"{len(export.dummies)} dummy joints"] if export.dummies else []
                extra += [f"the trees under a '{export.world_root}' root"] if export.world_root else []
                text = f"Exported {path}" + (f" ({', '.join(extra)})" if extra else "")
        except (OSError, OperationError, ValueError) as exc:
            self.files.report(f"Cannot export {path}: {exc}")
            return False
        except Exception as exc:
            self.files.report(describe_unexpected(f"Exporting {path}", exc))
            return False
        self.state.show_message(text)
        return True

    def export_gltf_dialog(self) -> None:
        if self.state.motion is None:
            return
        stem = self.state.path.with_suffix(".glb").name if self.state.path else "motion.glb"
        path, _ = QFileDialog.getSaveFileName(
            self.files.window,
            "Export glTF",
            str(Path(self.files.folder()) / stem),
            "glTF binary (*.glb);;glTF JSON (*.gltf)",
        )
        if path:
            self.export_gltf(path if path.lower().endswith((".glb", ".gltf")) else path + ".glb")

    def export_gltf(self, path: str | Path) -> bool:
        """Write the document as glTF 2.0 (Y up, metres, with the bone-capsule mesh)."""
        from gmr_studio.core.formats.gltf import export_gltf

        try:
            result = export_gltf(self.state.motion, path)
        except (OSError, ValueError) as exc:
            self.files.report(f"Cannot export {path}: {exc}")
            return False
        except Exception as exc:
            self.files.report(describe_unexpected(f"Exporting {path}", exc))
            return False
        self.state.show_message(f"Exported {path} ({result.unit_note})")
        return True

    # ------------------------------------------------------------- screenshots, video
    def save_screenshot_dialog(self) -> None:
        name = video.suggested_name(self.state.path, ".png", self.state.frame)
        start = str(Path(video.export_folder(self.files.settings, self.files.folder())) / name)
        path, _ = QFileDialog.getSaveFileName(self.files.window, "Save screenshot", start, "PNG images (*.png)")
        if path:
            video.remember_export_folder(self.files.settings, path)
            width, height = save_screenshot(
                self.files.scene_provider(), path if path.lower().endswith(".png") else path + ".png"
            )
            self.state.show_message(f"Saved a {width}x{height} screenshot to {path}")

    def export_video_dialog(self, speed: float = 1.0) -> None:
        if self.state.motion is None:
            return
        frames = video.ask_frame_range(self.files.window, self.state.motion.n_frames)
        if frames is None:
            return
        whole = frames == (0, self.state.motion.n_frames - 1)
        name = video.suggested_name(self.state.path, ".mp4", frames[0], None if whole else frames[1])
        start = str(Path(video.export_folder(self.files.settings, self.files.folder())) / name)
        path, _ = QFileDialog.getSaveFileName(self.files.window, "Export video", start, "MP4 video (*.mp4)")
        if not path:
            return
        path = path if path.lower().endswith(".mp4") else path + ".mp4"
        video.remember_export_folder(self.files.settings, path)
        progress = QProgressDialog("Writing video...", "Cancel", 0, 100, self.files.window)
        progress.setWindowModality(Qt.WindowModality.WindowModal)
        progress.setMinimumDuration(0)

        def report(done: int, total: int) -> bool:
            progress.setMaximum(total)
            progress.setValue(done)
            QApplication.processEvents()
            return not progress.wasCanceled()

        try:
            written = export_video(
                self.files.scene_provider(), path, speed=speed, progress=report, first=frames[0], last=frames[1]
            )
        except (OSError, RuntimeError) as exc:
            self.files.report(f"Cannot export the video: {exc}")
            written = 0
        finally:
            progress.reset()
        self.state.show_message(f"Wrote {written} frames to {path}" if written else "Video export cancelled")
