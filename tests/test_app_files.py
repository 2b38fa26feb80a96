"""Files in the real window: open (ASF/AMC, C3D), bad files, save, export, drop, video,
unsaved edits, long loads, remembered settings. Every test gets a fresh main window that
fails the test if it leaks a window or a VTK render window."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtCore import Qt

from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.kinematics.fk import world_positions
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.conftest import shared_path

pytestmark = pytest.mark.gui
studio = app_fixtures.studio  # the fixture: a main window that must not leak


def test_a_bad_file_leaves_the_document_as_it_was(qtbot, studio, tmp_path):
    open_file(studio, demo_folder() / MOTION_FILE)
    before = studio.state.snapshot
    bad = tmp_path / "bad.bvh"
    bad.write_text("HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 zero\n}\n")
    studio.files.open_path(str(bad), ask=False, wait=True)
    assert studio.state.snapshot is before and studio.state.path.name == MOTION_FILE
    assert f"{bad}:4:" in studio.status.text()


def test_save_as_gmr_and_export_bvh_round_trip(qtbot, studio, tmp_path):
    from gmr_studio.core.formats import read_motion
    from gmr_studio.core.formats.bvh_export import bvh_export, tree_file_name

    open_file(studio, demo_folder() / MOTION_FILE)
    state = studio.state
    from gmr_studio.app.model import commands

    commands.split_here(state, state.motion.joint_index("lfoot"))
    assert studio.isWindowModified()
    target = tmp_path / "edited.gmr"
    assert studio.files.save_to(target)
    assert not studio.isWindowModified() and "edited.gmr" in studio.windowTitle()
    size = state.motion.size

    def same_positions(path, names=None):
        motion = read_motion(path)
        order = [motion.joint_index(name) for name in (names or state.motion.names)]
        np.testing.assert_allclose(world_positions(motion)[:, order], state.positions, atol=1e-9 * size)

    same_positions(target)  # files list each tree depth first: joints compared by name
    assert studio.exports.export_bvh(tmp_path / "forest.bvh")  # one file, the trees under a World root
    assert "World" in studio.status.text()
    same_positions(tmp_path / "forest.bvh", bvh_export(state.motion).names)  # leaves are End Sites
    assert studio.exports.export_bvh(tmp_path / "trees.bvh", per_tree=True)
    first = read_motion(tree_file_name(tmp_path / "trees.bvh", "root"))
    second = read_motion(tree_file_name(tmp_path / "trees.bvh", "lfoot"))
    assert first.n_joints + second.n_joints >= state.motion.n_joints
    commands.join_everything(state)
    assert studio.exports.export_bvh(tmp_path / "one.bvh")
    same_positions(tmp_path / "one.bvh", bvh_export(state.motion).names)  # dummies where siblings differ
    assert str(target.resolve()) in studio.files.recent_files()


def test_unsaved_edits_are_offered_for_saving(qtbot, studio, monkeypatch, tmp_path):
    from PyQt6.QtWidgets import QMessageBox

    from gmr_studio.app.model import commands

    open_file(studio, demo_folder() / MOTION_FILE)
    commands.split_everything(studio.state)
    edited = studio.state.snapshot
    answers = iter([QMessageBox.StandardButton.Cancel, QMessageBox.StandardButton.Discard])
    monkeypatch.setattr(QMessageBox, "question", lambda *args, **kwargs: next(answers))
    studio.files.open_path(str(demo_folder() / MOTION_FILE), wait=True)
    assert studio.state.snapshot is edited  # cancelled
    studio.files.open_path(str(demo_folder() / MOTION_FILE), wait=True)
    assert studio.state.snapshot is not edited and not studio.state.modified


def test_closing_with_unsaved_edits_asks_and_cancel_keeps_the_window(qtbot, studio, monkeypatch):
    from PyQt6.QtWidgets import QMessageBox

    from gmr_studio.app.model import commands

    open_file(studio, demo_folder() / MOTION_FILE)
    commands.split_everything(studio.state)
    edited = studio.state.snapshot
    asked = []

    def cancel(*args, **kwargs):
        asked.append(args)
        return QMessageBox.StandardButton.Cancel

    monkeypatch.setattr(QMessageBox, "question", cancel)
    assert studio.close() is False
    assert len(asked) == 1 and studio.isVisible()
    assert studio.state.snapshot is edited and studio.state.modified


def test_dropping_a_file_opens_it(qtbot, studio):
    from PyQt6.QtCore import QMimeData, QPointF, QUrl
    from PyQt6.QtGui import QDropEvent

    data = QMimeData()
    data.setUrls([QUrl.fromLocalFile(str(demo_folder() / MOTION_FILE))])
    event = QDropEvent(
        QPointF(10, 10), Qt.DropAction.CopyAction, data, Qt.MouseButton.NoButton, Qt.KeyboardModifier.NoModifier
    )
    studio.dropEvent(event)
    qtbot.waitUntil(lambda: studio.state.motion is not None and not studio.files.busy(), timeout=5000)
    assert studio.state.path.name == MOTION_FILE


def test_video_export_writes_every_sampled_frame(qtbot, studio, tmp_path):
    import imageio_ffmpeg

    from gmr_studio.app.media.video import export_video, video_frames

    open_file(studio, demo_folder() / MOTION_FILE)
    studio.view.interactor.setFixedSize(320, 240)
    qtbot.wait(50)
    seen = []
    written = export_video(
        studio.view.scene, tmp_path / "walk.mp4", fps=10, speed=2.0, progress=lambda d, t: seen.append(d) or True
    )
    expected = len(video_frames(480, 120, 10, 2.0))
    assert written == expected == 20 and seen[-1] == expected
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(tmp_path / "walk.mp4"))
    assert frames == expected


def test_asf_amc_with_c3d_markers(qtbot, studio):
    """ASF/AMC opens like any motion (the ASF beside it) and the C3D's markers align to it."""
    amc = shared_path("cmu/subject01/01_01.amc")
    open_file(studio, amc, shared_path("cmu/subject01/01_01.c3d"))
    state = studio.state
    assert state.motion.n_frames == 2751 and "lfemur" in state.motion.names
    overlay = state.marker_overlay
    assert overlay is not None and overlay.alignment.frame_offset == 0
    assert "ASF unit (in / 0.45)" in overlay.alignment.method
    assert "Markers" in studio.inspector.text() and "42" in studio.inspector.text()
    # LANK follows the ankle (the end of ltibia) within a few centimetres all through
    ankle = state.positions[:, state.motion.joint_index("ltibia")]
    lank = overlay.positions[:, overlay.markers.labels.index("LANK")]
    millimetres = np.linalg.norm(lank - ankle, axis=1) * 25.4 / 0.45
    assert np.nanmedian(millimetres) < 75 and np.nanstd(millimetres) < 5


def test_a_long_load_shows_progress_and_keeps_the_window_responsive(qtbot, studio, monkeypatch):
    import time

    from PyQt6.QtCore import QTimer
    from PyQt6.QtWidgets import QProgressDialog

    from gmr_studio.app.model import loading

    real = loading.load_snapshot

    def slow(path):
        time.sleep(1.0)  # a big file: the reader runs in a worker thread
        return real(path)

    monkeypatch.setattr(loading, "load_snapshot", slow)
    ticks = []
    timer = QTimer()
    timer.timeout.connect(lambda: ticks.append(studio.findChild(QProgressDialog) is not None))
    timer.start(50)
    studio.files.open_path(str(demo_folder() / MOTION_FILE), ask=False)
    assert studio.files.busy() and studio.state.motion is None
    qtbot.waitUntil(lambda: studio.state.motion is not None, timeout=10000)
    timer.stop()
    assert len(ticks) >= 10  # the event loop kept running during the load
    assert any(ticks)  # with a progress dialog up
    qtbot.waitUntil(lambda: studio.findChild(QProgressDialog) is None, timeout=2000)


def test_a_bad_file_is_explained_in_a_dialog(qtbot, studio, tmp_path):
    from PyQt6.QtCore import QTimer
    from PyQt6.QtWidgets import QApplication, QMessageBox

    bad = tmp_path / "broken.gmr"
    bad.write_text("GMR 1\nHIERARCHY\nROOT a\n{\n OFFSET 0 0\n}\n")
    studio.files.quiet = False
    seen = []

    def read_and_close() -> None:
        box = QApplication.activeModalWidget()
        if isinstance(box, QMessageBox):
            seen.append((box.text(), box.detailedText()))
            box.close()
        else:
            QTimer.singleShot(50, read_and_close)

    QTimer.singleShot(50, read_and_close)
    studio.files.open_path(str(bad), ask=False, wait=True)
    assert seen, "no error dialog"
    text, details = seen[0]
    assert "broken.gmr" in text and "line 6, column 1" in text and "expected a number for OFFSET" in text
    assert details.startswith(f"{bad}:6:1:")
    assert studio.state.motion is None


def test_overlays_and_playback_settings_are_remembered(qtbot, tmp_path):
    from PyQt6.QtCore import QSettings

    from gmr_studio.app.window.main_window import MainWindow

    path = str(tmp_path / "settings.ini")
    first = MainWindow(settings=QSettings(path, QSettings.Format.IniFormat))
    qtbot.addWidget(first)
    first.actions["overlay_axes"].setChecked(True)
    first.actions["overlay_ground"].setChecked(False)
    first.player.set_speed(0.5)
    first.close()
    second = MainWindow(settings=QSettings(path, QSettings.Format.IniFormat))
    qtbot.addWidget(second)
    assert second.state.overlays["axes"] and not second.state.overlays["ground"]
    assert second.player.speed == 0.5 and second.timeline.speed_box.currentText() == "0.5x"
    second.close()
