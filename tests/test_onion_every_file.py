"""Issue 21's agreement suite, onion skins: on every shared file and rig, the onion poses are
the motion's own poses drawn as the view draws the figure (links dashed), and with the camera
framing the whole take (follow off) every one of them is inside the view."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.scene.onion import OnionSettings, OnionSkins, onion_frames, pose_lines, pose_points
from gmr_studio.app.scene.scene import SkeletonScene

pytestmark = pytest.mark.gui
SIZE = (320, 240)


def _cases():
    from gmr_studio.app.tools.gallery import all_cases

    return all_cases()


@pytest.mark.parametrize("case", _cases(), ids=lambda case: case.name)
def test_onion_poses_are_the_motions_own_inside_the_view(case, qapp):
    import pyvista as pv

    snapshot = case.load()
    n = snapshot.motion.n_frames
    step = max(1, n // 8)
    current = n // 2
    plotter = pv.Plotter(off_screen=True, window_size=SIZE)
    try:
        scene = SkeletonScene(plotter)
        scene.overlays["follow"] = False  # the camera frames the whole take
        scene.frame = current
        scene.set_snapshot(snapshot, reset_camera=True)
        skins = OnionSkins(OnionSettings(shown=True, step=step, count=2))
        scene.add_drawable(skins)
        scene.show_frame(current, render=False)
        scene.render(now=True)
        frames, _ = onion_frames(current, n, step, 2)
        assert skins.frames.tolist() == frames.tolist()
        _, links, n_points = pose_lines(snapshot.motion)
        figure = ~snapshot.motion.anchors
        for part, frame in zip(skins.poses, skins.frames, strict=True):
            assert part.visible and part.n_points == n_points
            expected = pose_points(snapshot.positions[frame], links)
            np.testing.assert_array_equal(np.asarray(part.mesh.points), np.nan_to_num(expected))
            xy = scene.display_positions(snapshot.positions[frame][figure])
            inside = (xy[:, 0] >= -1) & (xy[:, 0] <= SIZE[0] + 1) & (xy[:, 1] >= -1) & (xy[:, 1] <= SIZE[1] + 1)
            assert inside.all(), f"onion pose at frame {frame} drawn outside the view"
    finally:
        plotter.close()
