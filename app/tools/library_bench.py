"""The Library panel scrolling a large library, printed (asserts nothing).

``python -m gmr_studio.app.tools.library_bench LIBRARY.sqlite [--frames N] [--size WxH]``:
the panel alone at 1280x800, showing every row of the library; then ``N`` frames (600 by
default) of scrolling from the top to the bottom at an even pace, each frame moving the
scroll bar and painting the table at once (what a user's wheel does), thumbnails read as
their rows come into view. Prints frames per second over the whole scroll (wall clock),
the slowest frame and the 95th percentile frame. Needs a display (``xvfb-run``), as the
table paints through the platform's window system.
"""

from __future__ import annotations

import argparse
import tempfile
import time

import numpy as np


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("library", help="a library file (gmr library index, or core.benchmark.library_speed)")
    parser.add_argument("--frames", type=int, default=600, help="frames of scrolling, top to bottom (600)")
    parser.add_argument("--size", default="1280x800", help="the panel's size in pixels (1280x800)")
    args = parser.parse_args()
    width, height = (int(v) for v in args.size.lower().split("x"))
    from PyQt6.QtCore import QSettings
    from PyQt6.QtWidgets import QApplication

    from gmr_studio.app.library.panel import LibraryPanel

    app = QApplication.instance() or QApplication([])
    with tempfile.TemporaryDirectory() as folder:
        panel = LibraryPanel(QSettings(f"{folder}/settings.ini", QSettings.Format.IniFormat))
        panel.resize(width, height)
        panel.show()
        if not panel.open_library(args.library):
            raise SystemExit(f"cannot open {args.library}: {panel.status.text()}")
        for _ in range(20):
            app.processEvents()
            time.sleep(0.01)
        bar = panel.table.verticalScrollBar()
        rows = panel.model.rowCount()
        steps = np.linspace(0, bar.maximum(), args.frames + 1).round().astype(int)[1:]
        durations = []
        start = time.perf_counter()
        for value in steps:
            begin = time.perf_counter()
            bar.setValue(int(value))
            panel.table.viewport().repaint()
            app.processEvents()  # the thumbnails asked for are read, and painted on the next frame
            durations.append(time.perf_counter() - begin)
        total = time.perf_counter() - start
        panel.close_library()
        panel.close()
    durations = np.array(durations)
    rows_per_frame = rows / args.frames
    print(
        f"panel {width}x{height}, {rows} rows, {args.frames} frames top to bottom ({rows_per_frame:.1f} rows a frame): "
        f"{args.frames / total:.1f} frames per second; slowest frame {1e3 * durations.max():.1f} ms, "
        f"95th percentile {1e3 * np.percentile(durations, 95):.1f} ms"
    )


if __name__ == "__main__":
    main()
