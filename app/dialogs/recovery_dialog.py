"""At start: offer to restore or discard the recovery files a crash left behind.

:class:`RecoveryDialog` lists each file (document name, when it was written, how many edits
it holds). *Restore* opens the selected one as the document (it keeps its original file
name and stays modified, so saving asks where); *Discard* deletes the selected ones;
*Later* keeps them for the next start. One document is open at a time, so one file is
restored per start; the others stay listed for the next.
"""

from __future__ import annotations

from pathlib import Path

from PyQt6.QtCore import Qt
from PyQt6.QtWidgets import (
    QDialog,
    QDialogButtonBox,
    QLabel,
    QListWidget,
    QListWidgetItem,
    QPushButton,
    QVBoxLayout,
    QWidget,
)

from gmr_studio.app.model.loading import load_snapshot
from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.app.reliability import recovery
from gmr_studio.app.reliability.autosave import Autosaver


def restore(state: StudioState, autosaver: Autosaver | None, record: recovery.RecoveryRecord) -> None:
    """Open a recovery file as the document: named after its original file, modified, its
    copy kept (and counted) by the autosaver. Raises MotionFileError if it is damaged."""
    snapshot = load_snapshot(record.path)
    motion = snapshot.motion
    kept = tuple(c for c in motion.comments if not c.lstrip("# ").startswith(recovery.MARKER.lstrip("# ").strip()))
    if kept != motion.comments:  # the record line is the recovery file's, not the document's
        held = snapshot.rotations if snapshot.holds_rotations else None
        snapshot = Snapshot(motion.replace(comments=kept), snapshot.positions, held)
    state.open_document(snapshot, record.original)
    state.undo_stack.resetClean()  # not the original file's content: saving is offered
    if autosaver is not None:
        autosaver.adopt(record)
    name = record.display_name
    state.show_message(f"Restored {name} ({record.edits} edits, saved {record.saved_at.replace('T', ' ')})")


class RecoveryDialog(QDialog):
    """Lists recovery files; ``restored`` is the record the user chose to restore, if any."""

    def __init__(self, records: list[recovery.RecoveryRecord], parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setWindowTitle("Recover unsaved work")
        self.records = list(records)
        self.restored: recovery.RecoveryRecord | None = None
        self.discarded: list[recovery.RecoveryRecord] = []
        layout = QVBoxLayout(self)
        layout.addWidget(QLabel("GMR Studio did not close normally. These documents had unsaved edits:", self))
        self.list = QListWidget(self)
        self.list.setSelectionMode(QListWidget.SelectionMode.ExtendedSelection)
        layout.addWidget(self.list)
        buttons = QDialogButtonBox(self)
        self.restore_button = QPushButton("&Restore", self)
        self.discard_button = QPushButton("&Discard", self)
        self.later_button = QPushButton("&Later", self)
        buttons.addButton(self.restore_button, QDialogButtonBox.ButtonRole.AcceptRole)
        buttons.addButton(self.discard_button, QDialogButtonBox.ButtonRole.DestructiveRole)
        buttons.addButton(self.later_button, QDialogButtonBox.ButtonRole.RejectRole)
        layout.addWidget(buttons)
        self.restore_button.clicked.connect(self._on_restore)
        self.discard_button.clicked.connect(self._on_discard)
        self.later_button.clicked.connect(self.reject)
        self.list.itemSelectionChanged.connect(self._on_selection_changed)
        self._fill()
        self.resize(720, 280)

    def _fill(self) -> None:
        self.list.clear()
        for record in self.records:
            item = QListWidgetItem(item_text(record))
            item.setToolTip(str(record.path))
            self.list.addItem(item)
        if self.records:
            self.list.setCurrentRow(0)
        self._on_selection_changed()

    def _selected(self) -> list[recovery.RecoveryRecord]:
        return [self.records[index.row()] for index in self.list.selectedIndexes()]

    def _on_selection_changed(self) -> None:
        selected = self._selected()
        self.restore_button.setEnabled(len(selected) == 1)
        self.discard_button.setEnabled(bool(selected))

    def _on_restore(self) -> None:
        selected = self._selected()
        if len(selected) == 1:
            self.restored = selected[0]
            self.accept()

    def _on_discard(self) -> None:
        for record in self._selected():
            recovery.discard(record)
            self.discarded.append(record)
            self.records.remove(record)
        self._fill()
        if not self.records:
            self.reject()


def item_text(record: recovery.RecoveryRecord) -> str:
    """``01_01.bvh  -  2026-11-23 12:03:11  -  12 edits  (folder)``."""
    plural = "" if record.edits == 1 else "s"
    folder = f"  ({record.original.parent})" if record.original is not None else ""
    when = record.saved_at.replace("T", " ")
    return f"{record.display_name}  \u2014  {when}  \u2014  {record.edits} edit{plural}{folder}"


def offer_recovery(window, folder: Path | None = None) -> bool:
    """Show the dialog if there are recovery files; True if one was restored into ``window``
    (a :class:`~app.main_window.MainWindow`). A damaged file is reported and kept."""
    records = recovery.list_recoveries(folder)
    if not records:
        return False
    dialog = RecoveryDialog(records, window)
    dialog.setWindowModality(Qt.WindowModality.WindowModal)
    dialog.exec()
    if dialog.restored is None:
        return False
    try:
        restore(window.state, window.autosave, dialog.restored)
    except Exception as exc:
        window.files.show_error(exc)
        return False
    return True
