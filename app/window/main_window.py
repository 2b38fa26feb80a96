"""The main window, the app's composition root: it makes the state, the view and every
dock, menu and drawable, lays them out (:mod:`app.window.layout`) and wires them. Nothing
else in the app adds a dock, a menu or a drawable to the window. No math here."""

from __future__ import annotations

from pathlib import Path

from PyQt6.QtCore import QCoreApplication, QEvent, QSettings, Qt, QTimer
from PyQt6.QtGui import QCloseEvent, QDragEnterEvent, QDropEvent
from PyQt6.QtWidgets import QDockWidget, QLabel, QMainWindow, QMenu, QMessageBox, QUndoView, QWidget

from gmr_studio.app.dialogs.alignment_dialog import AlignmentDialog
from gmr_studio.app.dialogs.audit_dialog import AuditDialog
from gmr_studio.app.docks.contact_bars import ContactBars
from gmr_studio.app.docks.curves_dock import CurvesDock
from gmr_studio.app.docks.forest import ForestTree
from gmr_studio.app.docks.inspector import Inspector
from gmr_studio.app.docks.timeline import Timeline
from gmr_studio.app.model import commands, loading, marker_document, pelvis_recovery
from gmr_studio.app.model.playback import SPEEDS, Player
from gmr_studio.app.model.problems import Problems
from gmr_studio.app.model.state import StudioState
from gmr_studio.app.reliability.autosave import Autosaver
from gmr_studio.app.scene.view import SkeletonView
from gmr_studio.app.window import actions as action_table
from gmr_studio.app.window import layout
from gmr_studio.app.window.checks import install_problems
from gmr_studio.app.window.classroom import Classroom
from gmr_studio.app.window.comparison import install_comparison
from gmr_studio.app.window.exports import Exports
from gmr_studio.app.window.files import FileController
from gmr_studio.app.window.library import install_library
from gmr_studio.app.window.onion_menu import OnionMenu

KEYS_HELP = """<table>
<tr><td><b>Space</b></td><td>play / pause</td></tr>
<tr><td><b>Left / Right</b></td><td>previous / next frame (Shift: one second)</td></tr>
<tr><td><b>Home / End</b></td><td>first / last frame</td></tr>
<tr><td><b>[ / ]</b></td><td>slower / faster (0.25x to 4x)</td></tr>
<tr><td><b>Shift+O</b></td><td>onion skin: ghost poses around the current frame</td></tr>
<tr><td><b>I / O</b></td><td>frame range start / end here (Shift+drag on the slider: a range)</td></tr>
<tr><td><b>Click</b></td><td>select a joint (or a marker); right click: joint menu</td></tr>
<tr><td><b>Drag</b></td><td>turn the camera (Shift: pan, wheel or right drag: zoom)</td></tr>
<tr><td><b>Ctrl+R / Ctrl+T / Ctrl+J</b></td><td>shift root / split here / join to parent</td></tr>
<tr><td><b>Ctrl+Z / Ctrl+Shift+Z</b></td><td>undo / redo</td></tr>
<tr><td><b>G K A T L M B P</b></td><td>ground, soft links, axes, trail, labels, markers, marker labels, pelvis</td></tr>
</table>"""

DOCK_MINIMUM = layout.DOCK_MINIMUM
VIEW_MINIMUM = layout.VIEW_MINIMUM
SLIDER_MINIMUM = layout.SLIDER_MINIMUM


def default_settings() -> QSettings:
    return QSettings(QSettings.Format.IniFormat, QSettings.Scope.UserScope, "gmr-studio", "gmr-studio")


class MainWindow(QMainWindow):
    """GMR Studio's window: 3D view in the centre; forest, inspector, timeline, history docks."""

    def __init__(self, settings: QSettings | None = None, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.settings = settings if settings is not None else default_settings()
        self.state = StudioState(self)
        self.player = Player(self.state, self)
        self.problems = Problems(self.state, self.settings, self)  # the quality checks, remembered settings
        self.view = SkeletonView(self.state, self)
        self.setCentralWidget(self.view)
        self.files = FileController(self.state, lambda: self.view.scene, self.settings, self)
        self.exports = Exports(self.files)
        self.autosave = Autosaver(self.state, self)  # a recovery copy of unsaved edits
        self.setAcceptDrops(True)
        self.actions = action_table.build_actions(self, self._handlers(), self.state.undo_stack)
        self.actions["play"].setShortcutContext(Qt.ShortcutContext.WindowShortcut)
        self.recent_menu = QMenu("Open &recent", self)
        self.history = QUndoView(self.state.undo_stack)
        self.history.setEmptyLabel("<opened>")
        self.history_dock = self._dock("History", self.history, Qt.DockWidgetArea.RightDockWidgetArea)
        self.history_dock.hide()
        toggle = self.history_dock.toggleViewAction()
        toggle.setText("&History")
        toggle.setShortcut("Ctrl+H")
        self.joint_menu = action_table.fill_menus(self, self.actions, self.recent_menu, toggle)
        self.audit_action = self._add_audit_menu()
        self.forest = ForestTree(self.state)
        self.forest.tree_colors = self.view.scene.tree_colors  # one colour per tree in both
        self.inspector = Inspector(self.state)
        self.timeline = Timeline(self.state, self.player, self.actions, self.problems)
        self.forest.context_menu = self.view.context_menu = self.joint_menu
        # beside the view: Forest above Inspector in one column (layout.side_width wide)
        right = Qt.DockWidgetArea.RightDockWidgetArea
        self.forest_dock = self._dock("Forest", self.forest, right)
        self.inspector_dock = self._dock("Inspector", self.inspector, right)
        self.splitDockWidget(self.forest_dock, self.inspector_dock, Qt.Orientation.Vertical)
        self.tabifyDockWidget(self.inspector_dock, self.history_dock)
        self.inspector_dock.raise_()
        # under it: the timeline strip, and the analysis tabs shown when asked (View menu)
        bottom = Qt.DockWidgetArea.BottomDockWidgetArea
        self.timeline_dock = self._dock("Timeline", self.timeline, bottom)
        layout.make_strip(self.timeline_dock)
        self.contact_bars = ContactBars(self.state)
        self.curves = CurvesDock(self.state, self.player)
        self.curves_dock = self._dock("Curves", self.curves, bottom)
        self.contacts_dock = self._dock("Foot contacts", self.contact_bars, bottom)
        self.splitDockWidget(self.curves_dock, self.timeline_dock, Qt.Orientation.Vertical)
        self.splitDockWidget(self.curves_dock, self.contacts_dock, Qt.Orientation.Horizontal)
        for dock in (self.curves_dock, self.contacts_dock):
            dock.hide()
        self.view.setMinimumSize(*VIEW_MINIMUM)
        for dock in (self.forest_dock, self.inspector_dock):  # they may give way to the view
            dock.widget().setMinimumWidth(DOCK_MINIMUM)
        self.timeline.slider.setMinimumWidth(SLIDER_MINIMUM)  # never squeezed into a square
        self._fit_pending = QTimer(self, singleShot=True, interval=0)
        self._fit_pending.timeout.connect(self.fit_docks)
        self.classroom = Classroom(self, self.state, self.view.scene, beside=self.inspector_dock)
        self.view_menu.addAction(self.classroom.dock.toggleViewAction())
        self.layers, self.ghosts, self.layers_panel, self.error_dock = install_comparison(
            self, self.state, self.view.scene, self.files, beside=self.forest_dock
        )
        self.onion = OnionMenu(self, self.view.scene, self.layers, self.view_menu)
        self.inspector.sections.append(  # a joint of a skeleton built from markers: how it was placed
            lambda frame, joint: marker_document.joint_section(self.files.marker_document, self.state, frame, joint)
        )
        self.problems_dock = install_problems(self, self.problems, self.view.scene)
        self.library_dock = install_library(self)  # the takes of the library's folders
        self.analysis_docks = [
            self.curves_dock,
            self.contacts_dock,
            self.error_dock,
            self.problems_dock,
            self.library_dock,
        ]
        layout.tab_when_shown(self, self.analysis_docks)
        self.status = QLabel()
        self.statusBar().addWidget(self.status, 1)
        self._wire()
        self._restore_settings()
        self._on_path_changed("")

    # ------------------------------------------------------------------ layout
    def fit_docks(self) -> None:
        """Keep the view its share of the window (:func:`app.window.layout.fit_docks`)."""
        side = [self.forest_dock, self.inspector_dock, self.classroom.dock]
        layout.fit_docks(self, self.view, side, self.analysis_docks)

    def default_layout(self) -> None:
        """The side column at its width for this window (the rest is set up in ``__init__``)."""
        width = layout.side_width(self.width())
        self.resizeDocks([self.forest_dock, self.inspector_dock], [width, width], Qt.Orientation.Horizontal)
        self.resizeDocks([self.forest_dock, self.inspector_dock], [1, 2], Qt.Orientation.Vertical)
        heights = [layout.BOTTOM_HEIGHT] * len(self.analysis_docks)
        self.resizeDocks(self.analysis_docks, heights, Qt.Orientation.Vertical)

    def showEvent(self, event) -> None:  # noqa: N802 (Qt's name)
        super().showEvent(event)
        if not self._laid_out:
            self._laid_out = True
            if not self._restored:
                self.default_layout()
            self._fit_pending.start()

    def resizeEvent(self, event) -> None:  # noqa: N802 (Qt's name)
        super().resizeEvent(event)
        self._fit_pending.start()  # once the layout has settled at the new size

    def _add_audit_menu(self):
        """Tools > Audit round trips... (before Help): the audit dialog, its failing joints
        ringed in the view."""
        bar = self.menuBar()
        help_action = next((a for a in bar.actions() if a.text().replace("&", "") == "Help"), None)
        tools = bar.addMenu("&Tools")
        if help_action is not None:
            bar.insertMenu(help_action, tools)
        action = tools.addAction("&Audit round trips...")
        action.setStatusTip("run the document through every conversion and edit and check that no joint moves")

        def show() -> None:
            dialog = AuditDialog(self.state, self, scene=self.view.scene)
            dialog.setAttribute(Qt.WidgetAttribute.WA_DeleteOnClose)
            self.audit_dialog = dialog
            dialog.show()
            dialog.run_audit()

        action.triggered.connect(show)
        return action

    def _dock(self, title: str, widget: QWidget, area: Qt.DockWidgetArea) -> QDockWidget:
        dock = QDockWidget(title, self)
        dock.setObjectName(title.lower())
        dock.setWidget(widget)
        self.addDockWidget(area, dock)
        if hasattr(self, "view_menu"):
            self.view_menu.addAction(dock.toggleViewAction())
        return dock

    def _handlers(self) -> dict:
        state, player, files = self.state, self.player, self.files
        handlers = {
            "open": files.open_dialog,
            "add_markers": files.add_markers_dialog,
            "align_markers": self._align_markers,
            "remove_markers": lambda: state.set_markers(None),
            "recover_pelvis": self._recover_pelvis,
            "build_skeleton": files.build_skeleton,
            "refine_markers": files.set_refine_markers,
            "save": files.save,
            "save_as": files.save_as,
            "export_bvh": self.exports.export_bvh_dialog,
            "export_gltf": self.exports.export_gltf_dialog,
            "body_model": files.choose_body_model,
            "screenshot": self.exports.save_screenshot_dialog,
            "export_video": lambda: self.exports.export_video_dialog(player.speed),
            "quit": self.close,
            "shift_root": lambda: commands.shift_root_to(state, state.selected),
            "split": lambda: commands.split_here(state, state.selected),
            "join": lambda: commands.join_to_parent(state, state.selected),
            "split_all": lambda: commands.split_everything(state),
            "join_all": lambda: commands.join_everything(state),
            "remove_dummies": lambda: commands.remove_dummy_joints(state),
            "play": player.toggle,
            "step_back": lambda: (player.pause(), state.step(-1)),
            "step_forward": lambda: (player.pause(), state.step(1)),
            "back_second": lambda: state.step(-self._second()),
            "forward_second": lambda: state.step(self._second()),
            "first_frame": lambda: state.set_frame(0),
            "last_frame": lambda: state.set_frame(state.n_frames - 1),
            "loop": player.set_loop,
            "slower": lambda: player.set_speed(_next_speed(player.speed, -1)),
            "faster": lambda: player.set_speed(_next_speed(player.speed, 1)),
            "reset_camera": lambda: self.view.scene.reset_camera(),
            "about": self._about,
            "keys": lambda: QMessageBox.information(self, "Keyboard shortcuts", KEYS_HELP),
        }
        handlers.update(action_table.clip_handlers(self, state))
        for name in state.overlays:
            handlers[f"overlay_{name}"] = lambda shown, name=name: state.set_overlay(name, shown)
        return handlers

    def _second(self) -> int:
        return max(1, round(self.state.motion.frame_rate)) if self.state.motion else 1

    def _wire(self) -> None:
        state = self.state
        state.message.connect(self.status.setText)
        state.path_changed.connect(self._on_path_changed)
        state.modified_changed.connect(self.setWindowModified)
        for signal in (
            state.document_changed,
            state.motion_changed,
            state.selection_changed,
            state.markers_changed,
            state.pelvis_changed,
            state.range_changed,
        ):
            signal.connect(self._on_enabled_changed)
        self.player.playing_changed.connect(self._on_playing_changed)
        self.player.loop_changed.connect(self.actions["loop"].setChecked)
        self.files.recent_changed.connect(self._on_recent_changed)
        for name, shown in state.overlays.items():
            self.actions[f"overlay_{name}"].setChecked(shown)
        state.overlay_changed.connect(self._on_overlay_changed)
        self.actions["loop"].setChecked(self.player.loop)
        self.actions["refine_markers"].setChecked(self.files.refine_markers())
        self._on_recent_changed(self.files.recent_files())
        self._on_enabled_changed()

    # ----------------------------------------------------------------- handlers
    def _on_path_changed(self, path: str) -> None:
        name = Path(path).name if path else ("demo" if self.state.motion is not None else "no motion")
        self.setWindowTitle(f"{name}[*] \u2014 GMR Studio")
        self.setWindowModified(self.state.modified)

    def _on_overlay_changed(self, name: str, shown: bool) -> None:
        action = self.actions[f"overlay_{name}"]
        action_table.show_overlay_switch(action, shown, action.isEnabled())

    def _on_enabled_changed(self, *_args) -> None:
        action_table.update_enabled(self.actions, self.state)

    def _on_playing_changed(self, playing: bool) -> None:
        icon = "SP_MediaPause" if playing else "SP_MediaPlay"
        from PyQt6.QtWidgets import QStyle

        self.actions["play"].setIcon(self.style().standardIcon(getattr(QStyle.StandardPixmap, icon)))
        self.actions["play"].setText("&Pause" if playing else "&Play")

    def _on_recent_changed(self, paths: list) -> None:
        self.recent_menu.clear()
        for path in paths:
            self.recent_menu.addAction(Path(path).name, lambda p=path: self.files.open_path(p)).setStatusTip(path)
        self.recent_menu.addSeparator()
        self.recent_menu.addAction("Clear the list", self.files.clear_recent)
        self.recent_menu.setEnabled(bool(paths))

    def _align_markers(self) -> None:
        AlignmentDialog(self.state, self, self.view.scene).exec()

    def _recover_pelvis(self) -> None:
        pelvis_recovery.recover_pelvis_frames(self.state)

    def _about(self) -> None:
        QMessageBox.about(
            self,
            "About GMR Studio",
            "<b>GMR Studio</b><br/>Look at, edit and convert skeletal motion in the General Motion "
            "Representation: shift root, split and join trees, with undo.",
        )

    # ------------------------------------------------------------ drops, settings, close
    def dragEnterEvent(self, event: QDragEnterEvent) -> None:  # noqa: N802
        if event.mimeData().hasUrls():
            event.acceptProposedAction()

    def dropEvent(self, event: QDropEvent) -> None:  # noqa: N802
        if self.library_drops.drop(event):  # takes from the Library panel, folders for it
            return
        paths = [url.toLocalFile() for url in event.mimeData().urls() if url.isLocalFile()]
        motions = [p for p in paths if Path(p).suffix.lower() in loading.motion_suffixes()]
        markers = [p for p in paths if Path(p).suffix.lower() in loading.marker_suffixes()]
        shift = bool(event.modifiers() & Qt.KeyboardModifier.ShiftModifier)
        if (motions or markers) and shift and self.state.motion is not None:
            self.files.compare_path((motions or markers)[0])  # Shift: add as a comparison layer
        elif motions:
            self.files.open_path(motions[0], markers=markers[0] if markers else None)
        elif markers and self.state.motion is not None and not self._built_from_markers():
            self.files.add_markers_path(markers[0])
        elif markers:  # alone: the skeleton built from the markers becomes the document
            self.files.open_path(markers[0])
        event.acceptProposedAction()

    def _built_from_markers(self) -> bool:
        """The document was opened from a marker file (its skeleton built from the markers)."""
        path = self.state.path
        return path is not None and path.suffix.lower() in loading.marker_suffixes()

    def _restore_settings(self) -> None:
        geometry = self.settings.value("window/geometry")
        if geometry is not None:
            self.restoreGeometry(geometry)
        else:
            self.resize(1400, 900)
        self._restored = layout.restore_layout(self, self.settings)  # an older one: the default
        self._laid_out = False
        for name in self.state.overlays:
            value = self.settings.value(f"overlays/{name}")
            if value is not None:
                self.state.set_overlay(name, str(value).lower() == "true")
        speed = self.settings.value("playback/speed")
        if speed is not None:
            self.player.set_speed(float(speed))
        loop = self.settings.value("playback/loop")
        if loop is not None:
            self.player.set_loop(str(loop).lower() == "true")

    def _save_settings(self) -> None:
        self.settings.setValue("window/geometry", self.saveGeometry())
        layout.save_layout(self, self.settings)
        for name, shown in self.state.overlays.items():
            self.settings.setValue(f"overlays/{name}", shown)
        self.settings.setValue("playback/speed", self.player.speed)
        self.settings.setValue("playback/loop", self.player.loop)
        self.settings.sync()

    def report_problem(self, text: str) -> None:
        """Tell the user about an unexpected error (status bar, and a dialog that does not
        block what was running)."""
        self.state.show_message(text)
        if not self.files.quiet:
            box = QMessageBox(QMessageBox.Icon.Warning, "GMR Studio", text, QMessageBox.StandardButton.Ok, self)
            box.setAttribute(Qt.WidgetAttribute.WA_DeleteOnClose)
            box.open()

    def close_now(self) -> None:
        """Close without asking to save (a throwaway window: a screenshot's, a bench's) and
        delete it at once, Qt's deferred deletion run while the application lives: a closed
        window left to the interpreter's teardown, destroyed with the application's wrapper,
        crashed about one `--screenshot --window` run in five."""
        self.state.undo_stack.setClean()
        self.close()
        self.deleteLater()
        QCoreApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete.value)

    def closeEvent(self, event: QCloseEvent) -> None:  # noqa: N802
        if not self.files.maybe_save():
            event.ignore()
            return
        self.player.pause()
        self.autosave.discard()  # saved, or the user chose to drop the edits
        self.autosave.shutdown()
        self.problems.shutdown()
        self.library_panel.close_library()
        self.state.undo_stack.blockSignals(True)  # its actions go away with the window
        self._save_settings()
        self.view.close_view()
        event.accept()


def _next_speed(speed: float, direction: int) -> float:
    index = min(range(len(SPEEDS)), key=lambda i: abs(SPEEDS[i] - speed))
    return SPEEDS[min(max(index + direction, 0), len(SPEEDS) - 1)]
