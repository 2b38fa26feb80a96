"""The Library panel scrolling a large library, printed (asserts nothing).

``python -m gmr_studio.app.tools.library_bench LIBRARY.sqlite [--frames N] [--size WxH]``:
the panel alone at 1280x800, showing every row of the library; then ``N`` frames (600 by
default) of scrolling from the top to the bottom at an even pace, each frame moving the
scroll bar and painting the table at once (what a user's wheel does), thumbnails read as
their rows come into view. The goal is that no frame takes longer than a thirtieth of a
second: prints the frames per second over the whole scroll, each frame's wall-clock time
(median, 95th and 99th percentile, slowest) and how many frames took longer than 33.3 ms,
and the CPU time of each frame in this process (what other jobs on the machine do not
lengthen; the window system's own time is not in it), with the load average. Needs a
display (``xvfb-run``), as the table paints through the platform's window system.
"""

from __future__ import annotations

import argparse
import os
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
        durations, cpu = [], []
        load = os.getloadavg()[0]
        start = time.perf_counter()
        for value in steps:
            begin, begin_cpu = time.perf_counter(), time.process_time()
            bar.setValue(int(value))
            panel.table.viewport().repaint()
            app.processEvents()  # the thumbnails asked for are read, and painted on the next frame
            durations.append(time.perf_counter() - begin)
            cpu.append(time.process_time() - begin_cpu)
        total = time.perf_counter() - start
        panel.close_library()
        panel.close()
    wall_ms, cpu_ms = 1e3 * np.array(durations), 1e3 * np.array(cpu)
    slow = int(np.count_nonzero(wall_ms > 1e3 / 30))
    print(
        f"panel {width}x{height}, {rows} rows, {args.frames} frames top to bottom ({rows / args.frames:.1f} rows a "
        f"frame), load average {load:.1f}: {args.frames / total:.1f} frames per second over the scroll"
    )
    print(
        f"  a frame's wall clock: median {np.median(wall_ms):.1f} ms, 95th percentile "
        f"{np.percentile(wall_ms, 95):.1f}, 99th {np.percentile(wall_ms, 99):.1f}, slowest {wall_ms.max():.1f}; "
        f"{slow} of {args.frames} frames over 33.3 ms"
    )
    print(
        f"  a frame's CPU time: median {np.median(cpu_ms):.1f} ms, 95th percentile {np.percentile(cpu_ms, 95):.1f}, "
        f"slowest {cpu_ms.max():.1f}"
    )


if __name__ == "__main__":
    main()
