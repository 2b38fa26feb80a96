"""Marker alignment's turn about up turns about the figure's centre, drawn while the dialog
is open (issue 14.11)."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.dialogs.alignment_dialog import PIVOT_COLOR, AlignmentDialog
from gmr_studio.core.demo import MARKERS_FILE, MOTION_FILE, demo_folder
from gmr_studio.core.markers.alignment import MarkerAlignment, figure_centre_joint, turned_about
from gmr_studio.core.rotations.euler import rotation_about_axis
from gmr_studio.core.space.similarity import Similarity
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image

studio = app_fixtures.studio


def turn(axis: int, degrees: float) -> np.ndarray:
    """(3, 3) rotation by ``degrees`` about coordinate axis 0, 1 or 2 (core.rotations.euler)."""
    return rotation_about_axis("XYZ"[axis], np.radians(degrees))


def test_a_turn_keeps_the_pivot_and_the_distances_to_it(rng):
    alignment = MarkerAlignment(transform=Similarity(turn(2, 90.0), 0.01, np.array([3.0, -1.0, 2.0])))
    pivot = np.array([10.0, 4.0, -7.0])
    points = rng.normal(size=(50, 3)) * 100
    for axis in (1, 2):
        turned = turned_about(alignment, "xyz"[axis], 90.0, pivot)
        before, after = alignment.apply(points), turned.apply(points)
        np.testing.assert_allclose(
            np.linalg.norm(after - pivot, axis=1), np.linalg.norm(before - pivot, axis=1), rtol=1e-12
        )
        # along the up axis nothing moves; across it, a quarter turn about the pivot
        np.testing.assert_allclose(after[:, axis], before[:, axis], atol=1e-12)
        np.testing.assert_allclose(after - pivot, (before - pivot) @ turn(axis, 90.0).T, atol=1e-10)
        # the marker that sits on the pivot stays there
        on_pivot = np.linalg.solve(
            alignment.transform.scale * alignment.transform.rotation, pivot - alignment.transform.translation
        )
        np.testing.assert_allclose(turned.apply(on_pivot), pivot, atol=1e-10)


def test_the_centre_is_the_pelvis_else_the_biggest_trees_root():
    assert figure_centre_joint(("a", "Hips", "c"), np.array([0, 0, 0])) == 1
    assert figure_centre_joint(("x", "y", "z", "w"), np.array([0, 1, 1, 1])) == 1


def pivot_pixels(image: np.ndarray) -> np.ndarray:
    """(N, 2) row, column of the pixels drawn in the pivot's colour (unlit)."""
    target = np.array(PIVOT_COLOR) * 255
    return np.argwhere(np.abs(image[..., :3].astype(float) - target).max(axis=-1) < 40)


@pytest.mark.gui
def test_a_quarter_turn_spins_the_markers_in_place_and_the_pivot_is_drawn(qtbot, studio):
    open_file(studio, demo_folder() / MOTION_FILE, demo_folder() / MARKERS_FILE)
    state = studio.state
    state.set_frame(200)
    scene = studio.view.scene
    assert len(pivot_pixels(screen_image(studio))) == 0
    before = state.marker_overlay.positions[200]
    dialog = AlignmentDialog(state, studio, scene)
    qtbot.addWidget(dialog)
    pivot = state.positions[200, dialog.pivot_joint]
    assert state.motion.names[dialog.pivot_joint].lower() in ("root", "hips", "pelvis")
    dialog.turn.setValue(90.0)
    after = state.marker_overlay.positions[200]
    up = dialog.up_axis
    across = [a for a in range(3) if a != up]
    seen = np.isfinite(before).all(axis=1)
    # the cloud's horizontal distances to the pelvis are those before the turn: it stays on the figure
    np.testing.assert_allclose(
        np.linalg.norm((after - pivot)[seen][:, across], axis=1),
        np.linalg.norm((before - pivot)[seen][:, across], axis=1),
        rtol=1e-9,
    )
    centroid_distance = np.linalg.norm((np.nanmean(after, axis=0) - pivot)[across])
    assert centroid_distance < 0.25 * state.motion.size
    # the pivot is drawn where the pelvis is on screen
    image = screen_image(studio)
    drawn = pivot_pixels(image)
    assert len(drawn) > 30
    x, y, _ = scene.joint_screen_positions()[dialog.pivot_joint]
    assert np.hypot(drawn[:, 0] - y, drawn[:, 1] - x).min() < 6  # screen rows go down, as y does
    dialog.reject()
    assert len(pivot_pixels(screen_image(studio))) == 0
