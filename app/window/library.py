"""The Library panel wired into the window: its dock, its menu entries, opening and
comparing takes through the window's own paths, and drops.

:func:`install_library` adds the Library dock to the analysis area (hidden until View >
Library, Ctrl+Shift+L, or File > Add folder to library...), opens the library the first
time the dock is shown (so a window that never shows it makes no file), and routes the
panel's requests: a take opens through :meth:`~app.window.files.FileController.open_path`
(unsaved edits asked about first), a second one is compared with it
(:meth:`~app.window.files.FileController.compare_path`, a comparison layer). :class:`LibraryDrops`
takes what is dropped on the window: takes dragged from the table become comparison layers
(through the joint map that pairs their joints with the document's best; with no document
they open), folders are indexed into the library.
"""

from __future__ import annotations

from PyQt6.QtCore import Qt
from PyQt6.QtGui import QAction, QDropEvent
from PyQt6.QtWidgets import QDockWidget

from gmr_studio.app.library.panel import LibraryPanel, folders_of
from gmr_studio.app.library.table_model import TAKE_MIME
from gmr_studio.core.library.skeletons import Skeleton

#: the dock's height when it is first shown (pixels): a few rows of thumbnails
DOCK_HEIGHT = 330


def install_library(window) -> QDockWidget:
    """The Library dock (returned, hidden) in ``window``'s analysis area, File > Add folder
    to library... and View > Library."""
    panel = LibraryPanel(window.settings)
    window.library_panel = panel
    dock = window._dock("Library", panel, Qt.DockWidgetArea.BottomDockWidgetArea)
    window.splitDockWidget(window.curves_dock, dock, Qt.Orientation.Horizontal)  # the analysis area
    dock.hide()
    toggle = dock.toggleViewAction()
    toggle.setShortcut("Ctrl+Shift+L")
    toggle.setStatusTip("The takes of the library's folders: find, see and open them")
    window.addAction(toggle)

    def shown(visible: bool) -> None:
        if visible and panel.library is None:
            panel.open_library()
        if visible and dock.height() < DOCK_HEIGHT and not dock.isFloating():
            window.resizeDocks([dock], [DOCK_HEIGHT], Qt.Orientation.Vertical)

    dock.visibilityChanged.connect(shown)
    add = QAction("Add folder to &library...", window)
    add.setStatusTip("Index a folder of takes into the library (View > Library)")
    add.triggered.connect(lambda: (show(dock), panel.add_folder_dialog()))
    file_menu = window.menuBar().actions()[0].menu()
    file_menu.insertAction(file_menu.actions()[3], add)  # after Open, Open recent and Compare with
    window.add_to_library_action = add
    panel.open_requested.connect(lambda paths, joint_map: open_takes(window, paths, joint_map))
    panel.message.connect(window.state.show_message)
    window.library_drops = LibraryDrops(window, dock, panel)
    return dock


def show(dock: QDockWidget) -> None:
    dock.show()
    dock.raise_()


def open_takes(window, paths: list[str], joint_map: str | None = None) -> None:
    """Open ``paths[0]`` as the document the way File > Open does (unsaved edits asked
    about; a refusal leaves everything as it was) and compare ``paths[1]``, if given, with it
    through ``joint_map``."""
    files = window.files
    if not paths or not files.maybe_save():
        return
    if len(paths) > 1:

        def then(ok: bool) -> None:
            files.load_finished.disconnect(then)
            if ok:
                files.compare_path(paths[1], joint_map=joint_map)

        files.load_finished.connect(then)
    files.open_path(paths[0], ask=False)


class LibraryDrops:
    """What the window does with drops that are the library's (see the module docstring)."""

    def __init__(self, window, dock: QDockWidget, panel: LibraryPanel) -> None:
        self.window, self.dock, self.panel = window, dock, panel

    def drop(self, event: QDropEvent) -> bool:
        """Take the drop if it is takes from the table or folders; True if taken."""
        mime = event.mimeData()
        if mime.hasFormat(TAKE_MIME):
            paths = [p for p in bytes(mime.data(TAKE_MIME)).decode("utf-8").splitlines() if p]
            motion = self.window.state.motion
            if motion is None:
                first = self.panel.skeleton_of(paths[0])
                open_takes(self.window, paths[:2], self.panel.joint_map_with(first, paths[1]) if paths[1:] else None)
            else:
                document = Skeleton.of(motion)
                for path in paths:
                    self.window.files.compare_path(path, joint_map=self.panel.joint_map_with(document, path))
            event.acceptProposedAction()
            return True
        folders = folders_of(mime)
        if folders:
            show(self.dock)
            self.panel.add_folders(folders)
            event.acceptProposedAction()
            return True
        return False
