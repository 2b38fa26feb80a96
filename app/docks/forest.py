"""The forest dock: every tree of the skeleton forest, roots marked, soft links shown.

Selecting a row selects the joint in the state; a selection made elsewhere (a click in the
view) selects and reveals the row. The tree is rebuilt after an edit, keeping the selection.
"""

from __future__ import annotations

from PyQt6.QtCore import Qt
from PyQt6.QtGui import QBrush, QColor, QFont, QIcon, QPixmap
from PyQt6.QtWidgets import QMenu, QTreeWidget, QTreeWidgetItem, QWidget

from gmr_studio.app.model.state import StudioState
from gmr_studio.app.model.tree_colors import TreeColors

ROOT_MARK = "\u25c6"  # a diamond before root names
LINK_MARK = "\u21e2"  # a dashed arrow before a soft-link parent


def _swatch(rgb) -> QIcon:
    pixmap = QPixmap(12, 12)
    pixmap.fill(QColor.fromRgbF(*[float(c) for c in rgb]))
    return QIcon(pixmap)


class ForestTree(QTreeWidget):
    """Joints as a tree per root; column 1 shows soft links."""

    def __init__(self, state: StudioState, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.state = state
        self.context_menu: QMenu | None = None
        self.setColumnCount(2)
        self.setHeaderLabels(["Joint", "Soft link"])
        self.setUniformRowHeights(True)
        self.setIndentation(12)
        self.setContextMenuPolicy(Qt.ContextMenuPolicy.CustomContextMenu)
        self.customContextMenuRequested.connect(self._on_context_menu)
        self._items: dict[int, QTreeWidgetItem] = {}
        self.tree_colors = TreeColors()  # the main window hands it the view's, to match
        self._updating = False
        self.itemSelectionChanged.connect(self._on_item_selection_changed)
        state.document_changed.connect(self._on_motion_changed)
        state.motion_changed.connect(self._on_motion_changed)
        state.selection_changed.connect(self._on_selection_changed)

    def item_for(self, joint: int) -> QTreeWidgetItem | None:
        return self._items.get(joint)

    def _on_motion_changed(self) -> None:
        self._updating = True
        self.clear()
        self._items = {}
        snapshot = self.state.snapshot
        if snapshot is not None:
            motion = snapshot.motion
            colors = self.tree_colors.colors(motion)
            bold = QFont(self.font())
            bold.setBold(True)
            for j in motion.topological_order:
                j = int(j)
                parent = int(motion.parents[j])
                name = motion.names[j]
                item = QTreeWidgetItem([f"{ROOT_MARK} {name}" if parent < 0 else name, ""])
                item.setData(0, Qt.ItemDataRole.UserRole, j)
                if parent < 0:
                    item.setFont(0, bold)
                    item.setIcon(0, _swatch(colors[j]))
                    item.setToolTip(0, f"{name}: root of a tree")
                    self.addTopLevelItem(item)
                else:
                    self._items[parent].addChild(item)
                link = int(motion.soft_parents[j])
                if link >= 0:
                    item.setText(1, f"{LINK_MARK} {motion.names[link]}")
                    item.setForeground(1, QBrush(QColor(150, 150, 150)))
                    item.setToolTip(1, f"split from {motion.names[link]}: Join to parent puts it back")
                self._items[j] = item
            self.expandAll()
            self.resizeColumnToContents(0)
            self.resizeColumnToContents(1)
        self._updating = False
        self._on_selection_changed(-1 if self.state.selected is None else self.state.selected)

    def _on_selection_changed(self, joint: int) -> None:
        self._updating = True
        self.clearSelection()
        item = self._items.get(joint)
        if item is not None:
            item.setSelected(True)
            self.setCurrentItem(item)
            self.scrollToItem(item)
        self._updating = False

    def _on_item_selection_changed(self) -> None:
        if self._updating:
            return
        items = self.selectedItems()
        self.state.select(items[0].data(0, Qt.ItemDataRole.UserRole) if items else None)

    def _on_context_menu(self, point) -> None:
        item = self.itemAt(point)
        if item is not None:
            self.state.select(item.data(0, Qt.ItemDataRole.UserRole))
        if self.context_menu is not None:
            self.context_menu.popup(self.viewport().mapToGlobal(point))
