"""The Library panel: every take of the library's folders in a table, to find, see and open.

- A row per file: its thumbnail, name, format, duration, frames, rate, joints (or markers),
  skeleton group and problem counts (in the colour of the worst); a file that cannot be read
  says why. Click a column's header to sort by it.
- The filter box takes words of the name and the query's filters
  (:func:`core.library.query.parse_filter`: ``format:bvh min:2 max:10 joints:31
  has:pop:warning group:3 failed``).
- Enter or a double click opens the selected take (:attr:`LibraryPanel.open_requested`: the
  window opens it the way File > Open does, asking about unsaved edits); with two takes
  selected, the one the cursor is on opens and the other is compared with it, through the
  shipped joint map that pairs their joints best (CMU's BVH and ASF/AMC: the CMU map). A take dragged onto the view
  is added as a comparison layer.
- *Add folder...* (or a folder dropped on the panel or the window) indexes it in the
  background (:class:`~app.library.indexing.IndexJob`): a progress bar and *Cancel*, new rows
  shown as they are written. *Index again* reads what changed in every folder of the library.
- The library is a file (default :func:`core.library.schema.default_library_path`); *Open
  library...* picks or makes another, and the ones opened are remembered (``library/files``
  in the settings, the last one first).
"""

from __future__ import annotations

import time
from pathlib import Path

from PyQt6.QtCore import QSettings, QSize, Qt, QTimer, pyqtSignal
from PyQt6.QtGui import QDragEnterEvent, QDropEvent, QKeyEvent
from PyQt6.QtWidgets import (
    QAbstractItemView,
    QComboBox,
    QFileDialog,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QLineEdit,
    QProgressBar,
    QPushButton,
    QTableView,
    QVBoxLayout,
    QWidget,
)

from gmr_studio.app.library.indexing import IndexJob
from gmr_studio.app.library.table_model import COLUMNS, JOINTS, NAME, THUMBNAIL, LibraryModel, thumbnail_size
from gmr_studio.core.errors import OperationError
from gmr_studio.core.library.index import Library
from gmr_studio.core.library.query import Query, count, parse_filter, row_of_path
from gmr_studio.core.library.schema import default_library_path
from gmr_studio.core.library.skeletons import Skeleton, best_joint_map

MAX_LIBRARIES = 8
#: the thumbnails' height in the table (pixels): three quarters of the stored picture's
THUMBNAIL_HEIGHT = 48
#: the table is read again at most this often while rows are being written (ms), and never
#: more than a tenth of the time (a large library's rows take longer to count)
REFRESH_MS = 500
FILTER_HELP = (
    "Words of the name, and filters: format:bvh  min:2  max:10 (seconds)  joints:31  "
    "has:pop[:warning]  has:any:error  group:3  failed"
)


class LibraryTable(QTableView):
    """The table: Enter opens the selection as a double click does."""

    activated_rows = pyqtSignal()

    def keyPressEvent(self, event: QKeyEvent) -> None:  # noqa: N802 (Qt's name)
        if event.key() in (Qt.Key.Key_Return, Qt.Key.Key_Enter) and self.selectionModel().hasSelection():
            self.activated_rows.emit()
            event.accept()
            return
        super().keyPressEvent(event)


class LibraryPanel(QWidget):
    """The panel (module docstring); ``settings`` remembers the libraries opened."""

    #: (paths, joint map name or None): one path to open, or two: open the first and compare
    #: the second with it through the joint map that pairs their joints best
    open_requested = pyqtSignal(list, object)
    message = pyqtSignal(str)  # for the status bar
    indexing_changed = pyqtSignal(bool)

    def __init__(self, settings: QSettings, parent: QWidget | None = None, *, jobs: int | None = None) -> None:
        super().__init__(parent)
        self.settings = settings
        self.jobs = jobs
        self.library: Library | None = None
        self.job: IndexJob | None = None
        self.queued: list[str] = []
        self.model = LibraryModel(self)
        self.setAcceptDrops(True)

        self.libraries = QComboBox()
        self.libraries.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.libraries.setMinimumContentsLength(24)
        self.libraries.setToolTip("The library file: the takes of its folders")
        self.open_button = QPushButton("Open library...")
        self.add_button = QPushButton("Add folder...")
        self.again_button = QPushButton("Index again")
        self.again_button.setToolTip("Read what changed in every folder of the library (new, changed, removed files)")
        self.filter = QLineEdit()
        self.filter.setPlaceholderText("Filter: " + FILTER_HELP)
        self.filter.setToolTip(FILTER_HELP)
        self.filter.setClearButtonEnabled(True)
        top = QHBoxLayout()
        for widget in (self.libraries, self.open_button, self.add_button, self.again_button):
            top.addWidget(widget)
        top.addWidget(self.filter, 1)

        self.table = LibraryTable()
        self.table.setModel(self.model)
        self.table.setSortingEnabled(True)
        self.table.sortByColumn(NAME, Qt.SortOrder.AscendingOrder)
        self.table.setSelectionBehavior(QAbstractItemView.SelectionBehavior.SelectRows)
        self.table.setSelectionMode(QAbstractItemView.SelectionMode.ExtendedSelection)
        self.table.setEditTriggers(QAbstractItemView.EditTrigger.NoEditTriggers)
        self.table.setDragEnabled(True)
        self.table.setDragDropMode(QAbstractItemView.DragDropMode.DragOnly)
        self.table.setVerticalScrollMode(QAbstractItemView.ScrollMode.ScrollPerPixel)
        self.table.setWordWrap(False)
        self.table.setAlternatingRowColors(True)
        stored_width, stored_height = thumbnail_size()
        width, height = round(stored_width * THUMBNAIL_HEIGHT / stored_height), THUMBNAIL_HEIGHT
        self.table.setIconSize(QSize(width, height))
        self.model.thumbnail_height = height
        self.table.verticalHeader().setDefaultSectionSize(height + 4)
        self.table.verticalHeader().setSectionResizeMode(QHeaderView.ResizeMode.Fixed)
        self.table.verticalHeader().hide()
        header = self.table.horizontalHeader()
        header.setSectionResizeMode(QHeaderView.ResizeMode.Interactive)
        header.resizeSection(THUMBNAIL, width + 12)
        header.resizeSection(NAME, 220)
        for column in range(2, len(COLUMNS) - 1):
            header.resizeSection(column, 72)
        header.resizeSection(JOINTS, 92)  # "41 markers"
        header.setStretchLastSection(True)
        header.setSectionsClickable(True)

        self.progress = QProgressBar()
        self.progress.setTextVisible(True)
        self.cancel_button = QPushButton("Cancel")
        self.status = QLabel()
        bottom = QHBoxLayout()
        bottom.addWidget(self.status, 1)
        bottom.addWidget(self.progress)
        bottom.addWidget(self.cancel_button)
        self.progress.hide()
        self.cancel_button.hide()

        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        layout.addLayout(top)
        layout.addWidget(self.table, 1)
        layout.addLayout(bottom)

        self._filter_timer = QTimer(self, singleShot=True, interval=150)
        self._filter_timer.timeout.connect(self.apply_filter)
        self._refresh_timer = QTimer(self, singleShot=True, interval=REFRESH_MS)
        self._refresh_timer.timeout.connect(self.refresh)
        self.filter.textChanged.connect(lambda _text: self._filter_timer.start())
        self.filter.returnPressed.connect(self.apply_filter)
        self.table.activated_rows.connect(self.open_selected)
        self.table.doubleClicked.connect(lambda _index: self.open_selected())
        self.open_button.clicked.connect(self.choose_library)
        self.add_button.clicked.connect(self.add_folder_dialog)
        self.again_button.clicked.connect(self.index_again)
        self.cancel_button.clicked.connect(self.cancel)
        self.libraries.activated.connect(lambda i: self.open_library(self.libraries.itemData(i)))
        self.model.modelReset.connect(self._show_counts)

    # ----------------------------------------------------------------- libraries
    def remembered(self) -> list[str]:
        """The library files opened, the last one first (the default when none was)."""
        value = self.settings.value("library/files", [])
        files = [str(v) for v in ([value] if isinstance(value, str) else (value or []))]
        return files or [str(default_library_path())]

    def open_library(self, path: str | Path | None = None) -> bool:
        """Show the library at ``path`` (default: the last one opened), made if new;
        False (and the reason in the status) when it cannot be opened."""
        path = str(Path(path if path is not None else self.remembered()[0]).expanduser())
        if self.library is not None and str(self.library.path) == path:
            return True
        if self.job is not None:
            self.cancel()
            self.job.wait()
        try:
            library = Library(path)
        except OperationError as exc:
            self.message.emit(str(exc))
            self.status.setText(str(exc))
            return False
        if self.library is not None:
            self.model.set_connection(None)
            self.library.close()
        self.library = library
        files = [path] + [f for f in self.remembered() if f != path]
        self.settings.setValue("library/files", files[:MAX_LIBRARIES])
        self.libraries.blockSignals(True)
        self.libraries.clear()
        for file in files[:MAX_LIBRARIES]:
            self.libraries.addItem(Path(file).name, file)
            self.libraries.setItemData(self.libraries.count() - 1, file, Qt.ItemDataRole.ToolTipRole)
        self.libraries.setCurrentIndex(0)
        self.libraries.blockSignals(False)
        self.model.set_connection(library.connection)
        return True

    def choose_library(self) -> None:
        folder = str(Path(self.remembered()[0]).parent)
        path, _ = QFileDialog.getSaveFileName(
            self,
            "Open or make a library",
            folder,
            "Libraries (*.sqlite *.db);;All files (*)",
            options=QFileDialog.Option.DontConfirmOverwrite,
        )
        if path:
            self.open_library(path)

    def close_library(self) -> None:
        """Stop indexing and close the file (the window is closing)."""
        if self.job is not None:
            self.cancel()
            self.job.wait()
        if self.library is not None:
            self.model.set_connection(None)
            self.library.close()
            self.library = None

    # ------------------------------------------------------------------ indexing
    def add_folder_dialog(self) -> None:
        folder = QFileDialog.getExistingDirectory(self, "Add a folder of takes to the library")
        if folder:
            self.add_folders([folder])

    def add_folders(self, folders: list[str]) -> None:
        """Index ``folders`` into the library in the background (after the run in hand)."""
        if self.library is None and not self.open_library():
            return
        self.queued += [str(f) for f in folders if str(f) not in self.queued]
        if self.job is None:
            self._start_next()

    def index_again(self) -> None:
        """Read what changed in every folder of the library."""
        if self.library is not None:
            self.add_folders(self.library.folders())

    def cancel(self) -> None:
        self.queued.clear()
        if self.job is not None:
            self.job.cancel()
            self.status.setText("stopping after the files in hand...")

    def indexing(self) -> bool:
        return self.job is not None

    def _start_next(self) -> None:
        if not self.queued or self.library is None:
            return
        folders, self.queued = self.queued, []
        job = IndexJob(str(self.library.path), folders, jobs=self.jobs, parent=self)
        job.body_model = str(self.settings.value("body_model", "") or "") or None
        job.planned.connect(self._on_planned)
        job.progressed.connect(self._on_progressed)
        job.written.connect(lambda: self._refresh_timer.isActive() or self._refresh_timer.start())
        job.finished_indexing.connect(self._on_finished)
        job.failed.connect(self._on_failed)
        self.job = job
        self.progress.setRange(0, 0)
        self.progress.setFormat("listing the files...")
        self.progress.show()
        self.cancel_button.show()
        self.again_button.setEnabled(False)
        self.indexing_changed.emit(True)
        job.start()

    def _on_planned(self, total: int) -> None:
        self.progress.setRange(0, max(total, 1))
        self.progress.setValue(0)
        self.progress.setFormat(f"%v of {total} files" if total else "nothing new")

    def _on_progressed(self, done: int, failed: int) -> None:
        self.progress.setValue(done)
        if failed:
            self.progress.setFormat(f"%v of %m files, {failed} failed")

    def _on_finished(self, text: str, stopped: bool) -> None:
        self._end_job()
        self.model.forget_thumbnails()
        self.refresh()
        self.message.emit(f"Library: {text}")
        self.status.setToolTip(text)
        self._start_next()

    def _on_failed(self, text: str) -> None:
        self._end_job()
        self.refresh()
        self.message.emit(f"Library: {text}")
        self.status.setText(text)

    def _end_job(self) -> None:
        job, self.job = self.job, None
        if job is not None:
            job.wait()
            job.deleteLater()
        self.progress.hide()
        self.cancel_button.hide()
        self.again_button.setEnabled(True)
        self.indexing_changed.emit(False)

    # ------------------------------------------------------------------- showing
    def apply_filter(self) -> None:
        """The filter box's text as the table's query (its sort kept)."""
        self._filter_timer.stop()
        try:
            query = parse_filter(self.filter.text(), self.model.query)
        except ValueError as exc:
            self.filter.setStyleSheet("QLineEdit { border: 1px solid #e0303a; }")
            self.filter.setToolTip(f"{exc}\n\n{FILTER_HELP}")
            return
        self.filter.setStyleSheet("")
        self.filter.setToolTip(FILTER_HELP)
        if query != self.model.query:
            self.keep_selection(lambda: self.model.set_query(query))

    def refresh(self) -> None:
        """Read the table again (rows written), the selection and the current row kept."""
        self._refresh_timer.stop()
        start = time.perf_counter()
        self.keep_selection(self.model.refresh)
        self._refresh_timer.setInterval(max(REFRESH_MS, int(10_000 * (time.perf_counter() - start))))

    def keep_selection(self, change) -> None:
        """Run ``change`` (which resets the model) and select the same files again."""
        selected = self.selected_paths()
        current = self.model.path_of(self.table.currentIndex().row()) if self.table.currentIndex().isValid() else None
        change()
        selection = self.table.selectionModel()
        rows = self.model.rows_with_paths([*selected, *([current] if current else [])])
        for path in selected:
            if path in rows:
                selection.select(
                    self.model.index(rows[path], 0),
                    selection.SelectionFlag.Select | selection.SelectionFlag.Rows,
                )
        row = rows.get(current) if current else None
        if row is not None:
            selection.setCurrentIndex(self.model.index(row, NAME), selection.SelectionFlag.NoUpdate)

    def _show_counts(self) -> None:
        if self.library is None:
            self.status.setText("no library")
            return
        total = count(self.library.connection, Query())
        shown = self.model.rowCount()
        folders = len(self.library.folders())
        where = (
            f"{folders} folder{'s' * (folders != 1)}" if folders else "no folder yet: Add folder... or drop one here"
        )
        shown_text = f"{shown} of {total} takes" if shown != total else f"{total} takes"
        self.status.setText(f"{shown_text} in {where} ({self.library.path.name})")

    def selected_paths(self) -> list[str]:
        rows = sorted({index.row() for index in self.table.selectionModel().selectedRows()})
        return [p for p in (self.model.path_of(r) for r in rows) if p]

    def open_selected(self) -> None:
        """Open the selected take, or the first of two and compare the second with it."""
        paths = self.selected_paths()
        if not paths:
            return
        if len(paths) > 2:
            self.message.emit("Library: select one take to open, or two to compare")
            return
        current = self.model.path_of(self.table.currentIndex().row())
        if len(paths) == 2 and current in paths:  # the one the user is on opens; the other is compared
            paths = [current, *(p for p in paths if p != current)]
        joint_map = self.joint_map_with(self.skeleton_of(paths[0]), paths[1]) if len(paths) == 2 else None
        self.open_requested.emit(paths, joint_map)

    def skeleton_of(self, path: str) -> Skeleton | None:
        """The skeleton the library holds for a file (None: none, or not in the library)."""
        row = row_of_path(self.library.connection, path) if self.library is not None else None
        if row is None or row["skeleton"] is None:
            return None
        return Skeleton(tuple(row["skeleton"]["names"]), tuple(row["skeleton"]["parents"]))

    def joint_map_with(self, skeleton: Skeleton | None, path: str) -> str | None:
        """The shipped joint map to compare the take at ``path`` with a motion of
        ``skeleton`` through (:func:`core.library.skeletons.best_joint_map`), None: by name."""
        other = self.skeleton_of(path)
        return best_joint_map(skeleton, other) if skeleton is not None and other is not None else None

    # --------------------------------------------------------------------- drops
    def dragEnterEvent(self, event: QDragEnterEvent) -> None:  # noqa: N802 (Qt's name)
        if folders_of(event.mimeData()):
            event.acceptProposedAction()

    def dropEvent(self, event: QDropEvent) -> None:  # noqa: N802
        folders = folders_of(event.mimeData())
        if folders:
            self.add_folders(folders)
            event.acceptProposedAction()


def folders_of(mime) -> list[str]:
    """The local folders among dropped URLs."""
    if not mime.hasUrls():
        return []
    paths = [url.toLocalFile() for url in mime.urls() if url.isLocalFile()]
    return [p for p in paths if Path(p).is_dir()]
