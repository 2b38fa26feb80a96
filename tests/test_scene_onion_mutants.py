"""The document's onion skins (app/scene/onion.py, issue 24) on the tiny synthetic skeleton
(:mod:`tests.tiny_scene`): which frames around the current one, their fading opacities and
slots, the poses drawn as lines with the links dashed, and the pool of actors whose points,
opacities and visibilities a frame change rewrites."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.scene.figure import DASHES, dash_points
from gmr_studio.app.scene.onion import (
    COUNTS,
    MAX_OPACITY,
    STEPS,
    OnionSettings,
    OnionSkins,
    ghost_opacity,
    onion_frames,
    pose_lines,
    pose_points,
    slot_of,
)
from tests.tiny_scene import figure_motion, figure_world, holds, posed_motion, scene_of, snapshot_of

pytestmark = pytest.mark.gui
N_POINTS = 6 + 2 * DASHES * 2  # six joints, two links of DASHES dashes


def test_onion_frames_step_and_count_of_one_and_the_documents_ends():
    frames, distance = onion_frames(0, 3, 1, 1)
    assert frames.tolist() == [1] and distance.tolist() == [1]
    assert frames.dtype == np.int64 and distance.dtype == np.int64
    frames, distance = onion_frames(4, 9, 2, 2)  # 0 and 8 are the first and last frames
    assert frames.tolist() == [2, 6, 0, 8] and distance.tolist() == [-1, 1, -2, 2]
    frames, distance = onion_frames(4, 8, 2, 3)
    assert frames.tolist() == [2, 6, 0] and distance.tolist() == [-1, 1, -2]
    for step, count in ((0, 1), (1, 0), (-1, 2)):
        with pytest.raises(ValueError, match="at least 1"):
            onion_frames(5, 10, step, count)


def test_opacities_fade_linearly_to_a_fifth_at_count_steps():
    np.testing.assert_allclose(
        ghost_opacity(np.array([-1, 1, -2, 2, -3, 3]), 3), MAX_OPACITY * np.repeat([1.0, 0.6, 0.2], 2)
    )
    np.testing.assert_allclose(ghost_opacity(np.array([1, -2]), 2), MAX_OPACITY * np.array([1.0, 0.2]))
    np.testing.assert_allclose(ghost_opacity(np.array([-1, 1]), 1), [MAX_OPACITY, MAX_OPACITY])
    assert ghost_opacity(np.zeros(0, np.int64), 1).shape == (0,)


def test_slots_alternate_before_and_after_from_the_nearest():
    assert slot_of(np.array([-1, 1, -2, 2, -3, 3])).tolist() == [0, 1, 2, 3, 4, 5]
    assert slot_of([3, -1]).tolist() == [5, 0]


def test_a_pose_is_its_bones_then_the_links_dashes():
    motion = figure_motion()
    pairs, links, n_points = pose_lines(motion)
    assert links.tolist() == [[4, 2], [1, 0]] and n_points == N_POINTS
    assert pairs[:3].tolist() == [[1, 2], [2, 3], [4, 5]] and pairs.dtype == np.int64
    np.testing.assert_array_equal(pairs[3:], 6 + np.arange(4 * DASHES).reshape(-1, 2))
    positions = figure_world(1)[0]
    points = pose_points(positions, links)
    assert points.shape == (N_POINTS, 3)
    np.testing.assert_array_equal(points[:6], positions)
    np.testing.assert_allclose(points[6:], dash_points(positions[[4, 1]], positions[[2, 0]]).reshape(-1, 3))
    world = np.array([[[0.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])
    pairs, links, n_points = pose_lines(posed_motion(("Hips", "Head"), (-1, 0), world))
    assert pairs.tolist() == [[0, 1]] and links.shape == (0, 2) and n_points == 2
    row = world[0]
    assert pose_points(row, links) is row


def test_the_settings_and_their_frames():
    assert STEPS == (2, 5, 10, 20, 30, 60) and COUNTS == (1, 2, 3, 5, 8)  # the View > Onion skin menu's choices
    settings = OnionSettings()
    assert settings.step in STEPS and settings.count in COUNTS
    assert (settings.shown, settings.step, settings.count, settings.include_layers) == (False, 10, 3, True)
    assert settings.frames(15, 40)[0].tolist() == [5, 25, 35]


def test_the_pool_a_line_actor_per_slot_blue_before_orange_after():
    settings = OnionSettings(shown=True, step=2, count=2)
    snapshot = snapshot_of(figure_motion(9))
    with scene_of(snapshot) as scene:
        skins = OnionSkins(settings)
        scene.add_drawable(skins)
        assert len(skins.pool) == 4 and list(skins.parts) == [f"onion_{slot}" for slot in range(4)]
        for slot, part in enumerate(skins.pool):
            assert skins.parts[f"onion_{slot}"] is part and holds(scene.plotter.renderer, part.actor)
            prop = part.actor.GetProperty()
            assert prop.GetColor() == pytest.approx((0.35, 0.65, 1.0) if slot % 2 == 0 else (1.0, 0.6, 0.3))
            assert prop.GetLineWidth() == pytest.approx(2.5) and part.n_points == N_POINTS
        # frame 0: only the poses after it, two and four frames on
        assert skins.frames.tolist() == [2, 4] and [p.visible for p in skins.pool] == [False, True, False, True]
        assert skins.poses == [skins.pool[1], skins.pool[3]]
        np.testing.assert_allclose(skins.opacities, MAX_OPACITY * np.array([1.0, 0.2]))
        scene.show_frame(4)
        assert skins.frames.tolist() == [2, 6, 0, 8] and all(p.visible for p in skins.pool)
        for slot, frame, alpha in ((0, 2, 1.0), (1, 6, 1.0), (2, 0, 0.2), (3, 8, 0.2)):
            part = skins.pool[slot]
            np.testing.assert_allclose(part.mesh.points, pose_points(snapshot.positions[frame], skins.links))
            assert part.actor.GetProperty().GetOpacity() == pytest.approx(MAX_OPACITY * alpha)
        scene.show_frame(7)
        assert skins.frames.tolist() == [5, 3] and [p.visible for p in skins.pool] == [True, False, True, False]
        skins.set_visible(False)
        scene.show_frame(6)  # a hidden drawing writes nothing
        assert skins.frames.tolist() == [5, 3] and not any(p.visible for p in skins.pool)
        skins.set_visible(True)
        skins.show_frame(6)
        assert [p.visible for p in skins.pool] == [True, True, True, False]


def test_a_new_drawing_shows_no_pose():
    skins = OnionSkins(OnionSettings(shown=True))
    assert skins.pool == [] and skins.poses == [] and skins.parts == {}
    assert skins.frames.shape == (0,) and skins.frames.dtype == np.int64 and skins.opacities.shape == (0,)


def test_no_pool_while_not_shown_or_without_a_document():
    settings = OnionSettings(shown=False, step=2, count=2)
    with scene_of(snapshot_of(figure_motion(9))) as scene:
        skins = OnionSkins(settings)
        scene.add_drawable(skins)
        assert skins.pool == [] and skins.parts == {} and not skins.wanted(scene) and not skins.visible
        skins.show_frame(3)
        assert skins.frames.tolist() == [] and skins.poses == []
        settings.shown = True
        scene.redraw(skins)
        assert len(skins.pool) == 4 and skins.wanted(scene) and skins.visible
        settings.shown = False
        scene.redraw(skins)  # rebuilt: the pool and what it showed forgotten
        assert skins.pool == [] and skins.poses == [] and skins.frames.tolist() == [] and skins.opacities.shape == (0,)
    with scene_of(None) as scene:
        skins = OnionSkins(OnionSettings(shown=True))
        scene.add_drawable(skins)
        assert skins.pool == [] and skins.parts == {}


def test_the_skins_box_is_the_documents_joints_at_every_frame():
    """The poses are the document at other frames (bones and dashes between its joints): the
    box of its joints at every frame holds each; no pool: the empty box."""
    from gmr_studio.app.scene.drawable import EMPTY_BOX, box_of

    settings = OnionSettings(shown=False, step=2, count=2)
    snapshot = snapshot_of(figure_motion(9))
    with scene_of(snapshot) as scene:
        skins = OnionSkins(settings)
        scene.add_drawable(skins)
        np.testing.assert_array_equal(skins.extent(), EMPTY_BOX)
        settings.shown = True
        scene.redraw(skins)
        box = skins.extent()
        np.testing.assert_array_equal(box, box_of(snapshot.positions))
        for frame in range(9):
            scene.show_frame(frame)
            for part in skins.poses:
                assert (part.mesh.points >= box[0]).all() and (part.mesh.points <= box[1]).all(), frame
