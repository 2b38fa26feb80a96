"""Defect 6 of issue 13: a video of a range of frames, and the screenshot and video dialogs
suggesting a file name and the folder the last one went to."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtWidgets import QFileDialog

from gmr_studio.app.media import video
from gmr_studio.app.media.video import suggested_name, video_frames
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from tests import app_fixtures
from tests.app_fixtures import open_file

studio = app_fixtures.studio


def test_a_range_of_frames_is_sampled_by_time_within_it():
    whole = video_frames(480, 120, 30, 1.0)
    part = video_frames(480, 120, 30, 1.0, first=120, last=359)
    assert np.array_equal(whole, video_frames(480, 120, 30, 1.0, 0, 479))
    assert part[0] == 120 and part.max() <= 359 and len(part) == 60  # 2 s at 30 fps
    np.testing.assert_array_equal(part, 120 + video_frames(240, 120, 30, 1.0))
    assert len(video_frames(480, 120, 30, 2.0, 100, 99)) == 0


def test_suggested_names_say_the_motion_and_the_frames():
    assert suggested_name("/data/walk.gmr", ".png", 150) == "walk_frame00150.png"
    assert suggested_name("/data/walk.gmr", ".mp4", 0) == "walk.mp4"
    assert suggested_name("/data/walk.gmr", ".mp4", 100, 299) == "walk_frames100-299.mp4"
    assert suggested_name(None, ".png", 0) == "motion_frame00000.png"


@pytest.mark.gui
def test_the_dialogs_suggest_a_name_and_the_last_folder_and_the_video_keeps_to_its_range(
    qtbot, studio, tmp_path, monkeypatch
):
    import imageio_ffmpeg

    open_file(studio, demo_folder() / MOTION_FILE)
    studio.view.interactor.setFixedSize(160, 120)
    studio.state.set_frame(150)
    offered = []
    out = tmp_path / "renders"
    out.mkdir()

    def save_as(parent, title, start, filters):
        offered.append(start)
        return str(out / start.rsplit("/", 1)[-1]), filters

    monkeypatch.setattr(QFileDialog, "getSaveFileName", save_as)
    monkeypatch.setattr(video, "ask_frame_range", lambda parent, n, *a: (100, 159))
    studio.exports.save_screenshot_dialog()
    assert offered[-1].endswith("walk_frame00150.png")
    assert (out / "walk_frame00150.png").exists()
    studio.exports.export_video_dialog(speed=1.0)
    assert offered[-1] == str(out / "walk_frames100-159.mp4"), "the last folder, a name with the range"
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(out / "walk_frames100-159.mp4"))
    assert frames == len(video_frames(480, 120, video.VIDEO_FPS, 1.0, 100, 159)) == 15
    assert studio.state.frame == 150, "the view is left on the frame it showed"
