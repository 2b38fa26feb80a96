"""``python -m gmr_studio.app.tools.view_bench``: the 3D view's frame rate against a bare VTK widget.

Run under ``xvfb-run`` (software OpenGL). For each window size (1280x800, 1920x1080), in
the default layout, with CMU 01_01 (BVH), its 42 C3D markers and the pelvis triads, a joint
selected and the Curves dock shown, it prints side by side:

- **bare**: VTK's own Qt widget (``vtkmodules.qt.QVTKRenderWindowInteractor``, a native
  ``QWidget``) of the app's view size with 38 joints as spheres and a grid, no docks and
  no multisampling, its points moved every frame: the reference every ratio is taken to;
- **default**: ``state.set_frame(f)`` until Qt has processed what follows (every drawable
  moved, the docks updated, the view's render), median over consecutive frames, the same
  frames for every figure;
- **+ axes, trail, labels**, and **+ one comparison layer** (01_01.amc), as ratios to default;
  adding a layer brings the Layers and Error docks to the front (the app's own policy), so
  the Curves tab is raised again for it, and the default layout's Forest and Curves tabs
  before every other figure: each is measured with Curves shown;

measured in :data:`ROUNDS` short rounds, each of them all four in turn on the same frames
(round r on its own share of the take): a figure is the median of its rounds, a ratio the
median of the rounds' own ratios, so that a machine whose speed changes during the run (a
shared one does, from one second to the next) weighs on both sides of each ratio alike
(a few long rounds let the ratios swing from run to run);
- the docks' own costs, each timed alone: the inspector's text, the curves' cursor (moved
  and repainted), the foot contacts' bars (cursor moved and repainted);
- the view's renders a frame in the default figure (one is the aim: every drawable is
  written first, then the view is drawn once).

Each figure is given twice: wall time (with fps) and the process's CPU time per frame, all
threads (on a machine shared with other work the wall time includes waiting for a core).

The view's widget is native unless ``--kind framebuffer`` (the Wayland fallback,
:mod:`app.scene.render_widget`); the base is fixed per process, so the bench runs the
framebuffer kind in a child process and prints it in the same table.
"""

from __future__ import annotations

import argparse
import json
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
SIZES = ((1280, 800), (1920, 1080))


def _median_ms(seconds: list[float]) -> float:
    return float(1000 * np.median(seconds))


WARM_UP = 8  # untimed updates before each figure
ROUNDS = 20  # every figure measured in this many rounds, in turn (see the module docstring)
# every figure over the same frames (what is drawn changes along the take: markers, flagged
# joints), so that a ratio compares the same poses with and without what it adds
FIRST = 100


def _timed(step, count: int, warm_up: int = WARM_UP) -> list[float]:
    """[wall ms, CPU ms]: medians over ``count`` calls of ``step(i)`` after ``warm_up``
    untimed ones. CPU is the process's, every thread (Mesa's software rasteriser renders in
    threads of this process): on a machine shared with other work the wall time grows with
    the wait for a core, the CPU time much less, so the two together say what the frame costs."""
    for i in range(warm_up):
        step(i)
    wall, cpu = [], []
    for i in range(warm_up, warm_up + count):
        start, start_cpu = time.perf_counter(), time.process_time()
        step(i)
        cpu.append(time.process_time() - start_cpu)
        wall.append(time.perf_counter() - start)
    return [_median_ms(wall), _median_ms(cpu)]


def _frames(app, state, first: int, count: int) -> list[float]:
    """[wall ms, CPU ms] median per frame update of ``count`` consecutive frames from ``first``."""

    def step(i: int) -> None:
        state.set_frame((first - WARM_UP + i) % state.n_frames)
        app.processEvents()

    return _timed(step, count)


def bare_reference(app, width: int, height: int, frames: int, motion_positions: np.ndarray) -> list[float]:
    """[wall ms, CPU ms]: the median frame of VTK's native Qt widget showing 38 spheres and a grid."""
    import pyvista as pv
    from PyQt6.QtWidgets import QWidget
    from vtkmodules.qt.QVTKRenderWindowInteractor import QVTKRenderWindowInteractor
    from vtkmodules.vtkRenderingCore import vtkActor, vtkGlyph3DMapper, vtkPolyDataMapper, vtkRenderer

    window = QWidget()
    widget = QVTKRenderWindowInteractor(window)
    widget.resize(width, height)
    window.resize(width, height)
    renderer = vtkRenderer()
    renderer.SetBackground(0.16, 0.17, 0.20)
    widget.GetRenderWindow().AddRenderer(renderer)
    widget.GetRenderWindow().SetMultiSamples(0)
    joints = pv.PolyData(np.array(motion_positions[0, :38]))
    mapper = vtkGlyph3DMapper()
    mapper.SetInputData(joints)
    size = float(np.ptp(motion_positions[0], axis=0).max())
    mapper.SetSourceData(pv.Sphere(radius=0.016 * size, theta_resolution=16, phi_resolution=12))
    mapper.SetScaling(False)
    actor = vtkActor()
    actor.SetMapper(mapper)
    renderer.AddActor(actor)
    grid = pv.Plane(
        center=(0, float(motion_positions[..., 1].min()), 0),
        direction=(0, 1, 0),
        i_size=6 * size,
        j_size=6 * size,
        i_resolution=24,
        j_resolution=24,
    )
    grid_actor = vtkActor()
    grid_mapper = vtkPolyDataMapper()
    grid_mapper.SetInputData(grid.extract_all_edges())
    grid_actor.SetMapper(grid_mapper)
    renderer.AddActor(grid_actor)
    window.show()
    widget.show()
    widget.Initialize()
    renderer.ResetCamera()
    app.processEvents()
    points = joints.points

    def step(f: int) -> None:
        points[:] = motion_positions[f % len(motion_positions), :38]
        joints.GetPoints().Modified()
        widget.update()
        app.processEvents()

    times = _timed(step, frames)
    widget.Finalize()
    window.close()
    return times


def _dock_costs(app, window, frames: int) -> dict[str, float]:
    """Median ms of each dock's own frame update, called alone (and repainted at once)."""
    state = window.state
    window.contacts_dock.show()
    app.processEvents()
    costs: dict[str, list[float]] = {"inspector text": [], "curves cursor": [], "contact bars": []}
    strip = window.contact_bars.strip
    plot = window.curves.plot
    for f in range(100, 100 + frames):
        state.frame = f  # the state's frame without its signal: only the dock runs
        for name, update in (
            ("inspector text", lambda: window.inspector._refresh()),
            ("curves cursor", lambda f=f: (plot.set_cursor(f), plot.plot_widget.viewport().repaint())),
            ("contact bars", lambda f=f: (strip._on_frame_changed(f), strip.repaint())),
        ):
            start = time.perf_counter()
            update()
            costs[name].append(time.perf_counter() - start)
    window.contacts_dock.hide()
    app.processEvents()
    return {name: _median_ms(values) for name, values in costs.items()}


def _docks_shown(window) -> list[str]:
    """The titles of the docks on screen (shown and not behind another tab), sorted."""
    from PyQt6.QtWidgets import QDockWidget

    from gmr_studio.app.docks.frame_follow import seen

    return sorted(dock.windowTitle() for dock in window.findChildren(QDockWidget) if seen(dock))


def _raise(app, *docks) -> list[str]:
    """Bring ``docks`` to the front of their tabs (a layer added raises the Error and Layers
    tabs over Curves and Forest); the titles of the docks then shown."""
    for dock in docks:
        dock.show()
        dock.raise_()
    app.processEvents()
    return _docks_shown(docks[0].window())


def measure(width: int, height: int, frames: int, bare: list[float] | None, rounds: int = ROUNDS) -> dict:
    """Every figure at one window size, in this process (the view of this process's kind):
    [wall ms, CPU ms] medians over ``rounds`` rounds of ``frames / rounds`` frames each, and
    the rounds' own ratios (``ratios``: name -> [wall, CPU]). ``bare`` given: the parent's
    reference, not measured again."""
    from gmr_studio.app.model import pelvis_recovery
    from gmr_studio.app.model.loading import load_snapshot
    from gmr_studio.app.scene import render_widget
    from gmr_studio.app.tools.bench import bench_window, close_bench_window

    data = shared_data_dir()
    app, window, scratch = bench_window(width, height)
    window.files.open_path(str(data / BVH), markers=str(data / C3D), ask=False, wait=True)
    state = window.state
    pelvis_recovery.recover_pelvis_frames(state, quiet=True)
    state.select(state.motion.joint_index("LeftHand"))
    window.curves_dock.show()
    app.processEvents()
    view = window.view.interactor
    figures = {
        "kind": render_widget.current_kind(),
        "view": (view.width(), view.height()),
        "share": view.width() * view.height() / (window.width() * window.height()),
        "markers": state.marker_overlay.markers.n_markers,
        "pelvis": state.pelvis is not None,
    }
    other = load_snapshot(data / AMC)
    block = max(frames // rounds, 1)
    renders: list[int] = []
    render_window = window.view.scene.plotter.ren_win
    observer = render_window.AddObserver("EndEvent", lambda *_: renders.append(1))
    default_renders = default_steps = 0
    measured: dict[str, list[list[float]]] = {name: [] for name in ("bare", "default", "overlays", "layer")}
    for index in range(rounds):
        first = FIRST + index * block  # every figure of the round over these frames
        reference = bare if bare is not None else bare_reference(app, *figures["view"], block, state.positions)
        measured["bare"].append(reference)
        figures["docks shown"] = _raise(app, window.forest_dock, window.curves_dock)
        before = len(renders)
        measured["default"].append(_frames(app, state, first, block))
        default_renders += len(renders) - before
        default_steps += WARM_UP + block
        for name in ("axes", "trails", "labels"):
            state.set_overlay(name, True)
        measured["overlays"].append(_frames(app, state, first, block))
        for name in ("axes", "trails", "labels"):
            state.set_overlay(name, False)
        window.layers.add(other, data / AMC, "cmu")
        app.processEvents()
        figures["docks shown with the layer"] = _raise(app, window.curves_dock)
        measured["layer"].append(_frames(app, state, first, block))
        window.layers.remove(0)
        app.processEvents()
    render_window.RemoveObserver(observer)
    figures["renders a frame"] = default_renders / max(default_steps, 1)
    for name, values in measured.items():
        figures[name] = np.median(np.array(values), axis=0).tolist()
    figures["ratios"] = {
        name: np.median(np.array(measured[name]) / np.array(measured[reference]), axis=0).tolist()
        for name, reference in (("default", "bare"), ("overlays", "default"), ("layer", "default"))
    }
    figures["rounds"] = rounds
    figures["docks"] = _dock_costs(app, window, min(frames, 200))
    close_bench_window(window, scratch)
    return figures


def report(figures: dict) -> None:
    """Print one size's figures: wall ms, fps and the ratio, then CPU ms and its ratio (the
    ratios: medians of the rounds' own, so not always the quotient of the two medians)."""
    width, height = figures["view"]
    print(
        f"  view {width}x{height} ({figures['share']:.0%} of the window, {figures['kind']} widget), "
        f"{figures['markers']} markers, pelvis triads {'on' if figures['pelvis'] else 'off'}, "
        f"{figures['rounds']} rounds"
    )
    rows = (  # (label, figure, the figure it is a ratio to)
        ("bare VTK widget, 38 spheres + grid", "bare", None),
        ("default overlays, Curves shown", "default", "bare"),
        ("+ axes, trail, labels", "overlays", "default"),
        ("+ one comparison layer", "layer", "default"),
    )
    print(f"  {'':<38} {'wall':>10} {'':>9}  {'':15}  {'CPU':>8}")
    for label, name, reference in rows:
        wall, cpu = figures[name]
        ratio = cpu_ratio = ""
        if reference is not None:
            wall_ratio, cpu_ratio_value = figures["ratios"][name]
            ratio, cpu_ratio = f"{wall_ratio:5.2f}x {reference}", f"{cpu_ratio_value:5.2f}x"
        print(f"  {label:<38} {wall:7.2f} ms  {1000 / wall:5.0f} fps  {ratio:15}  {cpu:5.2f} ms  {cpu_ratio}")
    docks = ", ".join(f"{name} {ms:.2f} ms" for name, ms in figures["docks"].items())
    print(f"  docks, each alone: {docks}")
    print(f"  renders a frame (default figure): {figures['renders a frame']:.2f}")
    shown, with_layer = (", ".join(figures[key]) for key in ("docks shown", "docks shown with the layer"))
    print(f"  docks shown: {shown}; with the layer: {with_layer}")


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m gmr_studio.app.tools.view_bench", description=__doc__.splitlines()[0]
    )
    parser.add_argument("--frames", type=int, default=300, help="frames timed per figure (over all rounds)")
    parser.add_argument("--rounds", type=int, default=ROUNDS, help="rounds every figure is measured in, in turn")
    parser.add_argument("--kind", choices=("native", "framebuffer"), default="native")
    parser.add_argument("--size", help="one WxH instead of both sizes")
    parser.add_argument("--bare", help="(internal) the bare reference measured by the parent: WALL,CPU ms")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if not (shared_data_dir() / BVH).exists():
        print(f"the CMU files are not in {shared_data_dir()}: nothing to measure", file=sys.stderr)
        return 2
    from gmr_studio.app.scene import render_widget

    render_widget.interactor_class(args.kind)
    sizes = [tuple(int(v) for v in args.size.split("x"))] if args.size else list(SIZES)
    for width, height in sizes:
        bare = [float(v) for v in args.bare.split(",")] if args.bare else None
        figures = measure(width, height, args.frames, bare, args.rounds)
        if args.child:
            print(json.dumps(figures, default=float))
            continue
        print(f"{width}x{height} window:")
        report(figures)
        if args.kind == "native":
            command = [sys.executable, "-m", "gmr_studio.app.tools.view_bench", "--kind", "framebuffer", "--child"]
            bare_text = ",".join(map(str, figures["bare"]))
            command += ["--size", f"{width}x{height}", "--frames", str(args.frames), "--rounds", str(args.rounds)]
            command += ["--bare", bare_text]
            child = subprocess.run(command, capture_output=True, text=True, env=dict(os.environ))
            if child.returncode == 0:
                framebuffer = json.loads(child.stdout.strip().splitlines()[-1])
                print("  the same in the framebuffer widget (the Wayland fallback):")
                report(framebuffer)
            else:
                last = child.stderr.strip().splitlines()[-1:]
                print(f"  framebuffer widget: failed (exit status {child.returncode}; {last})")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
