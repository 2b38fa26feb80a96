"""``gmr-studio [FILE]``: the desktop app.

Placeholder until the viewer lands: a window that loads the file (or says what it would
show) so that the entry point, packaging and GUI test set-up are real.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence


def build_arguments() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="gmr-studio", description="Look at and edit skeletal motion (GMR).")
    parser.add_argument("file", nargs="?", help="a .bvh or .gmr file to open")
    return parser


def create_window(path: str | None):
    """The main window (a placeholder that summarises the motion)."""
    from PyQt6.QtWidgets import QLabel, QMainWindow

    from core.errors import MotionFileError
    from core.formats import load_gmr

    window = QMainWindow()
    window.setWindowTitle("GMR Studio")
    if path:
        try:
            motion = load_gmr(path)
            text = f"{path}\n{motion.n_joints} joints, {motion.n_frames} frames at {motion.frame_rate:.4g} Hz"
        except MotionFileError as exc:
            text = str(exc)
    else:
        text = "GMR Studio\n(the 3D viewer is on its way)"
    label = QLabel(text)
    window.setCentralWidget(label)
    window.resize(800, 600)
    return window


def main(argv: Sequence[str] | None = None) -> int:
    args = build_arguments().parse_args(argv)
    from PyQt6.QtWidgets import QApplication

    app = QApplication.instance() or QApplication(sys.argv[:1])
    window = create_window(args.file)
    window.show()
    return app.exec()


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
