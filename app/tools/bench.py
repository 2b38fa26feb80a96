"""``python -m gmr_studio.app.tools.bench``: how fast the app is, measured (prints only; run under xvfb-run).

1. Frame update of the view against a bare VTK widget at 1280x800 and 1920x1080, native
   and framebuffer widget, with axes/trail/labels and a comparison layer, and the docks'
   own costs (:mod:`app.tools.view_bench`).
2. Launch to first frame: a fresh ``gmr-studio 01_01.bvh`` process, from before it starts
   to the first rendered frame of the file (interpreter, imports, window, reading, FK).
3. Frame update with and without a comparison layer (01_01.amc over 01_01.bvh, the ghost,
   error colours, lines, legend, error plot): measured in alternating blocks in one run, so
   that the load of a busy machine falls on both alike; medians and their ratio, for wall time
   and for the main thread's CPU time (``time.thread_time``, less sensitive to other jobs).
4. A long take (01_01 tiled to 100,000 frames): the FK cache, every edit as the core
   operation and as the app's undoable edit, memory and ``gmr check``, each beside its
   yardstick (:mod:`app.tools.take_bench`, also on its own); opening a long
   take of every format against its reader's floor (:mod:`app.tools.open_bench`).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from collections.abc import Sequence

import numpy as np

from gmr_studio.core.shared_data import shared_data_dir

BVH = "cmu/subject01/01_01.bvh"
C3D = "cmu/subject01/01_01.c3d"
AMC = "cmu/subject01/01_01.amc"


def _summary(label: str, seconds: np.ndarray) -> None:
    ms = 1000 * np.asarray(seconds)
    median, p95 = np.median(ms), np.percentile(ms, 95)
    rates = f"{1000 / median:5.0f} fps (p95: {1000 / p95:4.0f})"
    print(f"{label:<46} median {median:6.2f} ms   p95 {p95:6.2f} ms   -> {rates}")


_APPLICATION: list = []  # the process's QApplication, held for the whole run


def application():
    """The process's ``QApplication``, created once and held until exit.

    A bench function must not own it as a local: freed when that function returns, it takes
    every widget's C++ side with it while their Python wrappers live on, and sip's clean-up
    of those wrappers then crashes (a segmentation fault at random, as the cycle collector
    runs)."""
    from PyQt6.QtWidgets import QApplication

    if not _APPLICATION:
        _APPLICATION.append(QApplication.instance() or QApplication(sys.argv[:1]))
    return _APPLICATION[0]


def bench_window(width: int, height: int):
    """(app, window, settings path): a main window of that size, shown, quiet, on a fresh
    settings file (a layout saved by an earlier run would change the view's size or hide a
    dock). :func:`close_bench_window` closes it and removes the file."""
    from PyQt6.QtCore import QSettings

    from gmr_studio.app.window.main_window import MainWindow

    app = application()
    scratch = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"gmr-studio-bench-{os.getpid()}.ini")
    if os.path.exists(scratch):
        os.remove(scratch)
    window = MainWindow(settings=QSettings(scratch, QSettings.Format.IniFormat))
    window.settings.clear()
    window.files.quiet = True
    window.resize(width, height)
    window.show()
    app.processEvents()
    return app, window, scratch


def close_bench_window(window, scratch: str) -> None:
    """Close a :func:`bench_window` without asking to save, delete it at once
    (:meth:`MainWindow.close_now`), and remove its settings file."""
    window.close_now()
    if os.path.exists(scratch):
        os.remove(scratch)


def bench_comparison(frames: int, rounds: int = 4) -> None:
    """Frame update without and with a comparison layer, alternating blocks (item 3)."""
    from gmr_studio.app.model.loading import load_snapshot

    data = shared_data_dir()
    app, window, scratch = bench_window(1280, 800)
    window.files.open_path(str(data / BVH), ask=False, wait=True)
    state = window.state
    state.select(state.motion.joint_index("LeftHand"))
    other = load_snapshot(data / AMC)
    times: dict[bool, list[float]] = {False: [], True: []}
    main_thread: dict[bool, list[float]] = {False: [], True: []}
    block = max(frames // rounds, 10)
    for round_ in range(rounds):
        for with_layer in (False, True):
            if with_layer:
                window.layers.add(other, data / AMC, "cmu")
            first = 1 + (2 * round_ + with_layer) * block
            for f in range(first - 10, first):  # warm up
                state.set_frame(f % state.n_frames)
                app.processEvents()
            for f in range(first, first + block):
                start, start_thread = time.perf_counter(), time.thread_time()
                state.set_frame(f % state.n_frames)
                app.processEvents()
                times[with_layer].append(time.perf_counter() - start)
                main_thread[with_layer].append(time.thread_time() - start_thread)
            if with_layer:
                window.layers.remove(0)
    _summary("set frame + render, no comparison", np.array(times[False]))
    _summary("set frame + render, comparison layer (amc)", np.array(times[True]))
    ratio = np.median(times[True]) / np.median(times[False])
    print(f"{'  with / without (medians)':<46} {ratio:6.3f}")
    cpu_without, cpu_with = (1000 * np.median(main_thread[key]) for key in (False, True))
    print(f"{'  main-thread CPU per frame: without / with':<46} median {cpu_without:6.2f} ms / {cpu_with:6.2f} ms")
    print(f"{'  with / without (main-thread CPU medians)':<46} {cpu_with / cpu_without:6.3f}")
    close_bench_window(window, scratch)


def bench_launch() -> None:
    path = shared_data_dir() / BVH
    start = time.time()
    result = subprocess.run(
        [sys.executable, "-m", "gmr_studio.app.main", str(path), "--first-frame-time"],
        capture_output=True,
        text=True,
        check=False,
    )
    if result.returncode != 0:
        print(f"launch: failed: {result.stderr.strip()}")
        return
    shown = float(result.stdout.strip().splitlines()[-1])
    print(f"{'launch to first frame of 01_01.bvh':<46} {shown - start:6.2f} s (new process, window shown)")


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m gmr_studio.app.tools.bench", description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=600, help="frames played for the frame-update timing")
    parser.add_argument("--edit-frames", type=int, default=100_000, help="frames of the long take edited")
    parser.add_argument("--rounds", type=int, default=5, help="rounds of the long take's timings (best of)")
    parser.add_argument("--frames-only", action="store_true", help="only the frame-update timing")
    args = parser.parse_args(argv)
    if not (shared_data_dir() / BVH).exists():
        print(f"the CMU files are not in {shared_data_dir()}: nothing to measure", file=sys.stderr)
        return 2
    from gmr_studio.app.tools import view_bench

    view_bench.main(["--frames", str(args.frames)])  # the view against a bare VTK widget
    if args.frames_only:
        return 0
    bench_comparison(args.frames)
    bench_launch()
    from gmr_studio.app.tools import open_bench, take_bench

    take_bench.bench_take(args.edit_frames, args.rounds)
    open_bench.bench_open(args.edit_frames, args.rounds)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
