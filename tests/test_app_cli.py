"""``gmr-studio`` on the command line: no-display message, screenshots with and without a display."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from gmr_studio.app.arguments import build_arguments, parse_size
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from tests.test_cli import modules_loaded_by

STUDIO = [sys.executable, "-m", "gmr_studio.app.main"]


def headless_env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM")}
    return env


def read_png(path) -> np.ndarray:
    """(H, W, 3) uint8 pixels of a PNG file."""
    from PyQt6.QtGui import QImage

    from gmr_studio.app.media.video import image_pixels

    return image_pixels(QImage(str(path)))


def test_help_is_printed_without_loading_qt_vtk_or_the_numerical_code():
    out, _, loaded = modules_loaded_by("gmr_studio.app.main", "--help")
    assert "--screenshot OUT.png" in out and "--shift-root J" in out
    assert not {"PyQt6", "pyvista", "pyvistaqt", "vtk", "vtkmodules", "pyqtgraph"} & loaded
    assert not {"numba", "scipy", "gmr_studio.core.kinematics", "gmr_studio.core.compare.engine"} & loaded


def test_without_a_display_it_says_how_to_run_and_exits_2():
    result = subprocess.run(STUDIO, capture_output=True, text=True, env=headless_env(), timeout=60)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "no display" in lines[0] and "xvfb-run" in lines[0] and "--screenshot" in lines[0]


def test_an_offscreen_qt_platform_is_no_display():
    env = {**headless_env(), "QT_QPA_PLATFORM": "offscreen"}
    result = subprocess.run(STUDIO, capture_output=True, text=True, env=env, timeout=60)
    assert result.returncode == 2 and "no display" in result.stderr


def test_screenshot_without_a_display_renders_off_screen(tmp_path):
    out = tmp_path / "walk.png"
    result = subprocess.run(
        [*STUDIO, str(demo_folder() / MOTION_FILE), "--screenshot", str(out), "--frame", "120", "--size", "400x300"],
        capture_output=True,
        text=True,
        env=headless_env(),
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    assert "400x300, frame 120" in result.stdout
    image = read_png(out).astype(int)
    assert image.shape == (300, 400, 3)
    blue = np.array([31, 119, 180])
    assert (np.abs(image - blue).max(axis=2) < 40).sum() > 50  # the skeleton's tree colour is there


def test_a_bad_file_on_the_command_line_is_one_line_and_exit_2(tmp_path):
    bad = tmp_path / "bad.gmr"
    bad.write_text("GMR 1\nHIERARCHY\nROOT a\n{\n OFFSET 0 0\n}\n")
    result = subprocess.run(
        [*STUDIO, str(bad), "--screenshot", str(tmp_path / "x.png")], capture_output=True, text=True, env=headless_env()
    )
    assert result.returncode == 2 and result.stderr.startswith(f"{bad}:6:1: expected a number")
    assert not (tmp_path / "x.png").exists()


def test_a_picture_into_a_folder_that_does_not_exist_is_one_line_and_exit_2(tmp_path):
    for flag in ("--screenshot", "--filmstrip"):
        target = tmp_path / "missing" / "x.png"
        result = subprocess.run([*STUDIO, flag, str(target)], capture_output=True, text=True, env=headless_env())
        assert result.returncode == 2 and "Traceback" not in result.stderr
        assert result.stderr.strip() == f"gmr-studio: {target}: the folder {target.parent} does not exist"


def test_size_and_arguments():
    assert parse_size("640x480") == (640, 480)
    with pytest.raises(Exception, match="1280x800"):
        parse_size("big")
    args = build_arguments().parse_args(["a.bvh", "--markers", "m.trc", "--screenshot", "o.png", "--frame", "3"])
    assert (args.file, args.markers, args.screenshot, args.frame) == ("a.bvh", "m.trc", "o.png", 3)


@pytest.mark.gui
def test_screenshot_of_the_whole_window_under_a_display(tmp_path):
    out = tmp_path / "window.png"
    result = subprocess.run(
        [*STUDIO, "--screenshot", str(out), "--window", "--size", "900x600"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    image = read_png(out).astype(int)
    assert image.shape == (600, 900, 3)
    blue = np.array([31, 119, 180])
    assert (np.abs(image - blue).max(axis=2) < 40).sum() > 50
    assert (image.reshape(-1, 3).std(axis=0) > 10).all()  # docks and the view, not one flat colour


def test_a_screenshot_without_a_display_prints_no_x_warning(tmp_path):
    """Issue 21, item 10: VTK renders through EGL without trying X first."""
    out = tmp_path / "demo.png"
    env = headless_env()
    env.pop("VTK_DEFAULT_OPENGL_WINDOW", None)
    result = subprocess.run([*STUDIO, "--screenshot", str(out)], capture_output=True, text=True, env=env, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "X server" not in result.stderr and "WARN" not in result.stderr, result.stderr
    assert read_png(out).shape[2] == 3


@pytest.mark.gui
def test_a_window_screenshot_deletes_its_window_before_it_returns(qtbot, tmp_path, capsys):
    """The window is deleted while the application lives, not left closed for the
    interpreter's teardown: a closed window destroyed with the application's wrapper made
    about one `--screenshot --window` in five end in a segmentation fault after writing."""
    from PyQt6.QtWidgets import QApplication

    from gmr_studio.app.arguments import default_files
    from gmr_studio.app.screenshots import window_screenshot
    from gmr_studio.app.window.main_window import MainWindow

    out = tmp_path / "window.png"
    args = build_arguments().parse_args(["--screenshot", str(out), "--window", "--size", "900x600", "--frame", "5"])
    before = {id(w) for w in QApplication.topLevelWidgets() if isinstance(w, MainWindow)}
    assert window_screenshot(*default_files(args), args, parse_size(args.size)) == 0
    assert capsys.readouterr().out == f"wrote {out} (900x600, frame 5)\n"
    assert read_png(out).shape == (600, 900, 3)
    left = [w for w in QApplication.topLevelWidgets() if isinstance(w, MainWindow) and id(w) not in before]
    assert left == []  # deleted, not only closed
