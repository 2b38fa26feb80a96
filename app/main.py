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
import sys
from collections.abc import Sequence
from pathlib import Path

from gmr_studio.app.arguments import (
    build_arguments,
    default_files,
    has_display,
    parse_onion,
    parse_size,
    render_without_display,
)
from gmr_studio.app.screenshots import offscreen_screenshot, window_screenshot
from gmr_studio.core.compare.clock import DEFAULT_OFFSET


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
    for output in (args.screenshot, args.filmstrip):
        if output and not Path(output).resolve().parent.is_dir():
            print(f"gmr-studio: {output}: the folder {Path(output).resolve().parent} does not exist", file=sys.stderr)
            return 2
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

    from gmr_studio.app.crash import install_hooks
    from gmr_studio.app.window.main_window import MainWindow
    from gmr_studio.app.window.theme import apply_theme

    app = QApplication.instance() or QApplication(sys.argv[:1])
    app.setApplicationName("GMR Studio")
    apply_theme(app)
    window = MainWindow()
    install_hooks(window.report_problem)  # an exception in a slot is logged and survived
    window.show()
    if args.steps:
        apply_steps_once_loaded(window, args.steps)
    if args.first_frame_time:
        window.files.load_finished.connect(lambda ok: _report_first_frame(app, window, ok))
    if args.compare:
        _compare_once_loaded(window, args)
    from gmr_studio.app.dialogs.recovery_dialog import offer_recovery

    if not offer_recovery(window):
        window.files.open_path(motion_path, markers=markers_path, ask=False, wait=bool(args.test_edits))
    if args.test_edits:
        from gmr_studio.app.model.edit_steps import make_test_edits

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


def apply_steps_once_loaded(window, steps: list) -> None:
    """Apply the edit flags to the first document the window loads (never to a later one)."""

    from gmr_studio.app.model.edit_steps import apply_steps

    def apply(loaded: bool) -> None:
        window.files.load_finished.disconnect(apply)
        problem = apply_steps(window.state, steps) if loaded else None
        if problem:
            window.state.show_message(problem)

    window.files.load_finished.connect(apply)


def _report_first_frame(app, window, loaded: bool) -> None:
    import time

    window.view.scene.render()
    app.processEvents()
    print(f"{time.time():.6f}" if loaded else "nan", flush=True)
    window.close()
    app.quit()


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
