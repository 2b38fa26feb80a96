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
