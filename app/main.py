"""``gmr-studio [FILE] [--markers M] [--compare B [--map M] [--compare-align KIND] [--compare-offset N|auto]]
[EDITS] [--screenshot OUT.png [--frame N] [--size WxH] [--window]]``.

EDITS are ``gmr edit``'s flags (``--shift-root J``, ``--split J``, ``--join J``,
``--split-all``, ``--join-all``, ``--remove-dummies``), applied in the order given through
the app's own undoable commands: to the picture with ``--screenshot``, else to the window,
which opens with them applied and unsaved (Edit > Undo takes them back).

With no FILE the demo opens (``resources/demo/``: a walk and its markers, made by
``python -m gmr_studio.core.demo``). ``--screenshot`` renders the 3D view to a PNG and exits; it
works without a display (off-screen rendering). Without a display and without
``--screenshot`` the app says how to run it and exits with status 2 instead of letting Qt
abort.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence

from gmr_studio.core.cli.edit import add_edit_arguments
from gmr_studio.core.compare import ALIGN_KINDS
from gmr_studio.core.compare.clock import DEFAULT_OFFSET
from gmr_studio.core.demo import MARKERS_FILE, MOTION_FILE, demo_folder


def build_arguments() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="gmr-studio", description="Look at and edit skeletal motion (GMR).")
    parser.add_argument("file", nargs="?", help="a .bvh, .gmr (or .amc) motion; default: the demo walk")
    parser.add_argument("--markers", metavar="M", help="a .trc (or .c3d) marker file to show over the motion")
    add_edit_arguments(parser)
    parser.add_argument(
        "--compare",
        metavar="B",
        help="show motion B as a ghost compared with FILE, or marker file B (.trc, .c3d) as a marker layer "
        "(a screenshot needs --window)",
    )
    parser.add_argument("--map", metavar="M", help="with --compare: a joint-name map (e.g. cmu, or a .toml)")
    parser.add_argument(
        "--compare-align",
        choices=ALIGN_KINDS,
        default="none",
        metavar="KIND",
        help="with --compare: align B onto FILE by none (default), rigid or similarity",
    )
    parser.add_argument(
        "--compare-offset",
        type=parse_offset,
        default=DEFAULT_OFFSET,
        metavar="N|auto",
        help="with --compare: B's time minus FILE's in FILE's frames, or auto (default: found)",
    )
    parser.add_argument("--screenshot", metavar="OUT.png", help="render the view to a PNG and exit")
    parser.add_argument("--frame", type=int, default=0, metavar="N", help="frame to render (with --screenshot)")
    parser.add_argument("--size", default="1280x800", metavar="WxH", help="image size (with --screenshot)")
    parser.add_argument("--window", action="store_true", help="with --screenshot: the whole window, docks included")
    parser.add_argument("--select", metavar="JOINT", help="with --screenshot: select this joint first")
    parser.add_argument(
        "--dock", metavar="DOCKS", default="", help="with --screenshot --window: docks to show, e.g. problems,curves"
    )
    parser.add_argument(
        "--finding",
        type=int,
        metavar="N",
        help="with --screenshot --window: choose the Problems dock's finding N (0-based, as listed): "
        "its frame, joint and camera",
    )
    parser.add_argument(
        "--show",
        metavar="OVERLAYS",
        default="",
        help="with --screenshot: overlays to switch on, e.g. axes,trails,labels",
    )
    parser.add_argument(
        "--onion",
        nargs="?",
        const="10,3",
        metavar="STEP,COUNT",
        help="with --screenshot: show the onion skin, every STEP frames, COUNT poses each side (default 10,3)",
    )
    parser.add_argument(
        "--filmstrip", metavar="OUT.png", help="render several poses in one picture (with --frames) and exit"
    )
    parser.add_argument("--frames", metavar="A:B:STEP", help="with --filmstrip: the frames, as a Python slice")
    parser.add_argument(
        "--layout", choices=("path", "side"), default="path", help="with --filmstrip: along the path or side by side"
    )
    parser.add_argument(
        "--recover", action="store_true", help="list the recovery files of unsaved work and exit (no window)"
    )
    # test-only (tests/test_app_recovery.py): make N edits after opening, as a user would
    parser.add_argument("--test-edits", type=int, default=0, help=argparse.SUPPRESS)
    # for app.bench: print the wall-clock time when the file's first frame is drawn, then quit
    parser.add_argument("--first-frame-time", action="store_true", help=argparse.SUPPRESS)
    return parser


def parse_offset(text: str) -> float | str:
    """``--compare-offset``: "auto" or a finite number of frames."""
    if text.strip().lower() == "auto":
        return "auto"
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of frames or auto, not {text!r}") from None
    if value != value or value in (float("inf"), float("-inf")):
        raise argparse.ArgumentTypeError(f"expected a finite number of frames, not {text!r}")
    return value


def parse_size(text: str) -> tuple[int, int]:
    try:
        width, height = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--size must look like 1280x800, not {text!r}") from None
    if not (16 <= width <= 8192 and 16 <= height <= 8192):
        raise argparse.ArgumentTypeError(f"--size {text}: each side must be 16 to 8192 pixels")
    return width, height


def parse_onion(text: str | None) -> tuple[int, int] | None:
    """``--onion STEP,COUNT`` -> (step, count), None without the flag."""
    if text is None:
        return None
    try:
        step, count = (int(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--onion must look like 10,3 (STEP,COUNT), not {text!r}") from None
    if step < 1 or count < 1:
        raise argparse.ArgumentTypeError(f"--onion {text}: STEP and COUNT must be at least 1")
    return step, count


def has_display() -> bool:
    """A display the window can be shown on: not Linux, or DISPLAY / WAYLAND_DISPLAY set, or a
    Qt platform chosen explicitly that shows windows (``offscreen`` and ``minimal`` do not)."""
    if sys.platform != "linux":
        return True
    platform = os.environ.get("QT_QPA_PLATFORM", "").split(":")[0]
    if platform in ("offscreen", "minimal"):
        return False
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY") or platform)


def render_without_display() -> None:
    """With no display, have VTK render off screen through EGL (Mesa's, or the GPU's) rather
    than try X first and print its 'bad X server connection' warning; a choice already made
    in ``VTK_DEFAULT_OPENGL_WINDOW`` is kept."""
    if not has_display():
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


def default_files(args: argparse.Namespace) -> tuple[str, str | None]:
    """The motion and markers to open: the arguments, or the demo."""
    if args.file:
        return args.file, args.markers
    folder = demo_folder()
    markers = folder / MARKERS_FILE
    return str(folder / MOTION_FILE), args.markers or (str(markers) if markers.exists() else None)


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_arguments()
    args = parser.parse_args(argv)
    if not args.compare and (args.compare_align != "none" or args.compare_offset != DEFAULT_OFFSET):
        parser.error("--compare-align and --compare-offset go with --compare B")
    try:
        size = parse_size(args.size)
        args.onion = parse_onion(args.onion)
    except argparse.ArgumentTypeError as exc:
        parser.error(str(exc))
    if args.recover:
        from gmr_studio.app.reliability.recovery import print_recoveries

        return print_recoveries()
    motion_path, markers_path = default_files(args)
    render_without_display()
    if args.filmstrip:
        from gmr_studio.app.media.filmstrip import filmstrip_command

        return filmstrip_command(motion_path, args.filmstrip, args.frames, args.layout, size)
    if args.screenshot and (args.window or has_display()):
        if not has_display():
            print("gmr-studio: --window needs a display (run under xvfb-run)", file=sys.stderr)
            return 2
        return window_screenshot(motion_path, markers_path, args, size)
    if args.screenshot and args.compare:
        print("gmr-studio: --compare draws in the window: add --window and run under xvfb-run", file=sys.stderr)
        return 2
    if args.screenshot:
        return offscreen_screenshot(motion_path, markers_path, args, size)
    if not has_display():
        print(
            "gmr-studio: no display (DISPLAY and WAYLAND_DISPLAY are unset): run it on a desktop, under "
            "`xvfb-run -a gmr-studio ...`, or render a picture with `gmr-studio FILE --screenshot OUT.png`",
            file=sys.stderr,
        )
        return 2
    from PyQt6.QtWidgets import QApplication

    from gmr_studio.app.reliability.crash import install_hooks
    from gmr_studio.app.window.main_window import MainWindow
    from gmr_studio.app.window.theme import apply_theme

    app = QApplication.instance() or QApplication(sys.argv[:1])
    app.setApplicationName("GMR Studio")
    apply_theme(app)
    window = MainWindow()
    install_hooks(window.report_problem)  # an exception in a slot is logged and survived
    window.show()
    if args.steps:
        _apply_steps_once_loaded(window, args.steps)
    if args.first_frame_time:
        window.files.load_finished.connect(lambda ok: _report_first_frame(app, window, ok))
    if args.compare:
        _compare_once_loaded(window, args)
    from gmr_studio.app.dialogs.recovery_dialog import offer_recovery

    if not offer_recovery(window):
        window.files.open_path(motion_path, markers=markers_path, ask=False, wait=bool(args.test_edits))
    if args.test_edits:
        make_test_edits(window.state, args.test_edits)
    return app.exec()


def _compare_once_loaded(window, args: argparse.Namespace) -> None:
    """Add ``--compare B`` as a comparison layer once the first document is shown."""

    def compare(loaded: bool) -> None:
        window.files.load_finished.disconnect(compare)
        if loaded:
            window.files.compare_path(
                args.compare, joint_map=args.map, align=args.compare_align, offset=args.compare_offset
            )

    window.files.load_finished.connect(compare)


def _apply_steps_once_loaded(window, steps: list) -> None:
    """Apply the edit flags to the first document the window loads (never to a later one)."""

    def apply(loaded: bool) -> None:
        window.files.load_finished.disconnect(apply)
        problem = apply_steps(window.state, steps) if loaded else None
        if problem:
            window.state.show_message(problem)

    window.files.load_finished.connect(apply)


def _edit_command(operation: str):
    """The app's command for one of ``gmr edit``'s operations: (state, joint index) -> pushed."""
    from gmr_studio.app.model import commands, extensions

    return {
        "shift_root": commands.make_root,
        "split": commands.split_here,
        "join": commands.join_to_parent,
        "split_all": lambda state, _: commands.split_everything(state),
        "join_all": lambda state, _: commands.join_everything(state),
        "remove_dummies": lambda state, _: extensions.remove_dummy_joints(state),
    }[operation]


def apply_steps(state, steps: list) -> str | None:
    """Apply ``gmr edit``'s steps ((operation, joint name) pairs, :func:`add_edit_arguments`)
    to the state's document through the app's undoable commands, in order; stops at the
    first one refused and returns its message, else None. A step with nothing to change
    (``--join-all`` on a tree) is no error, as in ``gmr edit``."""
    from gmr_studio.core.errors import OperationError

    for operation, joint in steps:
        flag = "--" + operation.replace("_", "-")
        index = None
        if operation in ("shift_root", "split", "join"):
            try:
                index = state.motion.joint_index(joint)
            except OperationError as exc:
                return f"{flag} {joint}: {exc}"
        messages: list[str] = []
        state.message.connect(messages.append)
        try:
            done = _edit_command(operation)(state, index)
        finally:
            state.message.disconnect(messages.append)
        if not done and not (messages and messages[-1].endswith(": nothing to change")):
            return f"{flag}: {messages[-1] if messages else 'refused'}"
    return None


def make_test_edits(state, count: int) -> None:
    """Test only (``--test-edits N``): split the tree at joints 1, 2, ... of the motion as
    it is after each edit (joints that are roots already are skipped); prints their names."""
    from gmr_studio.app.model import commands

    names, joint = [], 1
    while len(names) < count and joint < state.motion.n_joints:
        name = state.motion.names[joint]
        if state.motion.parents[joint] >= 0 and commands.split_here(state, joint):
            names.append(name)
        joint += 1
    print(f"made {len(names)} edits: split at {','.join(names)}", flush=True)


def _report_first_frame(app, window, loaded: bool) -> None:
    import time

    window.view.scene.render()
    app.processEvents()
    print(f"{time.time():.6f}" if loaded else "nan", flush=True)
    window.close()
    app.quit()


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


def _open_loaded(state, loaded, path: str, layers=None) -> None:
    """Make what :func:`_load_or_report` read the state's document."""
    from gmr_studio.app.model.marker_document import MarkerDocument, show_marker_document

    if isinstance(loaded, MarkerDocument):
        state.show_message(show_marker_document(state, loaded, path, layers))
    else:
        state.open_document(loaded, path)


def _add_comparison(window, args: argparse.Namespace) -> str | None:
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
    from gmr_studio.app.model import extensions
    from gmr_studio.app.model.state import StudioState
    from gmr_studio.app.scene.scene import SkeletonScene

    loaded = _load_or_report(motion_path, markers_path)
    if loaded is None:
        return 2
    snapshot, markers = loaded
    _app = QCoreApplication.instance() or QCoreApplication(sys.argv[:1])
    state = StudioState()
    _open_loaded(state, snapshot, motion_path)
    if markers is not None:
        state.set_markers(markers)
        extensions.recover_pelvis_frames(state, quiet=True)
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
    return None


def window_screenshot(motion_path: str, markers_path: str | None, args: argparse.Namespace, size) -> int:
    """Open the real window, show the frame, save its view (or the whole window) and exit."""
    from PyQt6.QtWidgets import QApplication

    from gmr_studio.app.media.video import save_screenshot, window_image
    from gmr_studio.app.model import extensions
    from gmr_studio.app.window.main_window import MainWindow

    loaded = _load_or_report(motion_path, markers_path)
    if loaded is None:
        return 2
    snapshot, markers = loaded
    import tempfile

    from PyQt6.QtCore import QSettings

    app = QApplication.instance() or QApplication(sys.argv[:1])
    scratch = tempfile.TemporaryDirectory()
    # throwaway settings: a screenshot neither reads nor changes the user's
    window = MainWindow(settings=QSettings(f"{scratch.name}/settings.ini", QSettings.Format.IniFormat))
    frame, out, whole_window = args.frame, args.screenshot, args.window
    _open_loaded(window.state, snapshot, motion_path, window.layers)
    if markers is not None:
        window.state.set_markers(markers)
        extensions.recover_pelvis_frames(window.state, quiet=True)
    problem = _prepare(window.state, args) or _add_comparison(window, args)
    if problem:
        print(f"gmr-studio: {problem}", file=sys.stderr)
        window.state.undo_stack.setClean()  # edits made before the refusal: nothing to save
        window.close()
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
        window.state.undo_stack.setClean()
        window.close()
        return 2
    app.processEvents()
    if whole_window:
        from gmr_studio.app.media.video import save_png

        image = window_image(window, window.view.interactor)
        save_png(image, out)
        width, height = image.shape[1], image.shape[0]
    else:
        width, height = save_screenshot(window.view.scene, out)
    window.state.undo_stack.setClean()
    window.close()
    scratch.cleanup()
    print(f"wrote {out} ({width}x{height}, frame {window.state.frame})")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
