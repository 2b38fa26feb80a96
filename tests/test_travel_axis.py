"""The figure's main direction of travel (core/space/heading.py): fitted on frames spread
over a long take it is the direction fitted on every frame."""

from __future__ import annotations

import numpy as np

from gmr_studio.core.space.heading import travel_axis


def wandering_walk(n_frames: int, heading_degrees: float, seed: int = 3) -> np.ndarray:
    """(F, 4, 3) a figure of four joints (Y up) walking 5 units along a heading, swaying to
    the sides and bobbing, with a little noise."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, n_frames)
    heading = np.radians(heading_degrees)
    along = np.array([np.cos(heading), 0.0, np.sin(heading)])
    across = np.array([-np.sin(heading), 0.0, np.cos(heading)])
    centre = 5.0 * t[:, None] * along + 0.3 * np.sin(40 * t)[:, None] * across
    centre[:, 1] = 1.0 + 0.05 * np.sin(90 * t)
    body = np.array([[0.0, 0.0, 0.0], [0.0, 0.6, 0.0], [0.2, -0.9, 0.0], [-0.2, -0.9, 0.0]])
    return centre[:, None] + body + 0.01 * rng.standard_normal((n_frames, 4, 3))


def test_fitted_on_frames_spread_over_a_long_take_it_points_as_on_every_frame():
    positions = wandering_walk(60_000, 35.0)
    every = travel_axis(positions, 1)
    spread = travel_axis(positions, 1, samples=2000)
    assert np.degrees(np.arccos(np.clip(every @ spread, -1.0, 1.0))) < 0.1
    np.testing.assert_allclose(every, [np.cos(np.radians(35.0)), 0.0, np.sin(np.radians(35.0))], atol=0.02)


def test_a_take_shorter_than_the_samples_is_fitted_on_every_frame():
    positions = wandering_walk(500, -120.0)
    np.testing.assert_array_equal(travel_axis(positions, 1, samples=2000), travel_axis(positions, 1))


def test_the_samples_include_the_last_frame_so_the_direction_points_where_it_ends():
    there_and_back = wandering_walk(10_001, 0.0)
    there_and_back[5000:] = there_and_back[5000::-1][:5001]  # walks back most of the way...
    there_and_back[-1] += [0.5, 0.0, 0.0]  # ...and ends ahead of where it started
    for samples in (None, 7, 100):
        assert travel_axis(there_and_back, 1, samples=samples)[0] > 0


def test_a_short_walk_backwards_points_backwards_as_a_unit_vector_with_z_up_too():
    walk = wandering_walk(200, 180.0) * 0.1  # half a unit towards -x
    np.testing.assert_allclose(travel_axis(walk, 1), [-1.0, 0.0, 0.0], atol=0.05)
    z_up = walk[..., [0, 2, 1]]
    axis = travel_axis(z_up, 2)
    np.testing.assert_allclose(axis, [-1.0, 0.0, 0.0], atol=0.05)
    assert axis[2] == 0.0 and abs(np.linalg.norm(axis) - 1.0) < 1e-15


def test_two_frames_are_a_path():
    two = np.zeros((2, 3, 3))
    two[1, :, 2] = 1.0  # every joint a unit along z
    np.testing.assert_allclose(travel_axis(two, 1), [0.0, 0.0, 1.0], atol=1e-15)


def test_a_figure_standing_still_faces_the_first_horizontal_axis():
    still = np.repeat(wandering_walk(1, 0.0), 50, axis=0)
    for up in (1, 2):
        np.testing.assert_array_equal(travel_axis(still, up), [1.0, 0.0, 0.0])


def test_still_below_is_how_far_the_figures_centroid_may_wander_and_still_stand():
    sway = np.zeros((100, 4, 3))
    sway[:, 0, 2] = 1.6 * np.sin(np.linspace(0, 6, 100))  # one of four joints: the centroid within 0.4
    np.testing.assert_array_equal(travel_axis(sway, 1, still_below=0.5), [1.0, 0.0, 0.0])
    np.testing.assert_allclose(np.abs(travel_axis(sway, 1, still_below=0.3)), [0.0, 0.0, 1.0], atol=1e-12)
    small = wandering_walk(300, 90.0) * 0.2  # a step of one unit along z: travel, by default
    np.testing.assert_allclose(travel_axis(small, 1), [0.0, 0.0, 1.0], atol=0.05)


def test_one_sample_still_fits_the_first_and_the_last_frame():
    still = np.repeat(wandering_walk(1, 0.0), 101, axis=0)
    still[0] += [0.0, 0.0, 2.0]  # only the first frame is elsewhere: it walks towards -z
    for samples in (None, 1, 3):
        np.testing.assert_allclose(travel_axis(still, 1, samples=samples), [0.0, 0.0, -1.0], atol=1e-12)


def test_a_short_walk_points_the_way_it_went_whichever_way_and_played_backwards_the_other_way():
    for degrees in range(0, 360, 30):
        walk = wandering_walk(300, degrees) * 0.1  # half a unit
        expected = [np.cos(np.radians(degrees)), 0.0, np.sin(np.radians(degrees))]
        np.testing.assert_allclose(travel_axis(walk, 1), expected, atol=0.05)
        np.testing.assert_allclose(travel_axis(walk[::-1], 1), -travel_axis(walk, 1), atol=1e-12)


def test_the_heading_is_the_same_in_any_unit():
    walk = wandering_walk(400, 60.0)
    for scale in (1e-6, 1e-3, 1e3):
        np.testing.assert_allclose(travel_axis(walk * scale, 1), travel_axis(walk, 1), atol=1e-9)
    still = np.repeat(wandering_walk(1, 0.0), 30, axis=0)
    for scale in (1e-6, 1e3):
        np.testing.assert_array_equal(travel_axis(still * scale, 1), [1.0, 0.0, 0.0])
