"""The Teach dock and its overlay in the real window, on CMU 01_01."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.model import commands
from gmr_studio.app.scene.teach_overlay import POST_COLOR, PRE_COLOR
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path

pytestmark = pytest.mark.gui
studio = app_fixtures.studio

CMU = "cmu/subject01/01_01.bvh"


def color_pixels(image: np.ndarray, color, tolerance: int = 40) -> np.ndarray:
    """(N, 2) row/column of the pixels within ``tolerance`` of ``color`` (0..1 floats)."""
    target = np.round(np.array(color) * 255)
    return np.argwhere(np.abs(image[..., :3].astype(int) - target).max(axis=-1) <= tolerance)


@pytest.fixture
def classroom(studio, qtbot):
    open_file(studio, shared_path(CMU))
    studio.state.set_frame(619)
    studio.state.select(studio.state.motion.names.index("LeftForeArm"))
    studio.classroom.show()
    qtbot.waitUntil(lambda: studio.classroom.panel.chain is not None, timeout=3000)
    return studio


def test_the_chain_of_the_selected_joint_is_shown_both_ways(classroom, qtbot):
    panel, state = classroom.classroom.panel, classroom.state
    joint = state.motion.names.index("LeftForeArm")
    qtbot.waitUntil(lambda: panel.chain is not None and panel.chain.joints[-1] == joint, timeout=3000)
    assert panel.chain.joints == state.motion.path_from_root(joint)
    np.testing.assert_allclose(panel.chain.gmr_product[:3, 3], state.snapshot.positions[619, joint], atol=1e-9)
    text = panel.chain_view.toPlainText()
    for name in (
        "Hips",
        "LeftShoulder",
        "LeftArm",
        "LeftForeArm",
        "Product of the links",
        "World transform (FK)",
        "rounding",
    ):
        assert name in text
    assert "LeftForeArm" in panel.title.text() and "619" in panel.title.text()


def test_the_rotation_slider_turns_the_drawn_bones(classroom, qtbot):
    window, panel, overlay = classroom, classroom.classroom.panel, classroom.classroom.overlay
    snapshot, joint = window.state.snapshot, window.state.selected
    assert overlay.geometry is not None
    np.testing.assert_allclose(overlay.geometry.pre[1], snapshot.positions[619, joint], atol=1e-9)
    child = snapshot.motion.children[joint][0]
    np.testing.assert_allclose(overlay.geometry.post[1], snapshot.positions[619, child], atol=1e-9)
    window.view.scene.render(now=True)
    posed = screen_image(window)
    assert len(color_pixels(posed, PRE_COLOR)) > 20 and len(color_pixels(posed, POST_COLOR)) > 20
    panel.amount.setValue(0)
    turned = overlay.geometry
    bone = snapshot.positions[619, joint] - snapshot.positions[619, snapshot.motion.parents[joint]]
    assert np.linalg.norm(turned.pre[1] - snapshot.positions[619, joint]) > 0.05 * np.linalg.norm(bone)
    np.testing.assert_allclose(np.linalg.norm(turned.pre[1] - turned.pre[0]), np.linalg.norm(bone), rtol=1e-9)
    window.view.scene.render(now=True)
    rest = screen_image(window)
    before, after = color_pixels(posed, PRE_COLOR).mean(axis=0), color_pixels(rest, PRE_COLOR).mean(axis=0)
    assert np.abs(before - after).max() > 2  # the pink bone moved on the screen


def test_hiding_the_dock_removes_the_drawing(classroom, qtbot):
    classroom.classroom.dock.hide()
    qtbot.waitUntil(lambda: classroom.classroom.overlay.geometry is None, timeout=3000)
    classroom.view.scene.render(now=True)
    assert len(color_pixels(screen_image(classroom), PRE_COLOR, tolerance=20)) == 0


def test_shift_root_is_explained(classroom):
    state, panel = classroom.state, classroom.classroom.panel
    assert commands.shift_root_to(state, state.motion.names.index("LeftHand"))
    text = panel.shift_text.text()
    assert "LeftHand became the root" in text and "Hips" in text and "did not move" in text


def test_the_roots_slider_measures_in_the_background(classroom, qtbot):
    panel, state = classroom.classroom.panel, classroom.state
    panel.roots.setValue(6)
    qtbot.waitUntil(lambda: 6 in panel.points, timeout=20000)
    point = panel.points[6]
    assert point.roots == 6 and len(point.split_joints) == 5
    assert point.largest_change <= 1e-9 * state.motion.size
    assert point.fk_us_per_frame > 0
    assert "6 root(s): FK" in panel.roots_label.text()
    assert state.motion.n_joints == len(state.motion.names) and (state.motion.parents < 0).sum() == 1  # untouched
