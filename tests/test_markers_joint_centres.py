"""Joint centres from skin markers (core/markers/joint_centres.py): the chord construction
when no right angle exists, the hip regressions per frame, Davis's marker diameter."""

from __future__ import annotations

import warnings

import numpy as np

from gmr_studio.core.markers import joint_centres as jc


def test_chord_with_the_proximal_centre_nearer_than_delta_stays_on_its_line():
    """|P - L| below delta (a marker or a width out of proportion): no right angle exists; the
    sine is clipped to 0 and the centre lies on the line from L towards P, at delta^2 / |P - L|,
    a number rather than NaN."""
    proximal, lateral, wand = np.array([0.0, 0, 40]), np.array([0.0, 0, 0]), np.array([0.0, 30, 20])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        centre = jc.chord(proximal, lateral, wand, 50.0)
    np.testing.assert_allclose(centre, [0.0, 0.0, 50.0**2 / 40.0], atol=1e-12)


def test_hip_regressions_per_frame_are_the_one_frame_values_stacked():
    """Pelvis widths and depths (or leg lengths and ASIS distances) per frame: (F, 2, 3), frame
    f the hips of frame f's measures, left then right."""
    width, depth, leg = (
        np.array([230.0, 250.0, 270.0]),
        np.array([140.0, 150.0, 160.0]),
        np.array([800.0, 900.0, 1000.0]),
    )
    harrington = jc.hip_harrington(width, depth)
    davis = jc.hip_davis(leg, width)
    assert harrington.shape == davis.shape == (3, 2, 3)
    for f in range(3):
        np.testing.assert_array_equal(harrington[f], jc.hip_harrington(width[f], depth[f]))
        np.testing.assert_array_equal(davis[f], jc.hip_davis(leg[f], width[f]))
    np.testing.assert_array_equal(harrington[:, 1, 1], -harrington[:, 0, 1])  # the right hip mirrors y
    np.testing.assert_array_equal(davis[:, 1, 1], -davis[:, 0, 1])


def test_davis_takes_plug_in_gaits_14_mm_markers_by_default():
    np.testing.assert_array_equal(jc.hip_davis(900.0, 250.0), jc.hip_davis(900.0, 250.0, 7.0))
    # a measured ASIS-trochanter distance replaces the leg-length estimate (0.1288 LL - 48.56)
    np.testing.assert_allclose(
        jc.hip_davis(900.0, 250.0, asis_trochanter=0.1288 * 900 - 48.56), jc.hip_davis(900.0, 250.0)
    )
