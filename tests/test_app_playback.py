"""Playback picks the frame from elapsed time: it drops frames rather than slowing down."""

from __future__ import annotations

from gmr_studio.app.model.playback import frame_at


def test_frame_follows_the_clock_at_any_speed():
    assert frame_at(0.0, 10, 120, 1.0, 1000, loop=True) == (10, False)
    assert frame_at(1.0, 10, 120, 1.0, 1000, loop=True) == (130, False)
    assert frame_at(1.0, 0, 120, 0.25, 1000, loop=True) == (30, False)
    assert frame_at(1.0, 0, 120, 4.0, 1000, loop=True) == (480, False)
    # a slow render (a tick after 0.3 s) lands on the frame of that time, skipping the ones between
    assert frame_at(0.3, 0, 120, 1.0, 1000, loop=True) == (36, False)


def test_loop_wraps_and_no_loop_stops_on_the_last_frame():
    assert frame_at(1.0, 0, 100, 1.0, 60, loop=True) == (40, False)
    assert frame_at(1.0, 0, 100, 1.0, 60, loop=False) == (59, True)
    assert frame_at(0.1, 0, 100, 1.0, 60, loop=False) == (10, False)
    assert frame_at(1.0, 0, 100, 1.0, 0, loop=True) == (0, True)
