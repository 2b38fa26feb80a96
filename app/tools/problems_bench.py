"""What the Problems dock's checks cost on a long take, printed (asserts nothing).

``python -m gmr_studio.app.tools.problems_bench [--frames N]``: CMU 01_01.bvh tiled to N
frames (100,000 by default) in the GMR form the app holds; the time from opening it to the
findings being published by :class:`app.model.problems.Problems` (the worker thread: wall
clock, and the process's CPU over all threads), the per-frame severity levels, and the
timeline's flag spans (computed once per change, then cached; painted at every frame).
Runs without a display (Qt's offscreen platform).
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=100_000)
    args = parser.parse_args()
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    from PyQt6.QtCore import QSettings
    from PyQt6.QtWidgets import QApplication

    from gmr_studio.app.docks.range_slider import RangeSlider
    from gmr_studio.app.model.problems import Problems
    from gmr_studio.app.model.state import Snapshot, StudioState
    from gmr_studio.core.benchmark.compare_speed import tiled
    from gmr_studio.core.formats import read_motion
    from gmr_studio.core.kinematics.convention import pre_from_post
    from gmr_studio.core.shared_data import shared_file

    app = QApplication.instance() or QApplication([])
    motion = pre_from_post(tiled(read_motion(shared_file("cmu/subject01/01_01.bvh")), args.frames))
    snapshot = Snapshot.of(motion)
    state = StudioState()
    with tempfile.TemporaryDirectory() as folder:
        problems = Problems(state, QSettings(f"{folder}/settings.ini", QSettings.Format.IniFormat))
        wall, cpu = time.perf_counter(), time.process_time()
        state.open_document(snapshot, None)
        problems.wait()
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    found = len(problems.findings)
    print(f"{motion.n_frames} frames x {motion.n_joints} joints (CMU 01_01.bvh tiled), {found} findings")
    print(f"checks until published: wall {wall:.2f} s, CPU {cpu:.2f} s (all threads)")
    start = time.perf_counter()
    levels = problems.frame_levels()
    print(f"per-frame levels: {1e3 * (time.perf_counter() - start):.1f} ms")
    slider = RangeSlider()
    slider.resize(900, 24)
    slider.setRange(0, motion.n_frames - 1)
    slider.set_levels(levels)
    best = float("inf")
    for _ in range(10):
        slider._spans = None
        start = time.perf_counter()
        spans = slider.flag_spans()
        best = min(best, time.perf_counter() - start)
    print(f"timeline flag spans (900 px, {len(spans)} spans): best {1e3 * best:.2f} ms once per change")
    del app


if __name__ == "__main__":
    main()
