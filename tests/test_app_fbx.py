"""FBX files in the real window: twenty opened in a row (the app survives each, shows each
file's skeleton and remembers it among the recent files), a bad one in between leaves the
document as it was, and the Open dialog offers ``.fbx``."""

from __future__ import annotations

import itertools

import pytest

from gmr_studio.app.model.loading import file_filter, motion_suffixes
from gmr_studio.core.formats import read_motion
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.conftest import shared_files

pytestmark = pytest.mark.gui
studio = app_fixtures.studio  # the fixture: a main window that must not leak
FBX_FILES = [p.values[0] for p in shared_files("fbx/*.fbx") if p.values[0] is not None]


def test_the_open_dialog_offers_fbx():
    assert "*.fbx" in file_filter(motion_suffixes(), "Motion files")


def test_twenty_fbx_files_open_in_a_row(qtbot, studio, tmp_path):
    if not FBX_FILES:
        pytest.skip("no shared data")
    joints = {path: read_motion(path).n_joints for path in FBX_FILES}
    bad = tmp_path / "truncated.fbx"
    bad.write_bytes(FBX_FILES[0].read_bytes()[:5000])
    for k, path in enumerate(itertools.islice(itertools.cycle(FBX_FILES), 20)):
        open_file(studio, path)
        assert studio.state.motion.n_joints == joints[path]
        assert studio.state.positions.shape[:2] == (studio.state.motion.n_frames, joints[path])
        if k == 9:  # a bad file in the middle: one line in the status bar, the document kept
            before = studio.state.snapshot
            studio.files.open_path(str(bad), ask=False, wait=True)
            assert studio.state.snapshot is before
            assert str(bad) in studio.status.text() and "truncated" in studio.status.text()
    assert studio.isVisible()
    assert str(FBX_FILES[(20 - 1) % len(FBX_FILES)]) == studio.files.recent_files()[0]


def test_an_fbx_compares_as_a_layer(qtbot, studio):
    from PyQt6.QtWidgets import QApplication

    if not FBX_FILES:
        pytest.skip("no shared data")
    path = next(p for p in FBX_FILES if "character_7500" in p.name)
    open_file(studio, path)
    document = studio.state.snapshot
    studio.files.compare_path(str(path), wait=True)
    QApplication.processEvents()
    assert len(studio.layers) == 1 and studio.state.snapshot is document
    comparison = studio.layers[0].comparison
    assert comparison.n_pairs == studio.state.motion.n_joints
    assert comparison.position.max <= 1e-9 * studio.state.motion.size  # the same take: no error
    assert studio.layers_panel.table.item(1, 2).text() == path.name
