"""Autosave: while the document has unsaved edits, a recovery copy is kept on disk.

:class:`Autosaver` listens to the state, not to whoever edits it, so edits from the menus,
the keyboard, the command line or a script all count. Rules:

- the first unsaved edit starts a timer: the copy is written within ``interval`` (30 s);
- after that at most once per ``interval`` while edits keep coming, and at once on every
  ``every``-th (10th) edit;
- a clean document (saved, or undone back to its file) and a document closed or replaced
  after the user was asked remove the copy.

Writing happens in one worker thread, in the order asked (write, write, remove...), so a
1,000,000-frame motion does not freeze the window and a removal never races a write. The
motion handed to the worker is immutable (an edit swaps in another one), so the worker
needs no lock.
"""

from __future__ import annotations

import concurrent.futures
from pathlib import Path

from PyQt6 import sip
from PyQt6.QtCore import QObject, QTimer, pyqtSignal

from gmr_studio.app.crash import log_exception
from gmr_studio.app.model.state import StudioState
from gmr_studio.app.reliability import recovery
from gmr_studio.core.model.motion import Motion

#: longest time unsaved edits go without a recovery copy, milliseconds
INTERVAL_MS = 30_000
#: every this many edits a copy is written at once
EVERY_EDITS = 10


class Autosaver(QObject):
    """Keeps a recovery copy of ``state``'s document while it has unsaved edits."""

    written = pyqtSignal(str)  # a recovery copy was written (its path), from the GUI thread
    removed = pyqtSignal(str)
    _finished = pyqtSignal(str, str)  # (what, path) from the worker, delivered in the GUI thread

    def __init__(
        self,
        state: StudioState,
        parent: QObject | None = None,
        *,
        interval_ms: int = INTERVAL_MS,
        every: int = EVERY_EDITS,
        folder: Path | None = None,
    ) -> None:
        super().__init__(parent)
        self.state = state
        self.every = every
        self.folder = folder
        self.edits = 0  # edits since the document was opened or last saved
        self.current: Path | None = None  # the copy this document has on disk (or will have)
        self._worker = concurrent.futures.ThreadPoolExecutor(max_workers=1, thread_name_prefix="autosave")
        self._pending: list[concurrent.futures.Future] = []
        self._closed = False
        self.timer = QTimer(self)
        self.timer.setSingleShot(True)
        self.timer.setInterval(interval_ms)
        self.timer.timeout.connect(self.save_now)
        self._finished.connect(self._on_finished)
        # the stack's index moves after every edit, undo, redo and history jump (the
        # state's motion_changed comes from inside the command, before the stack is dirty)
        state.undo_stack.indexChanged.connect(self._on_edited)
        state.modified_changed.connect(self._on_modified_changed)
        state.document_changed.connect(self._on_document_changed)

    # ------------------------------------------------------------------ state signals
    def _on_edited(self, _index: int) -> None:
        # a window closing deletes its undo stack, which may move its index while it goes
        if sip.isdeleted(self.state.undo_stack) or not self.state.modified:
            return
        self.edits += 1
        if self.every and self.edits % self.every == 0:
            self.save_now()
        elif not self.timer.isActive():
            self.timer.start()

    def _on_modified_changed(self, modified: bool) -> None:
        if not modified:  # saved, or undone back to the file
            self.edits = 0
            self.discard()

    def _on_document_changed(self) -> None:
        # another document: the user was asked about the previous one's edits already
        self.edits = 0
        self.discard()

    # ------------------------------------------------------------------------ actions
    def adopt(self, record: recovery.RecoveryRecord) -> None:
        """The document now open was restored from ``record``: keep its copy and count."""
        self.current = record.path
        self.edits = record.edits

    def save_now(self) -> None:
        """Write the copy now (in the worker) if the document has unsaved edits."""
        self.timer.stop()
        motion = self.state.motion
        if motion is None or not self.state.modified:
            return
        path = recovery.recovery_path(self.state.path, self.folder)
        if self.current is not None and self.current != path:
            self._submit("remove", self.current, None, 0)
        self.current = path
        self._submit("write", path, motion, self.edits)

    def discard(self) -> None:
        """Remove the document's copy (in the worker, after any write still running)."""
        self.timer.stop()
        if self.current is not None:
            self._submit("remove", self.current, None, 0)
            self.current = None

    def wait(self) -> None:
        """Block until every write and removal asked so far is done (tests, closing)."""
        for future in list(self._pending):
            future.result()
        from PyQt6.QtCore import QCoreApplication

        QCoreApplication.processEvents()

    def shutdown(self) -> None:
        """Finish what was asked and stop the worker (the window is closing)."""
        self.timer.stop()
        self._closed = True
        self._worker.shutdown(wait=True)

    # ------------------------------------------------------------------------- worker
    def _submit(self, what: str, path: Path, motion: Motion | None, edits: int) -> None:
        if self._closed:  # the window closed: nothing more is written or removed
            return
        original = self.state.path
        future = self._worker.submit(self._work, what, path, motion, original, edits)
        self._pending = [f for f in self._pending if not f.done()] + [future]

    def _work(self, what: str, path: Path, motion: Motion | None, original: Path | None, edits: int) -> None:
        try:
            if what == "write":
                recovery.write_recovery(motion, path, original, edits)
            else:
                path.unlink(missing_ok=True)
        except Exception as exc:  # a full disk must not take the app down; the log says why
            log_exception(f"Autosave ({what} {path})", exc)
            return
        self._finished.emit(what, str(path))

    def _on_finished(self, what: str, path: str) -> None:
        (self.written if what == "write" else self.removed).emit(path)
