"""Picture tests on the gallery (issue 13): on the demo, every motion file of the shared data
and every convention rig, the figure fills a sensible share of the view, stands on a ground
grid that is there, stays on the same pixels after each edit kind, and the demo's markers
sit on their joints. Pictures are small (240x180) to keep this to seconds a case."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.tools.gallery import (
    EDITS,
    all_cases,
    dilate,
    figure_mask,
    ground_mask,
    render_case,
)

pytestmark = pytest.mark.gui

SIZE = (240, 180)
CASES = {case.name: case for case in all_cases()}
# a root cube (3 joint radii wide) sticks out of the sphere it replaces by its half-diagonal
# less a radius, 1.6 radii; plus a pixel of rounding
CUBE_MARGIN = 1.6
# the demo's markers: 0.5 mm of seeded noise on a figure of about 1.7 m drawn in 180 pixels
MARKER_PIXELS = 1.0


@pytest.fixture(scope="module")
def pictures(qapp):
    cache: dict[str, list] = {}

    def get(name: str) -> list:
        if name not in cache:
            cache[name] = render_case(CASES[name], SIZE)
        return cache[name]

    return get


def _pixels(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    x = np.clip(np.rint(points[:, 0]).astype(int), 0, SIZE[0] - 1)
    y = np.clip(np.rint(points[:, 1]).astype(int), 0, SIZE[1] - 1)
    return x, y


@pytest.mark.parametrize("name", list(CASES))
def test_the_figure_fills_the_view_stands_on_the_grid_and_stays_put_through_the_edits(pictures, name):
    """One test a case, so that a case is rendered once (the 100,000-frame take costs)."""
    _check_figure_and_ground(pictures(name)[0], name)
    _check_edits(pictures(name), name)


def _check_figure_and_ground(opened, name: str) -> None:
    figure, ground = figure_mask(opened.image), ground_mask(opened.image)
    actor = opened.joints[~opened.anchors]
    x, y = _pixels(actor)
    inside = (actor[:, 0] >= 0) & (actor[:, 0] < SIZE[0]) & (actor[:, 1] >= 0) & (actor[:, 1] < SIZE[1])
    assert inside.all(), f"{name}: joints {np.flatnonzero(~inside)} are out of the view"
    assert dilate(figure, 1)[y, x].all(), "a joint is not drawn where it projects"
    rows, columns = np.flatnonzero(figure.any(axis=1)), np.flatnonzero(figure.any(axis=0))
    share = (rows.max() - rows.min() + 1) / SIZE[1]
    across = (columns.max() - columns.min() + 1) / SIZE[0]
    if len(actor) > 1 and np.ptp(actor[:, :2], axis=0).max() >= 2:  # not joints that all coincide
        # it fills the view one way or the other (a figure standing, or objects laid out on a
        # floor, as glTF scenes without a skin are), and is never cut
        assert max(share, across) >= 0.2, f"the figure spans {share:.0%} of the height, {across:.0%} of the width"
        assert share <= 0.95, f"the figure spans {share:.0%} of the view's height"
    # (half a view's width of grid pixels at least: a thin chain or a point stands on a small grid)
    assert ground.sum() > SIZE[0] / 2, f"no ground grid ({ground.sum()} pixels)"
    ground_rows = np.flatnonzero(ground.any(axis=1))
    feet = actor[:, 1].max()  # the lowest joint on screen
    if len(actor) > 1:  # a lone node (an FBX cube's node animation) may fly above its grid
        assert ground_rows.min() <= feet <= ground_rows.max() + 1, "the feet are not over the grid"


def _check_edits(pictures: list, name: str) -> None:
    opened, *edited = pictures
    figure_before = figure_mask(opened.image)
    margin = int(np.ceil(CUBE_MARGIN * opened.joint_radius)) + 1
    for picture in edited:
        if not picture.applied:
            assert len(opened.names) == 1, f"{picture.edit} refused on {name}"
            assert np.array_equal(picture.image, opened.image)
            continue
        what = f"{name}, {picture.edit}"
        assert np.abs(picture.joints[:, :2] - opened.joints[:, :2]).max() < 1e-6, f"{what}: joints moved"
        figure_after = figure_mask(picture.image)
        stray = figure_after & ~dilate(figure_before, margin)
        assert stray.sum() == 0, f"{what}: {stray.sum()} figure pixels where there was none"
        x, y = _pixels(picture.joints)
        assert dilate(figure_after, 1)[y, x].all(), f"{what}: a joint is no longer drawn"
        away = ~dilate(figure_before | figure_after, 2)
        assert np.array_equal(ground_mask(opened.image) & away, ground_mask(picture.image) & away), (
            f"{what}: the ground grid changed"
        )
    assert [p.edit for p in pictures] == list(EDITS)


def test_the_demos_markers_project_onto_their_joints(pictures):
    for picture in pictures("demo"):
        named = [
            (m, picture.names.index(label)) for m, label in enumerate(picture.marker_labels) if label in picture.names
        ]
        assert len(named) == len(picture.names), "a virtual marker on every joint"
        markers = np.array([picture.markers[m] for m, _ in named])
        joints = np.array([picture.joints[j] for _, j in named])
        shown = np.isfinite(markers).all(axis=1)
        assert shown.sum() > 0.8 * len(named)
        offset = np.linalg.norm(markers[shown, :2] - joints[shown, :2], axis=1)
        assert offset.max() < MARKER_PIXELS, f"{picture.edit}: a marker lands {offset.max():.2f} px from its joint"
        x, y = _pixels(markers[shown])
        assert figure_mask(picture.image)[y, x].all(), "a marker is not drawn where it projects"
