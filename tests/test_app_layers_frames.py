"""A comparison layer on a frame change: the same VTK objects, updated in place, drawn."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.scene.ghost_layer import NO_ERROR_COLOUR, error_colours
from gmr_studio.app.scene.vtk_parts import rgb_bytes
from tests import app_fixtures
from tests.app_fixtures import open_file, screen_image
from tests.conftest import shared_path

studio = app_fixtures.studio
pytestmark = pytest.mark.gui

BVH = "cmu/subject01/01_01.bvh"
AMC = "cmu/subject01/01_01.amc"


def _props(renderer) -> list[str]:
    """The address of every prop of ``renderer`` (actors and 2D props, the legend included)."""
    props = renderer.GetViewProps()
    props.InitTraversal()
    return [props.GetNextProp().__this__ for _ in range(props.GetNumberOfItems())]


def _magenta(image: np.ndarray) -> np.ndarray:
    """(H, W) pixels of the first layer's colour (1, 0.45, 0.9), also faded over the background."""
    return (image[..., 0] > 170) & (image[..., 1] < 140) & (image[..., 2] > 150)


def test_a_frame_change_updates_the_layer_in_place(studio):
    open_file(studio, shared_path(BVH))
    studio.problems.wait()  # the checks' marks drawn: the actors below are all there
    state, renderer = studio.state, studio.view.scene.plotter.renderer
    own_blending = renderer.GetUseOIT()
    state.set_frame(400)
    studio.files.compare_path(str(shared_path(AMC)), joint_map="cmu", wait=True)
    QApplication.processEvents()
    ghosts, layer = studio.ghosts, studio.layers[0]
    c = layer.comparison
    (bones, joints), error_lines = ghosts.ghosts[0], ghosts.error_lines
    error_joints = studio.view.scene.figure.parts["joints"]  # the document's, in the error's colours
    matched = ghosts.error_joints
    assert joints.n_points == 0 and not joints.visible  # every joint of B's ghost is a bone's end
    parts = (bones, error_joints, error_lines)
    objects = [(part.actor.__this__, part.mesh.__this__, part.mesh.GetPoints().__this__) for part in parts]
    inputs = [part.actor.GetMapper().GetInputDataObject(0, 0).__this__ for part in (bones, error_joints)]
    colours = error_joints.mesh.point_data.VTKObject.GetArray("colors").__this__
    props, legend = _props(renderer), ghosts.legend.actor.__this__
    # the colours of every compared frame, computed once when the layer was drawn
    assert ghosts.error_rgb.shape == (len(c.frames), c.n_pairs, 3)
    np.testing.assert_array_equal(ghosts.error_rgb, rgb_bytes(error_colours(c.position_error, c.position.max)))
    # translucent ghosts blended in drawing order while shown, the renderer's own setting after
    assert not renderer.GetUseOIT()
    pictures = {}
    for frame in (401, 1518, 0, 2000, 400):
        state.set_frame(frame)
        QApplication.processEvents()
        camera = renderer.GetActiveCamera()
        fitted = camera.GetClippingRange()
        renderer.ResetCameraClippingRange()  # VTK's own fit to everything drawn, the ghost included
        tight = camera.GetClippingRange()  # ... within the planes fitted to the take's box
        assert fitted[0] <= tight[0] and fitted[1] >= tight[1]
        # the same actors, poly data, points and colour arrays as before, nothing added
        assert _props(renderer) == props and ghosts.legend.actor.__this__ == legend
        assert [(p.actor.__this__, p.mesh.__this__, p.mesh.GetPoints().__this__) for p in parts] == objects
        assert [p.actor.GetMapper().GetInputDataObject(0, 0).__this__ for p in (bones, error_joints)] == inputs
        assert error_joints.mesh.point_data.VTKObject.GetArray("colors").__this__ == colours
        # ... holding this frame's values
        shown = np.asarray(error_joints.mesh.point_data["colors"])[matched]
        row = c.row_of_frame(frame)
        np.testing.assert_array_equal(shown, rgb_bytes(error_colours(c.position_error[row], c.position.max)))
        if frame == 0:  # before B's first frame (offset -1): no ghost, the error joints grey
            assert np.isnan(layer.ghost[0]).all() and not bones.visible and not joints.visible
            assert (shown == rgb_bytes(np.array(NO_ERROR_COLOUR))).all()
            continue
        ghost = layer.ghost[frame]  # bones: cylinders placed at each bone's middle
        np.testing.assert_allclose(bones.mesh.points, ghost[bones.pairs].mean(axis=1), atol=1e-6)
        np.testing.assert_allclose(error_joints.mesh.points[matched], c.positions_a[row], atol=1e-6)
        assert bones.visible and not joints.visible
        pictures[frame] = screen_image(studio)
    # and drawn: the ghost's colour where the ghost is at each frame, elsewhere as it moves
    masks = {frame: _magenta(image) for frame, image in pictures.items()}
    # (the ghost is its bones, B's joints at their ends; where B agrees with A the document's
    # figure hides it: 12 to 33 pixels of it show at these frames)
    assert all(mask.sum() > 8 for mask in masks.values())
    assert (masks[401] != masks[2000]).sum() > 30
    studio.layers.remove(0)
    QApplication.processEvents()
    # the layer's three actors and the legend gone, the renderer's own blending back
    assert renderer.GetUseOIT() == own_blending and len(_props(renderer)) == len(props) - 4


def test_the_comparison_bench_reports_wall_and_main_thread_ratios(capsys):
    """app.bench.bench_comparison: medians with and without a layer, and both ratios."""
    from gmr_studio.app.tools import bench

    for name in (bench.BVH, bench.AMC):  # the bench reads both: skipped without the data folder
        shared_path(name)
    bench.bench_comparison(20, rounds=1)
    lines = capsys.readouterr().out.splitlines()
    wall = [float(line.split("median")[1].split()[0]) for line in lines[:2]]
    assert lines[0].startswith("set frame + render, no comparison") and "comparison layer (amc)" in lines[1]

    def rounding(pair):  # how far a ratio of two values printed to 0.01 ms can be from the printed ratio
        return pair[1] / pair[0] * (0.005 / pair[0] + 0.005 / pair[1]) + 5e-4

    assert float(lines[2].split()[-1]) == pytest.approx(wall[1] / wall[0], abs=rounding(wall))
    assert "main-thread CPU" in lines[3]
    cpu = [float(value) for value in lines[3].split("median")[1].replace("ms", "").split("/")]
    assert all(value > 0 for value in wall + cpu)
    assert float(lines[4].split()[-1]) == pytest.approx(cpu[1] / cpu[0], abs=rounding(cpu))
