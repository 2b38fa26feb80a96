"""Indexing in the background: :meth:`core.library.index.Library.index` in a worker thread
(its files read in worker processes), reporting as it goes and stopping when asked.

:class:`IndexJob` opens its own connection to the library (SQLite connections stay in their
thread) and emits ``planned(total)`` once it knows how many files it reads,
``progressed(done, failed)`` after each file, ``written()`` after each batch committed (the
table shows the new rows), then ``finished(summary text, stopped)`` or ``failed(message)``.
:meth:`IndexJob.cancel` ends it after the task in hand: what is written stays, and the next
run goes on from there.
"""

from __future__ import annotations

import os

from PyQt6.QtCore import QThread, pyqtSignal

from gmr_studio.core.errors import OperationError
from gmr_studio.core.library.index import Library
from gmr_studio.core.library.reading import IndexOptions

#: files a task in the app: small, so that a cancel is quick
CHUNK_FILES = 2


class IndexJob(QThread):
    """Index ``folders`` into the library at ``path`` (module docstring)."""

    planned = pyqtSignal(int)
    progressed = pyqtSignal(int, int)
    written = pyqtSignal()
    finished_indexing = pyqtSignal(str, bool)
    failed = pyqtSignal(str)

    def __init__(self, path: str, folders: list[str], *, jobs: int | None = None, parent=None) -> None:
        super().__init__(parent)
        self.path = path
        self.folders = list(folders)
        self.jobs = jobs if jobs is not None else max(1, os.cpu_count() or 1)
        self.body_model: str | None = None
        self._cancelled = False
        self._done = self._failed = 0

    def cancel(self) -> None:
        """Stop after the task in hand (the rows written stay)."""
        self._cancelled = True

    @property
    def cancelled(self) -> bool:
        return self._cancelled

    def run(self) -> None:
        try:
            with Library(self.path) as library:
                summary = library.index(
                    self.folders,
                    IndexOptions(body_model=self.body_model),
                    jobs=self.jobs,
                    chunk=CHUNK_FILES,
                    on_planned=lambda plan: self.planned.emit(len(plan.tasks)),
                    on_file=self._on_file,
                    on_batch=lambda _count: self.written.emit(),
                    stop=lambda: self._cancelled,
                )
        except OperationError as exc:
            self.failed.emit(str(exc))
        except Exception as exc:  # a bug or a resource problem: said, never a crash of the window
            self.failed.emit(f"{type(exc).__name__}: {exc}")
        else:
            self.finished_indexing.emit(summary.text(), summary.stopped)

    def _on_file(self, record) -> None:
        self._done += 1
        self._failed += record.status != "ok"
        self.progressed.emit(self._done, self._failed)
