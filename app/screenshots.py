"""``gmr-studio FILE --screenshot OUT.png``: the view of a file rendered off screen (no
display needed), or in the real window (``--window``: the view, or the whole window), with
the command line's edits, overlays, selection, comparison, docks and onion skin applied."""

from __future__ import annotations

import argparse
import sys


def _load_or_report(motion_path: str, markers_path: str | None):
    """(snapshot, markers) read from the files, or for a marker file alone (the skeleton built
    from its markers) (MarkerDocument, None); None after printing why a file cannot be read."""
    from pathlib import Path

    from gmr_studio.app.model.loading import load_markers, load_snapshot, marker_suffixes
    from gmr_studio.app.model.marker_document import load_marker_document
    from gmr_studio.core.errors import MotionFileError, OperationError

    try:
        if Path(motion_path).suffix.lower() in marker_suffixes():
            return load_marker_document(motion_path), None
        snapshot = load_snapshot(motion_path)
        markers = load_markers(markers_path) if markers_path else None
    except (MotionFileError, OperationError) as exc:
        print(exc, file=sys.stderr)
        return None
    return snapshot, markers


def _open_loaded(state, loaded: tuple, path: str, layers=None) -> None:
    """Make what :func:`_load_or_report` read the state's document, with its markers and the
    pelvis frames recovered from them."""
    from gmr_studio.app.model import pelvis_recovery
    from gmr_studio.app.model.marker_document import MarkerDocument, show_marker_document

    document, markers = loaded
    if isinstance(document, MarkerDocument):
        state.show_message(show_marker_document(state, document, path, layers))
    else:
        state.open_document(document, path)
    if markers is not None:
        state.set_markers(markers)
        pelvis_recovery.recover_pelvis_frames(state, quiet=True)


def add_comparison(window, args: argparse.Namespace) -> str | None:
    """--compare B [--map M] [--compare-align K] [--compare-offset N|auto]: B as a comparison
    layer of the window (a marker file as a marker-set layer); an error message, or None."""
    if not args.compare:
        return None
    from pathlib import Path

    from gmr_studio.app.model.loading import load_markers, load_snapshot, marker_suffixes
    from gmr_studio.core.errors import MotionFileError

    try:
        if Path(args.compare).suffix.lower() in marker_suffixes():
            window.layers.add_markers(load_markers(args.compare), args.compare)
        else:
            snapshot = load_snapshot(args.compare)
            window.layers.add(snapshot, args.compare, args.map, align=args.compare_align, offset=args.compare_offset)
    except (MotionFileError, ValueError) as exc:
        return f"--compare: {exc}"
    return None


def _prepare(state, args: argparse.Namespace) -> str | None:
    """Apply the edit flags, --select and --show to a state; an error message, or None."""
    from gmr_studio.app.model.edit_steps import apply_steps

    problem = apply_steps(state, args.steps)
    if problem:
        return problem
    for name in [n.strip() for n in args.show.split(",") if n.strip()]:
        if name not in state.overlays:
            return f"--show: no overlay {name!r} (expected some of {', '.join(state.overlays)})"
        state.set_overlay(name, True)
    if args.select:
        if args.select not in state.motion.names:
            return f"--select: no joint {args.select!r} in the motion"
        state.select(state.motion.names.index(args.select))
    return None


def offscreen_screenshot(motion_path: str, markers_path: str | None, args: argparse.Namespace, size) -> int:
    """Render the view of a file without any window (no display needed)."""
    import pyvista as pv
    from PyQt6.QtCore import QCoreApplication

    from gmr_studio.app.media.video import save_screenshot
    from gmr_studio.app.model.state import StudioState
    from gmr_studio.app.scene.scene import SkeletonScene

    loaded = _load_or_report(motion_path, markers_path)
    if loaded is None:
        return 2
    _app = QCoreApplication.instance() or QCoreApplication(sys.argv[:1])
    state = StudioState()
    _open_loaded(state, loaded, motion_path)
    problem = _prepare(state, args)
    if problem:
        print(f"gmr-studio: {problem}", file=sys.stderr)
        return 2
    frame, out = args.frame, args.screenshot
    plotter = pv.Plotter(off_screen=True, window_size=size)
    try:
        scene = SkeletonScene(plotter)
        scene.frame = frame
        scene.overlays = dict(state.overlays)
        scene.selected = state.selected
        scene.set_snapshot(state.snapshot, reset_camera=True)
        scene.set_markers(state.marker_overlay)
        scene.set_pelvis(state.pelvis)
        if args.onion:
            from gmr_studio.app.scene.onion import OnionSettings, OnionSkins

            step, count = args.onion
            scene.add_drawable(OnionSkins(OnionSettings(shown=True, step=step, count=count)), before=scene.figure)
        scene.show_frame(frame)
        width, height = save_screenshot(scene, out)
    finally:
        plotter.close()
    print(f"wrote {out} ({width}x{height}, frame {scene.frame})")
    return 0


def _show_docks(window, args: argparse.Namespace) -> str | None:
    """--dock and --finding in a shown window; an error message, or None."""
    docks = {d.objectName(): d for d in window.findChildren(type(window.problems_dock))}
    for name in [n.strip().lower() for n in args.dock.split(",") if n.strip()]:
        if name not in docks:
            return f"--dock: no dock {name!r} (expected some of {', '.join(sorted(docks))})"
        docks[name].show()
        docks[name].raise_()
    if args.finding is not None:
        window.problems.wait()
        panel = window.problems_panel
        if not 0 <= args.finding < panel.table.rowCount():
            return f"--finding {args.finding}: the Problems dock lists {panel.table.rowCount()} findings"
        panel.table.selectRow(args.finding)
        panel.choose_row(args.finding)
    window.problems.wait()
    window.classroom.panel.settle()
    return None


def window_screenshot(motion_path: str, markers_path: str | None, args: argparse.Namespace, size) -> int:
    """Open the real window, show the frame, save its view (or the whole window) and exit."""
    from PyQt6.QtWidgets import QApplication

    from gmr_studio.app.media.video import save_screenshot, window_image
    from gmr_studio.app.window.main_window import MainWindow

    loaded = _load_or_report(motion_path, markers_path)
    if loaded is None:
        return 2
    import tempfile

    from PyQt6.QtCore import QSettings

    app = QApplication.instance() or QApplication(sys.argv[:1])
    scratch = tempfile.TemporaryDirectory()
    # throwaway settings: a screenshot neither reads nor changes the user's
    window = MainWindow(settings=QSettings(f"{scratch.name}/settings.ini", QSettings.Format.IniFormat))
    frame, out, whole_window = args.frame, args.screenshot, args.window
    _open_loaded(window.state, loaded, motion_path, window.layers)
    problem = _prepare(window.state, args) or add_comparison(window, args)
    if problem:
        print(f"gmr-studio: {problem}", file=sys.stderr)
        window.close_now()  # edits made before the refusal: nothing to save
        return 2
    if whole_window:
        window.resize(*size)
    else:
        window.view.interactor.setFixedSize(*size)
    if args.onion:
        window.onion.set_step(args.onion[0])
        window.onion.set_count(args.onion[1])
        window.onion.toggle.setChecked(True)
    window.show()
    app.processEvents()
    window.state.set_frame(frame)
    window.view.scene.reset_camera()
    problem = _show_docks(window, args)
    if problem:
        print(f"gmr-studio: {problem}", file=sys.stderr)
        window.close_now()
        return 2
    app.processEvents()
    if whole_window:
        from gmr_studio.app.media.video import save_png

        image = window_image(window, window.view.interactor)
        save_png(image, out)
        width, height = image.shape[1], image.shape[0]
    else:
        width, height = save_screenshot(window.view.scene, out)
    frame = window.state.frame
    window.close_now()
    scratch.cleanup()
    print(f"wrote {out} ({width}x{height}, frame {frame})")
    return 0
