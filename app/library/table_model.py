"""The Library panel's table over the library's SQLite file, holding only what is in view.

:class:`LibraryModel` counts the rows its query lets through and reads their ids a block at
a time as the view scrolls to them (:data:`core.library.query.ID_BLOCK` ids in the query's
order, the last :data:`BLOCKS_KEPT` blocks kept), then the rows themselves a page at a time
(:data:`PAGE_ROWS` rows, the last :data:`PAGES_KEPT` pages kept): a query is answered by its
count and its first block, whatever the size of the library. Thumbnails are read and
decoded (and scaled to :attr:`LibraryModel.thumbnail_height`) after the view has asked for
them, a batch at a time on the next turn of the event loop, so that scrolling never waits
for a picture; the last :data:`THUMBNAILS_KEPT` stay.
Sorting a column asks the file again (its indexes sort); rows are dragged out as their files
(``text/uri-list``) and as :data:`TAKE_MIME` (the window adds a dropped take as a comparison
layer).
"""

from __future__ import annotations

import sqlite3
from collections import OrderedDict

import numpy as np
from PyQt6.QtCore import QAbstractTableModel, QMimeData, QModelIndex, Qt, QTimer, QUrl
from PyQt6.QtGui import QBrush, QColor, QImage, QPixmap

from gmr_studio.app.model.problems import LEVEL_COLOURS
from gmr_studio.core.library.query import ID_BLOCK, Query, first_ids, positions, rows_by_id, select_ids
from gmr_studio.core.library.thumbnails import SIZE

#: (title, sort field) of each column; the thumbnail's column sorts by path
COLUMNS = (
    ("", "path"),
    ("Name", "name"),
    ("Format", "format"),
    ("Duration", "duration"),
    ("Frames", "frames"),
    ("Rate", "rate"),
    ("Joints", "joints"),
    ("Group", "group"),
    ("Problems", "problems"),
)
THUMBNAIL, NAME, FORMAT, DURATION, FRAMES, RATE, JOINTS, GROUP, PROBLEMS = range(len(COLUMNS))
_NUMBER_COLUMNS = (DURATION, FRAMES, RATE, JOINTS, GROUP)
#: blocks of ids kept (:data:`core.library.query.ID_BLOCK` ids a block)
BLOCKS_KEPT = 16
PAGE_ROWS = 64
PAGES_KEPT = 16
THUMBNAILS_KEPT = 400
#: the MIME type of takes dragged out of the table: their paths, one a line
TAKE_MIME = "application/x-gmr-library-takes"
PATH_ROLE = Qt.ItemDataRole.UserRole + 1
ROW_ROLE = Qt.ItemDataRole.UserRole + 2
# the roles as plain numbers: the view asks for every role of every cell it paints, by number
_DISPLAY, _DECORATION = int(Qt.ItemDataRole.DisplayRole), int(Qt.ItemDataRole.DecorationRole)
_FOREGROUND, _ALIGNMENT, _TOOLTIP = (
    int(Qt.ItemDataRole.ForegroundRole),
    int(Qt.ItemDataRole.TextAlignmentRole),
    int(Qt.ItemDataRole.ToolTipRole),
)
_PATH, _ROW = int(PATH_ROLE), int(ROW_ROLE)
_ROLES = frozenset((_DISPLAY, _DECORATION, _FOREGROUND, _ALIGNMENT, _TOOLTIP, _PATH, _ROW))
_FLAGS = Qt.ItemFlag.ItemIsEnabled | Qt.ItemFlag.ItemIsSelectable | Qt.ItemFlag.ItemIsDragEnabled
_RIGHT = int(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)


def problems_text(quality: dict | None) -> str:
    """``2 errors, 5 warnings, 1 info`` or ``none`` (``--`` for a file not read)."""
    if not quality:
        return "--"
    parts = [
        f"{quality[s]} {s}{'s' if quality[s] != 1 and s != 'info' else ''}"
        for s in ("error", "warning", "info")
        if quality[s]
    ]
    return ", ".join(parts) if parts else "none"


class LibraryModel(QAbstractTableModel):
    """The rows of a library that a :class:`~core.library.query.Query` lets through."""

    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self.connection: sqlite3.Connection | None = None
        self.query = Query()
        self.total = 0  # rows the query lets through
        self.id_block = ID_BLOCK  # ids read at a time: a whole number of pages
        self._blocks: OrderedDict[int, np.ndarray] = OrderedDict()  # block -> its ids
        self.thumbnail_height = SIZE[1]  # pixels: the thumbnails scaled to this height when read
        # page -> (row, its cells' texts, their brushes) of each row of the page (None: gone)
        self._pages: OrderedDict[int, list[tuple[dict, tuple, tuple] | None]] = OrderedDict()
        self._last: tuple[int, list] = (-1, [])  # the page asked for last
        self._pictures: OrderedDict[int, QPixmap | None] = OrderedDict()
        self._wanted: dict[int, int] = {}  # id -> row of thumbnails asked for, not yet read
        self._loader = QTimer(self, singleShot=True, interval=0)
        self._loader.timeout.connect(self._load_thumbnails)

    # ------------------------------------------------------------------ contents
    def set_connection(self, connection: sqlite3.Connection | None) -> None:
        """Show another library (None: none)."""
        self.connection = connection
        self._pictures.clear()
        self.refresh()

    def set_query(self, query: Query) -> None:
        self.query = query
        self.refresh()

    def refresh(self) -> None:
        """Ask the file again (rows added, changed or gone), keeping the query."""
        self.beginResetModel()
        self._blocks.clear()
        self.total = 0
        if self.connection is not None:
            self.total, self._blocks[0] = first_ids(self.connection, self.query, self.id_block)
        self._pages.clear()
        self._last = (-1, [])
        self._wanted.clear()
        self.endResetModel()

    def forget_thumbnails(self) -> None:
        """Read the thumbnails again when next shown (files indexed again)."""
        self._pictures.clear()

    def row_of(self, row: int) -> dict | None:
        """The JSON row (:func:`core.library.query.row_json`) shown at ``row``."""
        entry = self._entry(row)
        return entry[0] if entry is not None else None

    def _entry(self, row: int) -> tuple[dict, tuple, tuple] | None:
        """(JSON row, its cells' texts, their brushes) shown at ``row``, its page read when
        not in hand."""
        if not 0 <= row < self.total:
            return None
        page = row // PAGE_ROWS
        if page == self._last[0]:
            entries = self._last[1]
            return entries[row - page * PAGE_ROWS] if row - page * PAGE_ROWS < len(entries) else None
        entries = self._pages.get(page)
        if entries is None:
            block, start = divmod(page * PAGE_ROWS, self.id_block)
            ids = self._ids_of_block(block)[start : start + PAGE_ROWS]
            found = rows_by_id(self.connection, ids.tolist()) if self.connection is not None else {}
            entries = [_cells(found[int(i)]) if int(i) in found else None for i in ids]
            self._pages[page] = entries
            while len(self._pages) > PAGES_KEPT:
                self._pages.popitem(last=False)
        else:
            self._pages.move_to_end(page)
        self._last = (page, entries)
        return entries[row - page * PAGE_ROWS] if row - page * PAGE_ROWS < len(entries) else None

    def _ids_of_block(self, block: int) -> np.ndarray:
        """The ids of the rows of ``block`` (fewer when rows went since the count)."""
        ids = self._blocks.get(block)
        if ids is None:
            if self.connection is None:
                return np.zeros(0, np.int64)
            ids = select_ids(self.connection, self.query, limit=self.id_block, offset=block * self.id_block)
            self._blocks[block] = ids
            while len(self._blocks) > BLOCKS_KEPT:
                self._blocks.popitem(last=False)
        else:
            self._blocks.move_to_end(block)
        return ids

    def path_of(self, row: int) -> str | None:
        found = self.row_of(row)
        return found["path"] if found else None

    def row_with_path(self, path: str) -> int | None:
        """The row showing the file at ``path`` (None when the query leaves it out)."""
        if self.connection is None:
            return None
        return self.rows_with_paths([path]).get(path)

    def rows_with_paths(self, paths: list[str]) -> dict[str, int]:
        """path -> the row showing it, of the ``paths`` the query lets through (found in the
        blocks of ids in hand, else asked of the file at once)."""
        if self.connection is None or not paths:
            return {}
        id_of = {}
        for start in range(0, len(paths), 500):  # within SQLite's count of parameters a statement
            chunk = paths[start : start + 500]
            marks = ", ".join("?" * len(chunk))
            id_of.update(self.connection.execute(f"SELECT path, id FROM files WHERE path IN ({marks})", chunk))
        rows, missing = {}, []
        for path, file_id in id_of.items():
            for block, ids in self._blocks.items():
                found = np.flatnonzero(ids == file_id)
                if found.size:
                    rows[path] = block * self.id_block + int(found[0])
                    break
            else:
                missing.append((path, file_id))
        if missing:
            places = positions(self.connection, self.query, [file_id for _, file_id in missing])
            rows.update({path: places[file_id] for path, file_id in missing if file_id in places})
        return rows

    # ------------------------------------------------------------ Qt's model API
    def rowCount(self, parent: QModelIndex = QModelIndex()) -> int:  # noqa: N802, B008 (Qt's signature)
        return 0 if parent.isValid() else self.total

    def columnCount(self, parent: QModelIndex = QModelIndex()) -> int:  # noqa: N802, B008
        return 0 if parent.isValid() else len(COLUMNS)

    def headerData(self, section: int, orientation: Qt.Orientation, role: int = Qt.ItemDataRole.DisplayRole):  # noqa: N802
        if role == _DISPLAY and orientation == Qt.Orientation.Horizontal:
            return COLUMNS[section][0]
        return None

    def flags(self, index: QModelIndex) -> Qt.ItemFlag:
        return _FLAGS if index.isValid() else Qt.ItemFlag.NoItemFlags

    def data(self, index: QModelIndex, role: int = Qt.ItemDataRole.DisplayRole):
        if role not in _ROLES or not index.isValid():  # the view asks for many roles a cell: most are none
            return None
        entry = self._entry(index.row())
        if entry is None:
            return None
        row, texts, brushes = entry
        column = index.column()
        if role == _DISPLAY:
            return texts[column]
        if role == _DECORATION:
            return self._thumbnail(row, index.row()) if column == THUMBNAIL else None
        if role == _FOREGROUND:
            return brushes[column]
        if role == _ALIGNMENT:
            return _RIGHT if column in _NUMBER_COLUMNS else None
        if role == _TOOLTIP:
            return _tooltip(row, column)
        if role == _PATH:
            return row["path"]
        return row  # ROW_ROLE

    def sort(self, column: int, order: Qt.SortOrder = Qt.SortOrder.AscendingOrder) -> None:
        from dataclasses import replace

        descending = order == Qt.SortOrder.DescendingOrder
        self.set_query(replace(self.query, sort=COLUMNS[column][1], descending=descending))

    def mimeTypes(self) -> list[str]:  # noqa: N802
        return [TAKE_MIME, "text/uri-list"]

    def mimeData(self, indexes) -> QMimeData:  # noqa: N802
        rows = sorted({i.row() for i in indexes})
        paths = [p for p in (self.path_of(r) for r in rows) if p]
        mime = QMimeData()
        mime.setData(TAKE_MIME, "\n".join(paths).encode("utf-8"))
        mime.setUrls([QUrl.fromLocalFile(p) for p in paths])
        return mime

    def supportedDragActions(self) -> Qt.DropAction:  # noqa: N802
        return Qt.DropAction.CopyAction

    # ---------------------------------------------------------------- thumbnails
    def _thumbnail(self, row: dict, index: int):
        file_id = row["id"]
        if file_id in self._pictures:
            self._pictures.move_to_end(file_id)
            return self._pictures[file_id]
        if row["thumbnail"]:
            self._wanted[file_id] = index
            self._loader.start()
        return None

    def _load_thumbnails(self) -> None:
        """Read and decode the thumbnails the view asked for, then tell it."""
        wanted, self._wanted = self._wanted, {}
        if not wanted or self.connection is None:
            return
        marks = ", ".join(str(int(i)) for i in wanted)
        found = dict(self.connection.execute(f"SELECT file_id, png FROM thumbnails WHERE file_id IN ({marks})"))
        for file_id in wanted:
            data = found.get(file_id)
            picture = None
            if data is not None:
                image = QImage.fromData(bytes(data), "PNG")
                if image.height() != self.thumbnail_height:
                    image = image.scaledToHeight(self.thumbnail_height, Qt.TransformationMode.SmoothTransformation)
                picture = QPixmap.fromImage(image)
            self._pictures[file_id] = picture
        while len(self._pictures) > THUMBNAILS_KEPT:
            self._pictures.popitem(last=False)
        rows = [r for r in wanted.values() if r < self.total]
        if rows:
            self.dataChanged.emit(
                self.index(min(rows), THUMBNAIL), self.index(max(rows), THUMBNAIL), [Qt.ItemDataRole.DecorationRole]
            )


_LEVEL_BRUSHES = {s: QBrush(QColor.fromRgbF(*LEVEL_COLOURS[k + 1])) for k, s in enumerate(("info", "warning", "error"))}
_FAILED_BRUSH = _LEVEL_BRUSHES["error"]


def thumbnail_size() -> tuple[int, int]:
    """(width, height) pixels of a thumbnail as the library stores them."""
    return SIZE


def _cells(row: dict) -> tuple[dict, tuple, tuple]:
    """(row, the texts of its cells, their brushes (None: the view's own colour))."""
    texts = tuple(_cell_text(row, column) for column in range(len(COLUMNS)))
    if row["status"] != "ok":
        brushes = tuple(_FAILED_BRUSH if column in (NAME, PROBLEMS) else None for column in range(len(COLUMNS)))
    else:
        worst = row["quality"]["worst"] if row["quality"] else None
        brushes = tuple(
            _LEVEL_BRUSHES[worst] if worst and column == PROBLEMS else None for column in range(len(COLUMNS))
        )
    return row, texts, brushes


def _cell_text(row: dict, column: int) -> str | None:
    ok = row["status"] == "ok"
    if column == NAME:
        return row["name"]
    if column == FORMAT:
        return row["format"]
    if column == PROBLEMS:
        return problems_text(row["quality"]) if ok else f"cannot be read: {row['message']}"
    if not ok:
        return ""
    if column == DURATION:
        return f"{row['duration']:.2f} s"
    if column == FRAMES:
        return f"{row['frames']}"
    if column == RATE:
        return f"{row['frame_rate']:.4g} Hz"
    if column == JOINTS:
        return f"{row['joints']}" if row["joints"] is not None else f"{row['markers']} markers"
    if column == GROUP:
        return f"{row['skeleton']['group']}" if row["skeleton"] else ""
    return None


def _tooltip(row: dict, column: int) -> str:
    if row["status"] != "ok":
        return row["message"] or ""
    if column == PROBLEMS and row["quality"] and row["quality"]["kinds"]:
        lines = [
            f"{kind}: {', '.join(f'{n} {s}' for s, n in counts.items())}"
            for kind, counts in row["quality"]["kinds"].items()
        ]
        lines.append(f"worst at frame {row['quality']['worst_frame']}")
        return "\n".join(lines)
    if column == GROUP and row["skeleton"]:
        return f"skeleton group {row['skeleton']['group']} (match {row['skeleton']['group_match']:.2f})"
    return row["path"]
