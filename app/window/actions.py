"""Every menu, toolbar and keyboard command of the window, in one table.

:func:`build_actions` makes the QActions (text, shortcut, tip, checkable) and connects each
to its handler; :func:`fill_menus` lays them out in the menu bar, the toolbar and the joint
context menu. :func:`update_enabled` enables the edit actions that apply to the selection.
"""

from __future__ import annotations

from collections.abc import Callable

from PyQt6.QtGui import QAction, QKeySequence, QUndoStack
from PyQt6.QtWidgets import QInputDialog, QMainWindow, QMenu, QStyle, QToolBar

from gmr_studio.app.docks.range_slider import range_ending_at, range_starting_at
from gmr_studio.app.model import commands
from gmr_studio.app.model.commands import can_join, can_remove_dummies
from gmr_studio.app.model.state import StudioState
from gmr_studio.core.edits.mirror import side_partners
from gmr_studio.core.space.up_axis import up_axis_of
from gmr_studio.core.timebase.clock import nominal_rate, rate_text

Key = QKeySequence.StandardKey

#: name -> (text, shortcut(s), status tip, checkable, standard icon or None)
ACTIONS: dict[str, tuple[str, object, str, bool, str | None]] = {
    "open": (
        "&Open...",
        Key.Open,
        "Open a BVH, ASF/AMC or GMR motion, or a C3D/TRC marker file (its skeleton built from the markers)",
        False,
        "SP_DialogOpenButton",
    ),
    "body_model": ("&Body model...", "", "The SMPL/SMPL-H/SMPL-X model AMASS .npz motions are read with", False, None),
    "add_markers": ("Add &markers...", "Ctrl+M", "Show a C3D or TRC marker file over the motion", False, None),
    "align_markers": ("Marker &alignment...", "", "Units, axes, offset and scale of the markers", False, None),
    "remove_markers": ("Remove markers", "", "Hide and forget the markers", False, None),
    "recover_pelvis": ("Recover &pelvis frames", "", "Procrustes pelvis orientation from the markers", False, None),
    "build_skeleton": (
        "&Build skeleton",
        "",
        "Replace the motion by the skeleton built from the markers shown (recognised marker set; undoable)",
        False,
        None,
    ),
    "refine_markers": (
        "Re&fine the fit",
        "",
        "Skeletons built from markers: least squares over the joint angles after the closed form (slower)",
        True,
        None,
    ),
    "save": ("&Save", Key.Save, "Save the motion as GMR", False, "SP_DialogSaveButton"),
    "save_as": ("Save &as GMR...", Key.SaveAs, "Save the motion as another GMR file", False, None),
    "export_bvh": ("&Export BVH...", "Ctrl+E", "Write the motion as BVH (one tree)", False, None),
    "export_gltf": (
        "Export &glTF...",
        "",
        "Write the motion as glTF 2.0 (.glb): nodes, animation, bone mesh",
        False,
        None,
    ),
    "screenshot": ("Save screens&hot...", "Ctrl+Shift+P", "Save the 3D view as a PNG", False, None),
    "export_video": ("Export &video...", "", "Write an mp4 of the playback", False, None),
    "quit": ("&Quit", Key.Quit, "Close GMR Studio", False, None),
    "shift_root": ("Shift &root", "Ctrl+R", "Shift the root of the tree to the selected joint", False, None),
    "split": ("&Split here", "Ctrl+T", "Make the selected joint a root (with a soft link to its parent)", False, None),
    "join": ("&Join to parent", "Ctrl+J", "Put the selected split root back under its soft-link parent", False, None),
    "split_all": ("Split a&ll", "Ctrl+Shift+T", "Every joint its own root", False, None),
    "join_all": ("Join al&l", "Ctrl+Shift+J", "Join every soft link (restores the original trees)", False, None),
    "remove_dummies": ("Remove &dummy joints", "", "Fold zero-offset dummy joints into their children", False, None),
    "trim_range": ("&Trim to range", "", "Keep only the selected frame range (an undoable edit)", False, None),
    "resample": ("Res&ample...", "", "Resample the motion to another frame rate (an undoable edit)", False, None),
    "mirror": ("&Mirror left/right", "", "Swap left and right across the sagittal plane (undoable)", False, None),
    "up_axis": ("&Up axis...", "", "Turn the world so that Y or Z is up (an undoable edit)", False, None),
    "scale": ("S&cale lengths...", "", "Multiply every length by a factor (an undoable edit)", False, None),
    "range_start": ("Set range &start", "I", "Start the frame range at the current frame", False, None),
    "range_end": ("Set range &end", "O", "End the frame range at the current frame (included)", False, None),
    "clear_range": ("&Clear range", "", "Forget the frame range", False, None),
    "play": ("&Play", "Space", "Play or pause", False, "SP_MediaPlay"),
    "step_back": ("Step &back", "Left", "Previous frame", False, "SP_MediaSeekBackward"),
    "step_forward": ("Step &forward", "Right", "Next frame", False, "SP_MediaSeekForward"),
    "back_second": ("Back one second", "Shift+Left", "One second earlier", False, None),
    "forward_second": ("Forward one second", "Shift+Right", "One second later", False, None),
    "first_frame": ("First frame", "Home", "Go to the first frame", False, "SP_MediaSkipBackward"),
    "last_frame": ("Last frame", "End", "Go to the last frame", False, "SP_MediaSkipForward"),
    "loop": ("&Loop", "Ctrl+L", "Play in a loop", True, None),
    "slower": ("Slower", "[", "Halve the playback speed (down to 0.25x)", False, None),
    "faster": ("Faster", "]", "Double the playback speed (up to 4x)", False, None),
    "reset_camera": (
        "&Reset camera",
        "Ctrl+0",
        "Frame the figure (or the whole motion when not following)",
        False,
        None,
    ),
    "overlay_ground": ("&Ground grid", "G", "Show the ground grid", True, None),
    "overlay_soft_links": ("Soft lin&ks", "K", "Show soft links as dashed lines", True, None),
    "overlay_axes": ("Joint &axes", "A", "Show each joint's world rotation as a triad", True, None),
    "overlay_trails": (
        "&Trail of the selection",
        "T",
        "Show the selected joint's path over the last second",
        True,
        None,
    ),
    "overlay_labels": ("Joint &labels", "L", "Show joint names", True, None),
    "overlay_markers": ("&Markers", "M", "Show the markers", True, None),
    "overlay_marker_labels": ("Marker la&bels", "B", "Label the hovered and selected marker", True, None),
    "overlay_pelvis": ("&Pelvis frames", "P", "Show the recovered pelvis frame", True, None),
    "overlay_follow": ("&Follow the figure", "F", "Move the camera along with the figure", True, None),
    "about": ("&About GMR Studio", "", "", False, None),
    "keys": ("&Keyboard shortcuts", "F1", "", False, None),
}

SELECTION_EDITS = ("shift_root", "split", "join")
CLIP_EDITS = ("trim_range", "resample", "mirror", "up_axis", "scale")
RANGE_ACTIONS = ("range_start", "range_end", "clear_range")
#: longest undo/redo label shown in the menu and the toolbar (the full one is the tooltip),
#: so that an edit of a long joint name does not widen the toolbar
UNDO_LABEL_CHARS = 28


def elide(text: str, limit: int = UNDO_LABEL_CHARS) -> str:
    """``text`` cut to ``limit`` characters, ending in an ellipsis when cut."""
    return text if len(text) <= limit else text[: limit - 1].rstrip() + "\u2026"


def _short_labels(action: QAction, prefix: str, text_changed) -> None:
    """Keep an undo stack action's label short; its tooltip and status tip say it all."""

    def update(text: str) -> None:
        full = f"{prefix} {text}" if text else prefix
        action.setText(elide(full))
        plain = full.replace("&", "")
        action.setToolTip(plain)
        action.setStatusTip(plain)

    text_changed.connect(update)  # after the stack's own connection, so this label wins
    update("")


def redo_shortcuts() -> list[QKeySequence]:
    """Ctrl+Shift+Z and the platform's own Redo keys, each once: on X11 the platform's Redo
    is Ctrl+Shift+Z too, and one key given twice to an action is an ambiguous shortcut that
    Qt refuses to trigger."""
    keys: list[QKeySequence] = []
    for key in [QKeySequence("Ctrl+Shift+Z"), *QKeySequence.keyBindings(Key.Redo)]:
        if not key.isEmpty() and all(key != other for other in keys):
            keys.append(key)
    return keys


def build_actions(window: QMainWindow, handlers: dict[str, Callable], stack: QUndoStack) -> dict[str, QAction]:
    """All actions of the window, connected to ``handlers[name]`` (triggered or toggled);
    undo and redo are the undo stack's own (their text names the edit)."""
    actions: dict[str, QAction] = {
        "undo": stack.createUndoAction(window, "&Undo"),
        "redo": stack.createRedoAction(window, "&Redo"),
    }
    _short_labels(actions["undo"], "&Undo", stack.undoTextChanged)
    _short_labels(actions["redo"], "&Redo", stack.redoTextChanged)
    actions["undo"].setShortcut(QKeySequence(Key.Undo))
    actions["redo"].setShortcuts(redo_shortcuts())
    style = window.style()
    for name, icon in (("undo", "SP_ArrowBack"), ("redo", "SP_ArrowForward")):
        # an icon: the toolbar shows it alone, whatever the edit's name (the tooltip names it)
        actions[name].setIcon(style.standardIcon(getattr(QStyle.StandardPixmap, icon)))
        window.addAction(actions[name])
    for name, (text, shortcut, tip, checkable, icon) in ACTIONS.items():
        action = QAction(text, window)
        if shortcut:
            action.setShortcut(QKeySequence(shortcut))
        action.setStatusTip(tip)
        action.setToolTip(
            f"{text.replace('&', '').rstrip('.')}" + (f" ({action.shortcut().toString()})" if shortcut else "")
        )
        action.setCheckable(checkable)
        if icon:
            action.setIcon(style.standardIcon(getattr(QStyle.StandardPixmap, icon)))
        handler = handlers.get(name)
        if handler is not None:
            (action.toggled if checkable else action.triggered).connect(handler)
        window.addAction(action)  # shortcuts work whichever widget has the focus
        actions[name] = action
    return actions


def fill_menus(window: QMainWindow, actions: dict[str, QAction], recent_menu: QMenu, history_toggle) -> QMenu:
    """Menus and toolbar; returns the joint context menu."""
    bar = window.menuBar()
    file_menu = bar.addMenu("&File")
    file_menu.addAction(actions["open"])
    file_menu.addMenu(recent_menu)
    file_menu.addAction(actions["body_model"])
    file_menu.addSeparator()
    for name in ("save", "save_as", "export_bvh", "export_gltf"):
        file_menu.addAction(actions[name])
    file_menu.addSeparator()
    for name in ("screenshot", "export_video"):
        file_menu.addAction(actions[name])
    file_menu.addSeparator()
    file_menu.addAction(actions["quit"])
    edit_menu = bar.addMenu("&Edit")
    for name in ("undo", "redo"):
        edit_menu.addAction(actions[name])
    edit_menu.addAction(history_toggle)
    edit_menu.addSeparator()
    for name in ("shift_root", "split", "join", "split_all", "join_all", "remove_dummies"):
        edit_menu.addAction(actions[name])
    edit_menu.addSeparator()
    for name in CLIP_EDITS:
        edit_menu.addAction(actions[name])
    markers_menu = bar.addMenu("&Markers")
    for name in ("add_markers", "align_markers", "recover_pelvis", "remove_markers"):
        markers_menu.addAction(actions[name])
    markers_menu.addSeparator()
    for name in ("build_skeleton", "refine_markers"):
        markers_menu.addAction(actions[name])
    view_menu = bar.addMenu("&View")
    view_menu.addAction(actions["reset_camera"])
    view_menu.addSeparator()
    for name in [n for n in ACTIONS if n.startswith("overlay_")]:
        view_menu.addAction(actions[name])
    view_menu.addSeparator()
    window.view_menu = view_menu  # the docks add their toggles here
    play_menu = bar.addMenu("&Playback")
    for name in ("play", "step_back", "step_forward", "back_second", "forward_second", "first_frame", "last_frame"):
        play_menu.addAction(actions[name])
    play_menu.addSeparator()
    for name in ("loop", "slower", "faster"):
        play_menu.addAction(actions[name])
    play_menu.addSeparator()
    for name in RANGE_ACTIONS:
        play_menu.addAction(actions[name])
    help_menu = bar.addMenu("&Help")
    help_menu.addAction(actions["keys"])
    help_menu.addAction(actions["about"])
    toolbar = QToolBar("Tools", window)
    toolbar.setObjectName("tools")
    for name in ("open", "save"):
        toolbar.addAction(actions[name])
    toolbar.addSeparator()
    for name in ("undo", "redo"):
        toolbar.addAction(actions[name])
    toolbar.addSeparator()
    for name in ("shift_root", "split", "join", "split_all", "join_all", "remove_dummies"):
        toolbar.addAction(actions[name])
    toolbar.addSeparator()
    for name in ("overlay_axes", "overlay_trails", "overlay_labels", "overlay_markers", "overlay_pelvis"):
        toolbar.addAction(actions[name])
    window.addToolBar(toolbar)
    joint_menu = QMenu("Joint", window)
    for name in ("shift_root", "split", "join"):
        joint_menu.addAction(actions[name])
    joint_menu.addSeparator()
    for name in ("split_all", "join_all", "remove_dummies"):
        joint_menu.addAction(actions[name])
    return joint_menu


def show_overlay_switch(action: QAction, shown: bool, available: bool) -> None:
    """An overlay's switch: enabled when there is something to show, checked when it is shown
    (without emitting: the state already holds the choice)."""
    action.setEnabled(available)
    action.blockSignals(True)
    action.setChecked(shown and available)
    action.blockSignals(False)


def update_enabled(actions: dict[str, QAction], state: StudioState) -> None:
    """Enable what applies: edits on the selection, document actions when a motion is open."""
    motion, joint = state.motion, state.selected
    has_motion = motion is not None
    not_root = bool(has_motion and joint is not None and motion.parents[joint] >= 0)
    actions["shift_root"].setEnabled(not_root)
    actions["split"].setEnabled(not_root)
    actions["join"].setEnabled(bool(can_join(motion, joint)))
    actions["split_all"].setEnabled(bool(has_motion and len(motion.roots) < motion.n_joints))
    actions["join_all"].setEnabled(bool(has_motion and (motion.soft_parents >= 0).any()))
    actions["remove_dummies"].setEnabled(can_remove_dummies(motion))
    for name in (
        "save",
        "save_as",
        "export_bvh",
        "export_gltf",
        "screenshot",
        "export_video",
        "add_markers",
        "reset_camera",
    ):
        actions[name].setEnabled(has_motion)
    has_markers = state.marker_overlay is not None
    for name in ("align_markers", "remove_markers"):
        actions[name].setEnabled(has_markers)
    actions["recover_pelvis"].setEnabled(has_markers)
    actions["build_skeleton"].setEnabled(has_markers)
    # the marker and pelvis switches look off (and are) while there is nothing to show;
    # the user's choice is kept in the state and shows again when markers are loaded
    for name, available in (
        ("markers", has_markers),
        ("marker_labels", has_markers),
        ("pelvis", state.pelvis is not None),
    ):
        show_overlay_switch(actions[f"overlay_{name}"], state.overlays[name], available)
    selected = state.frame_range
    actions["trim_range"].setEnabled(bool(has_motion and selected is not None and selected != (0, motion.n_frames)))
    actions["resample"].setEnabled(bool(has_motion and motion.n_frames >= 2))
    actions["mirror"].setEnabled(bool(has_motion and side_partners(motion.names).pairs.size))
    for name in ("up_axis", "scale"):
        actions[name].setEnabled(has_motion)
    for name in ("range_start", "range_end"):
        actions[name].setEnabled(has_motion)
    actions["clear_range"].setEnabled(selected is not None)


def clip_handlers(window: QMainWindow, state: StudioState) -> dict[str, Callable]:
    """Handlers of the clip edits (:data:`CLIP_EDITS`) and of the range keys (:data:`RANGE_ACTIONS`)."""

    def trim_to_range() -> bool:
        return state.frame_range is not None and commands.trim_to_range(state, *state.frame_range)

    def set_start() -> None:
        state.set_frame_range(*range_starting_at(state.frame_range, state.frame, state.n_frames))

    def set_end() -> None:
        state.set_frame_range(*range_ending_at(state.frame_range, state.frame))

    return {
        "trim_range": trim_to_range,
        "resample": lambda: ask_and_resample(window, state),
        "mirror": lambda: commands.mirror_left_right(state),
        "up_axis": lambda: ask_and_turn_up(window, state),
        "scale": lambda: ask_and_scale(window, state),
        "range_start": set_start,
        "range_end": set_end,
        "clear_range": lambda: state.set_frame_range(-1, -1),
    }


def ask_and_resample(window: QMainWindow, state: StudioState) -> bool:
    """Ask for a frame rate (half the current one offered) and resample to it, undoably."""
    motion = state.motion
    if motion is None:
        return False
    rate, accepted = QInputDialog.getDouble(
        window,
        "Resample",
        f"New frame rate in Hz (now {rate_text(motion.frame_time)} Hz):",
        round(nominal_rate(motion.frame_time) / 2, 3),
        1.0,
        1000.0,
        3,
    )
    return bool(accepted) and commands.resample_to(state, rate)


def ask_and_turn_up(window: QMainWindow, state: StudioState) -> bool:
    """Ask which axis is to be up (the other one than the motion's offered) and turn the
    world to it, undoably."""
    motion = state.motion
    if motion is None:
        return False
    now = up_axis_of(motion)
    choices = ["Z up", "Y up"] if now == "y" else ["Y up", "Z up"]
    choice, accepted = QInputDialog.getItem(
        window, "Up axis", f"The motion is {now.upper()} up. Turn the world so that:", choices, 0, False
    )
    return bool(accepted) and commands.up_axis_to(state, choice[0].lower())


def ask_and_scale(window: QMainWindow, state: StudioState) -> bool:
    """Ask for a factor and multiply every length by it, undoably."""
    if state.motion is None:
        return False
    factor, accepted = QInputDialog.getDouble(window, "Scale lengths", "Multiply every length by:", 1.0, 1e-6, 1e6, 6)
    return bool(accepted) and factor != 1.0 and commands.scale_by(state, factor)
