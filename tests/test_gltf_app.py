"""File > Export glTF... in the real window: the menu action, the written file's positions
equal the edited document's FK."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtWidgets import QFileDialog

from gmr_studio.core.demo import MOTION_FILE, demo_folder
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.test_gltf import expected_positions, load_gltf, node_world_positions

pytestmark = pytest.mark.gui
studio = app_fixtures.studio


def test_export_gltf_from_the_file_menu(qtbot, studio, tmp_path, monkeypatch):
    from gmr_studio.app.model import commands

    open_file(studio, demo_folder() / MOTION_FILE)
    state = studio.state
    commands.split_here(state, state.motion.joint_index("lfoot"))
    action = studio.actions["export_gltf"]
    file_menu = studio.menuBar().actions()[0].menu()
    assert action in file_menu.actions() and action.isEnabled()
    target = tmp_path / "edited"
    monkeypatch.setattr(QFileDialog, "getSaveFileName", lambda *args, **kwargs: (str(target), ""))
    action.trigger()
    written = tmp_path / "edited.glb"
    assert written.exists() and "Exported" in studio.status.text()
    gltf, blob = load_gltf(written)
    read = node_world_positions(gltf, blob)
    motion = state.motion
    factor = gltf.asset.extras["metres_per_unit"]
    got = np.stack([read[name] for name in motion.names], axis=1)
    expected = expected_positions(motion, "y", factor)
    assert np.abs(got - expected).max() <= 5e-7 * motion.size * factor
    assert len(motion.roots) == len(gltf.nodes[gltf.scenes[0].nodes[0]].children) == 2


def test_export_gltf_reports_a_bad_folder(qtbot, studio, tmp_path):
    open_file(studio, demo_folder() / MOTION_FILE)
    assert not studio.exports.export_gltf(tmp_path / "missing" / "x.glb")
    assert "Cannot export" in studio.status.text()
