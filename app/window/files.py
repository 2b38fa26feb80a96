"""Files: open (dialog, drop, command line), save, markers, recent files, settings (exports:
:mod:`app.window.exports`).

:class:`FileController` turns user requests into state changes. Reading happens in a
worker thread (:class:`~app.loading.LoadJob`) with a busy progress dialog; a bad file is
shown in a dialog with its path, line, column and message, and the current document stays
as it was. Unsaved edits are offered for saving before another file replaces them or the
window closes. Recent files and the last folder live in QSettings.
"""

from __future__ import annotations

import functools
from pathlib import Path

from PyQt6.QtCore import QObject, QSettings, Qt, pyqtSignal
from PyQt6.QtWidgets import QApplication, QFileDialog, QMessageBox, QProgressDialog, QWidget

from gmr_studio.app.crash import describe_unexpected, log_exception
from gmr_studio.app.model import loading, marker_document, pelvis_recovery
from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.core.compare.clock import DEFAULT_OFFSET
from gmr_studio.core.errors import MotionFileError, OperationError
from gmr_studio.core.formats import write_motion
from gmr_studio.core.markers import MarkerSet
from gmr_studio.core.timebase.clock import rate_text

MAX_RECENT = 8


def error_text(exc: BaseException) -> tuple[str, str]:
    """(short text, details) for an error dialog: file, line and column, message."""
    if isinstance(exc, MotionFileError):
        where = f"line {exc.line}" + (f", column {exc.column}" if exc.column is not None else "") if exc.line else ""
        head = f"{Path(exc.path).name}" + (f" ({where})" if where else "")
        return f"Cannot read {head}:\n{exc.message}", str(exc)
    if isinstance(exc, OperationError):  # an edit the core refuses, e.g. a skeleton the markers cannot make
        return str(exc), str(exc)
    return f"{type(exc).__name__}: {exc}", str(exc)


class FileController(QObject):
    """File menu logic for one window; ``window`` parents the dialogs."""

    recent_changed = pyqtSignal(list)
    load_finished = pyqtSignal(bool)  # a load ended (True: shown, False: failed)

    def __init__(self, state: StudioState, scene_provider, settings: QSettings, window: QWidget) -> None:
        super().__init__(window)
        self.state = state
        self.scene_provider = scene_provider  # () -> SkeletonScene
        self.settings = settings
        self.window = window
        self._jobs: dict[loading.LoadJob, tuple] = {}
        self.pending_markers: str | None = None
        self.quiet = False  # tests: errors go to the status bar only, no modal dialog
        self.layers = None  # the window's comparison layers (app.layers.Layers)
        self.marker_document = None  # the last skeleton built from markers (app.model.marker_document)

    # ------------------------------------------------------------------- settings
    def recent_files(self) -> list[str]:
        value = self.settings.value("recent_files", [])
        if isinstance(value, str):
            value = [value]
        return [str(v) for v in (value or [])]

    def _remember(self, path: str | Path) -> None:
        path = str(Path(path).resolve())
        recent = [path] + [p for p in self.recent_files() if p != path]
        self.settings.setValue("recent_files", recent[:MAX_RECENT])
        self.settings.setValue("last_folder", str(Path(path).parent))
        self.recent_changed.emit(recent[:MAX_RECENT])

    def clear_recent(self) -> None:
        self.settings.setValue("recent_files", [])
        self.recent_changed.emit([])

    def folder(self) -> str:
        return str(self.settings.value("last_folder", "") or "")

    # ---------------------------------------------------------------------- open
    def open_dialog(self) -> None:
        if not self.maybe_save():
            return
        path, _ = QFileDialog.getOpenFileName(
            self.window,
            "Open motion",
            self.folder(),
            loading.file_filter(loading.motion_suffixes() + loading.marker_suffixes(), "Motion and marker files"),
        )
        if path:
            self.open_path(path, ask=False)

    def open_path(
        self, path: str | Path, *, markers: str | Path | None = None, ask: bool = True, wait: bool = False
    ) -> None:
        """Open a motion file (in a worker thread; ``wait`` blocks until it is shown); a
        marker file (C3D, TRC) opens as the skeleton built from its markers.

        ``markers``: a marker file to add once the motion is shown."""
        if ask and not self.maybe_save():
            return
        self.pending_markers = str(markers) if markers else None
        if Path(path).suffix.lower() in loading.marker_suffixes():
            reader = functools.partial(marker_document.load_marker_document, refine=self.refine_markers())
            label = f"Reading {Path(path).name} and building the skeleton from its markers..."
            self._run(reader, path, self._on_marker_document_loaded, label, wait)
            return
        options = {"body_model": self.body_model(ask=True)} if Path(path).suffix.lower() == ".npz" else {}
        reader = functools.partial(loading.load_snapshot, **options)
        self._run(reader, path, self._on_motion_loaded, f"Reading {Path(path).name}...", wait)

    def refine_markers(self) -> bool:
        """Skeletons built from markers get the least-squares refinement (a setting)."""
        return str(self.settings.value("markers/refine", "false")).lower() == "true"

    def set_refine_markers(self, refine: bool) -> None:
        self.settings.setValue("markers/refine", bool(refine))

    def _on_marker_document_loaded(self, document: marker_document.MarkerDocument, path: str, wait: bool) -> None:
        self.pending_markers = None
        self.marker_document = document
        self.state.show_message(marker_document.show_marker_document(self.state, document, path, self.layers))
        self._remember(path)
        self.load_finished.emit(True)

    def build_skeleton(self, *, wait: bool = False) -> None:
        """Markers > Build skeleton: the skeleton built from the markers shown (in a worker
        thread) replaces the document, as one undoable edit."""
        overlay = self.state.marker_overlay
        if overlay is None:
            self.state.show_message("Build skeleton: add markers first (Markers > Add markers)")
            return
        build = functools.partial(marker_document.build_from_markers, overlay.markers, refine=self.refine_markers())
        label = f"Building the skeleton from {overlay.markers.n_markers} markers..."
        self._run(lambda _path: build(), overlay.markers.source or "markers", self._on_skeleton_built, label, wait)

    def _on_skeleton_built(self, document: marker_document.MarkerDocument, _path: str, _wait: bool) -> None:
        self.marker_document = document
        if marker_document.push_build_skeleton(self.state, document):
            marker_document.add_model_layer(document, document.markers.source or "markers", self.layers)
        self.load_finished.emit(True)

    def body_model(self, *, ask: bool) -> str | None:
        """The body model file AMASS/SMPL motions are read with (a setting); when unset and
        ``ask``, a dialog asks for it (None if cancelled: the reader then says what is missing)."""
        chosen = str(self.settings.value("body_model", "") or "")
        if (not chosen or not Path(chosen).exists()) and ask and not self.quiet:
            self.choose_body_model()
            chosen = str(self.settings.value("body_model", "") or "")
        return chosen or None

    def choose_body_model(self) -> None:
        path, _ = QFileDialog.getOpenFileName(
            self.window,
            "Body model for AMASS/SMPL motions (SMPL-H for AMASS)",
            self.folder(),
            "Body models (*.npz *.pkl);;All files (*)",
        )
        if path:
            self.settings.setValue("body_model", path)
            self.state.show_message(f"AMASS/SMPL motions are read with the body model {path}")

    def _run(self, function, path, on_loaded, label: str, wait: bool) -> None:
        job = loading.LoadJob(function, path, self)
        progress = None
        if self.window.isVisible() and not wait:
            progress = QProgressDialog(label, None, 0, 0, self.window)
            progress.setWindowTitle("GMR Studio")
            progress.setWindowModality(Qt.WindowModality.WindowModal)
            progress.setMinimumDuration(300)
            progress.setValue(0)
        self._jobs[job] = (on_loaded, progress, str(path), wait)
        job.loaded.connect(self._on_job_loaded)
        job.failed.connect(self._on_job_failed)
        self.state.show_message(label)
        job.start()
        if wait:
            job.wait()
            while job in self._jobs:  # deliver the queued result (and any job it starts)
                QApplication.processEvents()

    def busy(self) -> bool:
        """A file is being read."""
        return bool(self._jobs)

    def _finish(self, job: loading.LoadJob):
        on_loaded, progress, path, wait = self._jobs.pop(job)
        if progress is not None:
            progress.reset()
            progress.deleteLater()
        job.wait()
        job.deleteLater()
        return on_loaded, path, wait

    def _on_job_loaded(self, job: loading.LoadJob, result) -> None:
        on_loaded, path, wait = self._finish(job)
        on_loaded(result, path, wait)

    def _on_job_failed(self, job: loading.LoadJob, exc: BaseException) -> None:
        self._finish(job)
        self._on_failed(exc)

    def _on_motion_loaded(self, snapshot: Snapshot, path: str, wait: bool) -> None:
        self.state.open_document(snapshot, path)
        self._remember(path)
        motion = snapshot.motion
        self.state.show_message(
            f"Opened {Path(path).name}: {motion.n_joints} joints, {len(motion.roots)} root(s), "
            f"{motion.n_frames} frames at {rate_text(motion.frame_time)} Hz"
        )
        self.load_finished.emit(True)
        if self.pending_markers:
            markers, self.pending_markers = self.pending_markers, None
            self.add_markers_path(markers, wait=wait)

    def show_error(self, exc: BaseException) -> None:
        """Tell the user a file could not be read (file, line, column, what); nothing changes."""
        self._on_failed(exc)

    def _on_failed(self, exc: BaseException) -> None:
        self.pending_markers = None
        short, details = error_text(exc)
        if not isinstance(exc, (MotionFileError, OperationError)):  # a bug or a resource problem, not a bad file
            log = log_exception("Reading a file", exc)
            details += f"\n(logged in {log})" if log else ""
        self.state.show_message(details)
        self.load_finished.emit(False)
        if not self.quiet:
            box = QMessageBox(
                QMessageBox.Icon.Critical, "GMR Studio", short, QMessageBox.StandardButton.Ok, self.window
            )
            box.setDetailedText(details)
            box.exec()

    # ---------------------------------------------------------------- comparisons
    def compare_dialog(self) -> None:
        """File > Compare with...: a motion to show as a ghost layer compared with the
        document, or a marker file (TRC, C3D) to show as a marker-set layer."""
        if self.state.motion is None or self.layers is None:
            return
        suffixes = loading.motion_suffixes() + loading.marker_suffixes()
        path, _ = QFileDialog.getOpenFileName(
            self.window, "Compare with", self.folder(), loading.file_filter(suffixes, "Motion and marker files")
        )
        if path:
            self.compare_path(path)

    def compare_path(
        self,
        path: str | Path,
        *,
        joint_map: str | None = None,
        align: str = "none",
        offset: float | str = DEFAULT_OFFSET,
        wait: bool = False,
    ) -> None:
        """Read ``path`` (worker thread; a bad file: the same dialog as opening, the document
        untouched) and add it as a comparison layer: a motion with its joints matched through
        ``joint_map``, aligned by ``align`` at ``offset``; a marker file (TRC, C3D) as a
        marker-set layer, aligned as the marker overlay is."""
        label = f"Reading {Path(path).name}..."
        if Path(path).suffix.lower() in loading.marker_suffixes():
            self._run(loading.load_markers, path, self._on_compare_markers_loaded, label, wait)
            return
        on_loaded = functools.partial(self._on_compare_loaded, joint_map=joint_map, align=align, offset=offset)
        self._run(loading.load_snapshot, path, on_loaded, label, wait)

    def _on_compare_loaded(
        self,
        snapshot: Snapshot,
        path: str,
        _wait: bool,
        *,
        joint_map: str | None,
        align: str = "none",
        offset: float | str = DEFAULT_OFFSET,
    ) -> None:
        try:
            layer = self.layers.add(snapshot, path, joint_map, align=align, offset=offset)
        except ValueError as exc:
            self.report(f"Cannot compare with {Path(path).name}: {exc}")
            self.load_finished.emit(False)
            return
        c = layer.comparison
        self.state.show_message(
            f"Comparing with {layer.name}: {c.n_pairs} joints matched, MPJPE {c.position.mean:.4g} {c.units_text} "
            f"({layer.alignment_text})"
        )
        self.load_finished.emit(True)

    def _on_compare_markers_loaded(self, markers: MarkerSet, path: str, _wait: bool) -> None:
        try:
            layer = self.layers.add_markers(markers, path)
        except ValueError as exc:
            self.report(f"Cannot compare with {Path(path).name}: {exc}")
            self.load_finished.emit(False)
            return
        self.state.show_message(f"Showing {layer.name} as a layer: {layer.alignment_text}")
        self.load_finished.emit(True)

    # ------------------------------------------------------------------- markers
    def add_markers_dialog(self) -> None:
        if self.state.motion is None:
            return
        path, _ = QFileDialog.getOpenFileName(
            self.window, "Add markers", self.folder(), loading.file_filter(loading.marker_suffixes(), "Marker files")
        )
        if path:
            self.add_markers_path(path)

    def add_markers_path(self, path: str | Path, *, wait: bool = False) -> None:
        self._run(loading.load_markers, path, self._on_markers_loaded, f"Reading markers {Path(path).name}...", wait)

    def _on_markers_loaded(self, markers: MarkerSet, path: str, _wait: bool) -> None:
        self.state.set_markers(markers)
        overlay = self.state.marker_overlay
        if overlay is not None:
            text = (
                f"Added {markers.n_markers} markers from {Path(path).name} ({markers.rate:g} Hz, {markers.units}); "
                f"aligned: {overlay.alignment.method}"
            )
            try:
                if pelvis_recovery.recover_pelvis_frames(self.state, quiet=True):
                    text += "; pelvis frames recovered"
            except ValueError as exc:  # e.g. an automatic alignment the pelvis fit cannot use
                text += f"; pelvis frames not recovered: {exc}"
            self.state.show_message(text)
        self.load_finished.emit(True)

    # ---------------------------------------------------------------------- save
    def maybe_save(self) -> bool:
        """True if the caller may drop the document: it is unmodified, or the user saved it
        or chose to discard the edits."""
        if not self.state.modified:
            return True
        name = self.state.path.name if self.state.path else "the motion"
        answer = QMessageBox.question(
            self.window,
            "GMR Studio",
            f"Save the changes to {name}?",
            QMessageBox.StandardButton.Save | QMessageBox.StandardButton.Discard | QMessageBox.StandardButton.Cancel,
            QMessageBox.StandardButton.Save,
        )
        if answer == QMessageBox.StandardButton.Save:
            return self.save()
        return answer == QMessageBox.StandardButton.Discard

    def save(self) -> bool:
        path = self.state.path
        if path is None or path.suffix.lower() != ".gmr":
            return self.save_as()
        return self.save_to(path)

    def save_as(self) -> bool:
        if self.state.motion is None:
            return False
        stem = self.state.path.with_suffix(".gmr").name if self.state.path else "motion.gmr"
        path, _ = QFileDialog.getSaveFileName(
            self.window, "Save as GMR", str(Path(self.folder()) / stem), "GMR files (*.gmr)"
        )
        if not path:
            return False
        if not path.lower().endswith(".gmr"):
            path += ".gmr"
        return self.save_to(path)

    def save_to(self, path: str | Path) -> bool:
        """Write the document as GMR (atomically) and make ``path`` its file."""
        try:
            write_motion(self.state.motion, path)
        except OSError as exc:
            self.report(f"Cannot save {path}: {exc.strerror or exc}")
            return False
        except Exception as exc:
            self.report(describe_unexpected(f"Saving {path}", exc))
            return False
        self.state.mark_saved(path)
        self._remember(path)
        self.state.show_message(f"Saved {path}")
        return True

    def report(self, text: str) -> None:
        self.state.show_message(text)
        if not self.quiet:
            QMessageBox.warning(self.window, "GMR Studio", text)
