"""``gmr-studio``'s command line: the arguments, their parsers, the files opened by
default (the demo) and whether there is a display to show a window on."""

from __future__ import annotations

import argparse
import os
import sys

from gmr_studio.core.compare import ALIGN_KINDS
from gmr_studio.core.compare.clock import DEFAULT_OFFSET
from gmr_studio.core.demo import MARKERS_FILE, MOTION_FILE, demo_folder
from gmr_studio.core.edits.steps import add_edit_arguments


def build_arguments() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="gmr-studio", description="Look at and edit skeletal motion (GMR).")
    parser.add_argument("file", nargs="?", help="a motion file (.bvh, .gmr, .amc, glTF, .fbx); default: the demo walk")
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
