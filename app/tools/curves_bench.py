"""``python -m gmr_studio.app.tools.curves_bench``: what the curves dock costs (prints only; run under xvfb-run).

On CMU 01_01 tiled to 100,000 frames (38 joints), with the world position of LeftFoot,
RightHand and Head plotted (9 curves of 100,000 points each, the whole range in view):

1. Drawing: computing the curves, handing them to the plot and repainting it.
2. The same plot in a window of its own: moving its cursor one frame and repainting (what
   playback asks of it, without the cost of composing the main window, whose OpenGL 3D
   view makes every repaint of any widget in it a full composition under Xvfb).
3. The whole window during playback: ``state.set_frame(f)`` and the events that follow (3D
   view, timeline, inspector, contact bars, curves) with the curves dock shown and hidden;
   the difference of the medians is what the curves add to a frame update. Reported as wall
   time (``time.perf_counter``) and as the CPU time of the process (``time.process_time``, all
   its threads, the 3D view's llvmpipe rasteriser included), which waiting for a core on a
   loaded machine does not inflate; ``--repeats`` comparisons in one run.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections.abc import Sequence

import numpy as np

from gmr_studio.core.shared_data import shared_data_dir

BVH = "cmu/subject01/01_01.bvh"


def _median_ms(seconds: list[float]) -> tuple[float, float]:
    ms = 1000 * np.asarray(seconds)
    return float(np.median(ms)), float(np.percentile(ms, 95))


def _print(label: str, seconds: list[float]) -> float:
    median, p95 = _median_ms(seconds)
    print(f"{label:<58} median {median:7.2f} ms   p95 {p95:7.2f} ms")
    return median


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m gmr_studio.app.tools.curves_bench", description=__doc__.splitlines()[0]
    )
    parser.add_argument("--frames", type=int, default=100_000, help="frames of the motion plotted")
    parser.add_argument("--updates", type=int, default=300, help="frame updates timed")
    parser.add_argument("--warmup", type=int, default=10, help="untimed frame updates before each timed block")
    parser.add_argument("--repeats", type=int, default=3, help="shown/hidden comparisons of the window's updates")
    parser.add_argument("--profile", action="store_true", help="print a profile of the window's frame updates")
    args = parser.parse_args(argv)
    if not (shared_data_dir() / BVH).exists():
        print(f"the CMU files are not in {shared_data_dir()}: nothing to measure", file=sys.stderr)
        return 2
    from gmr_studio.app.docks.timeplot import TimePlot
    from gmr_studio.app.model.state import Snapshot
    from gmr_studio.app.tools.bench import bench_window, close_bench_window
    from gmr_studio.core.formats import load_gmr

    base = load_gmr(shared_data_dir() / BVH)
    index = np.tile(np.arange(base.n_frames), -(-args.frames // base.n_frames))[: args.frames]
    motion = base.frame_slice(index)
    app, window, scratch = bench_window(1400, 1000)
    state, dock = window.state, window.curves
    state.open_document(Snapshot.of(motion), None)
    state.select(motion.joint_index("Head"))
    dock.set_quantity("world")
    for name in ("LeftFoot", "RightHand"):
        dock.pinned.append(motion.joint_index(name))
    app.processEvents()
    dock.refresh(autoscale=True)
    print(f"machine load (1, 5, 15 min): {', '.join(f'{v:.1f}' for v in os.getloadavg())} on {os.cpu_count()} cores")
    print(
        f"01_01 tiled: {motion.n_frames} frames x {motion.n_joints} joints; plot "
        f"{dock.plot.plot_widget.width()}x{dock.plot.plot_widget.height()} px, "
        f"{len(dock.plot.columns)} curves of {dock.plot.values.shape[0]} points"
    )
    draws = []
    for _ in range(5):
        start = time.perf_counter()
        dock.refresh(autoscale=True)
        dock.plot.plot_widget.viewport().repaint()
        draws.append(time.perf_counter() - start)
    _print("draw: compute the curves, plot them, repaint", draws)
    alone = TimePlot()
    alone.resize(dock.plot.width(), dock.plot.height())
    alone.set_curves(dock.plot.frames, dock.plot.columns, dock.plot.values, dock.plot.unit)
    alone.show()
    alone.autoscale()
    app.processEvents()
    moves, moves_cpu = [], []
    for f in range(args.updates):
        start, start_cpu = time.perf_counter(), time.process_time()
        alone.set_cursor(1000 + f)
        app.processEvents()  # the view repaints the strips of the cursor's old and new places
        moves.append(time.perf_counter() - start)
        moves_cpu.append(time.process_time() - start_cpu)
    _print("the same plot in its own window: move the cursor + repaint", moves)
    _print("  the same, CPU time", moves_cpu)
    alone.close()
    if args.profile:
        import cProfile
        import pstats

        with cProfile.Profile() as profile:
            for f in range(50):
                state.set_frame(3000 + f)
                app.processEvents()
        pstats.Stats(profile).sort_stats("cumulative").print_stats(25)
    curves_dock = window.findChild(type(window.history_dock), "curves")
    added = {"wall": [], "cpu": []}
    for repeat in range(args.repeats):
        wall, cpu = _window_updates(
            app, state, curves_dock, args.updates, args.warmup, first=2000 + repeat * 6 * args.updates
        )
        for clock, samples in (("wall", wall), ("cpu", cpu)):
            shown, hidden = (float(np.median(samples[v])) * 1000 for v in (True, False))
            added[clock].append(shown - hidden)
            print(
                f"repeat {repeat + 1}, {clock:>4}: window frame update, dock shown {shown:7.2f} ms, "
                f"hidden {hidden:7.2f} ms, added {shown - hidden:+7.2f} ms"
            )
    for clock in ("wall", "cpu"):
        values = ", ".join(f"{v:+.2f}" for v in added[clock])
        print(
            f"the curves dock adds to a frame update, {clock} time: median {np.median(added[clock]):+.2f} ms "
            f"over {args.repeats} repeats ({values})"
        )
    close_bench_window(window, scratch)
    return 0


def _window_updates(app, state, curves_dock, updates: int, warmup: int, first: int) -> tuple[dict, dict]:
    """Time ``state.set_frame`` + the events that follow, dock shown and hidden in turns
    (so that the machine's load hits both alike): wall (``perf_counter``) and CPU
    (``process_time``, every thread of this process) seconds per update, keyed by shown."""
    wall: dict[bool, list[float]] = {True: [], False: []}
    cpu: dict[bool, list[float]] = {True: [], False: []}
    for block in range(6):
        shown = block % 2 == 0
        curves_dock.setVisible(shown)
        for f in range(warmup):
            state.set_frame(f)
            app.processEvents()
        for f in range(updates // 3):
            start_wall, start_cpu = time.perf_counter(), time.process_time()
            state.set_frame(first + block * updates + f)
            app.processEvents()
            wall[shown].append(time.perf_counter() - start_wall)
            cpu[shown].append(time.process_time() - start_cpu)
    return wall, cpu


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
