"""What a comparison reads of each side (core/compare/tracks.py): the units and source units a
file's comments state, a motion's and a marker set's track, and B's units and up axis brought to
A's, with the sentence that says how."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gmr_studio.core.compare.tracks import Track, space_change, track_of_motion, track_of_points
from gmr_studio.core.demo import MOTION_FILE, demo_folder
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import forward_kinematics
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.space.units import UNITS, unit_of_length


def walk(facts: FileFacts | None = None):
    motion = load_gmr(demo_folder() / MOTION_FILE).frame_slice(slice(0, 12))
    return motion.replace(facts=facts or FileFacts(up_axis="y"))


def test_a_motions_track():
    motion = walk(FileFacts(unit=UNITS["cm"], up_axis="z", source_unit=UNITS["cm"]))
    expected, rotations = forward_kinematics(pre_from_post(motion), with_rotations=True, threads=None)
    track = track_of_motion(motion, label="walk.bvh")
    np.testing.assert_array_equal(track.positions, expected)
    np.testing.assert_array_equal(track.rotations, rotations)
    np.testing.assert_array_equal(track.has_rotation, np.asarray(motion.parents) >= 0)
    assert not track.has_rotation[motion.roots].any() and track.has_rotation.sum() == motion.n_joints - len(
        motion.roots
    )
    assert track.names == motion.names and track.frame_rate == motion.frame_rate and track.size == motion.size
    assert (track.units, track.up, track.label, track.source_unit) == ("cm", "z", "walk.bvh", UNITS["cm"])
    assert (track.n_frames, track.n_points) == (12, motion.n_joints)
    given = expected + 1.0  # the app's cache: taken as it is, rotations only when asked for
    cached = track_of_motion(motion, with_rotations=False, positions=given)
    assert cached.positions is given and cached.rotations is None
    np.testing.assert_array_equal(track_of_motion(motion, positions=given).rotations, rotations)
    np.testing.assert_array_equal(track_of_motion(motion, positions=given).positions, expected)
    computed = track_of_motion(motion, with_rotations=False)
    np.testing.assert_array_equal(computed.positions, expected)
    assert computed.rotations is None
    plain = track_of_motion(walk())
    assert (plain.units, plain.up, plain.source_unit, plain.label) == (None, "y", None, "")


def test_a_marker_sets_track():
    positions = np.zeros((4, 3, 3))
    positions[:, 0] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.5, 0.0, 0.0]]
    positions[:, 1] = [[0.0, -1.0, 0.0], [0.0, 0.5, 0.0], [np.nan, np.nan, np.nan], [0.0, 0.0, 0.0]]
    positions[:, 2] = [[0.0, 0.0, -0.5], [0.0, 0.0, 0.5], [0.0, 0.0, 9.0], [0.0, 0.0, 0.0]]
    positions[2, 2, 0] = np.nan  # one coordinate missing: the point is missing
    positions += np.array([5.0, -3.0, 7.0])  # away from the origin: the extent is along each axis
    track = track_of_points(["a", "b", "c"], positions.tolist(), 60, units="mm", up="z", label="m.trc")
    assert track.names == ("a", "b", "c") and track.rotations is None and track.frame_rate == 60.0
    assert isinstance(track.frame_rate, float) and track.positions.dtype == np.float64
    np.testing.assert_array_equal(track.positions, positions)
    np.testing.assert_array_equal(track.has_rotation, [False, False, False])
    assert track.size == 2.0  # x from 0 to 2; z's 9 is in a point with a gap, y spans 1.5
    assert (track.units, track.up, track.label) == ("mm", "z", "m.trc")
    assert track_of_points(["a"], np.ones((3, 1, 3)), 30.0).size == 1.0  # no extent: 1
    assert track_of_points(["a"], np.full((3, 1, 3), np.nan), 30.0).size == 1.0  # nothing present: 1
    assert track_of_points(["a"], np.array([[[0.0, 0.0, 0.0]], [[0.0, 0.25, 0.0]]]), 30.0).size == 0.25
    assert track_of_points(["a"], np.array([[[0.0, 0.0, 0.0]], [[0.0, 0.0, -3.0]]]), 30.0).size == 3.0


def points(units=None, up="y", source_metres=None) -> Track:
    track = track_of_points(["p"], np.zeros((2, 1, 3)), 30.0, units=units, up=up)
    return dataclasses.replace(track, source_unit=None if source_metres is None else unit_of_length(source_metres))


def test_units_brought_to_as():
    for unit in UNITS.values():
        assert space_change(points("m"), points(unit.name)).scale == unit.metres
        assert space_change(points(unit.name), points("m")).scale == 1.0 / unit.metres
    change = space_change(points("cm"), points("in"))
    assert change.scale == 2.54 and change.notes[0] == "B in in, A in cm: B scaled by 2.54"
    assert (change.units_a, change.units_b) == ("cm", "in")
    given = space_change(points("cm"), points("in"), scale=0.5)
    assert given.scale == 0.5 and given.notes[0] == "B scaled by 0.5 (given)"
    for wrong in (0.0, -1.0, np.nan, np.inf):
        with pytest.raises(ValueError, match="the scale must be a positive number"):
            space_change(points(), points(), scale=wrong)


def test_units_from_a_glTF_exports_note():
    # B is our glTF export in metres of a motion in units of 0.0254 m; A states none
    b = points("m", source_metres=0.0254)
    change = space_change(points(), b)
    assert change.scale == 1.0 / 0.0254 and "exported from in" in change.notes[0]
    assert "A states no unit" in change.notes[0]
    reverse = space_change(points("m", source_metres=0.0254), points())
    assert reverse.scale == 0.0254 and "B states no unit" in reverse.notes[0]
    # the note is read only on a side in metres, with the other side stating nothing
    assert space_change(points("cm"), b).scale == 100.0
    assert space_change(points(), points("cm", source_metres=0.0254)).scale == 1.0 / 0.0254 / 100
    assert space_change(points("m"), points(source_metres=0.0254)).scale == 1.0
    assert space_change(points(source_metres=0.0254), points("m")).scale == 1.0
    assert space_change(points("m", source_metres=0.0254), points("m", source_metres=0.5)).scale == 1.0


def test_units_stated_on_one_side_or_neither():
    one = space_change(points("mm"), points())
    assert one.scale == 1.0 and one.notes[0] == "units: only one side states them (mm); the other is taken as the same"
    other = space_change(points(), points("ft"))
    assert (
        other.scale == 1.0 and other.notes[0] == "units: only one side states them (ft); the other is taken as the same"
    )
    neither = space_change(points(), points())
    assert neither.scale == 1.0 and neither.notes[0] == "units: neither file states them; taken as the same"
    assert isinstance(neither.scale, float)


def test_the_up_axis_brought_to_as():
    up = np.array([0.0, 1.0, 0.0])
    same = space_change(points(up="z"), points(up="z"))
    np.testing.assert_array_equal(same.up_rotation, np.eye(3))
    assert same.notes[-1] == "up axis: z on both sides" and (same.up_a, same.up_b) == ("z", "z")
    to_z = space_change(points(up="z"), points(up="y"))
    np.testing.assert_array_equal(to_z.up_rotation @ up, [0.0, 0.0, 1.0])  # B's up is A's up
    assert to_z.notes[-1] == "up axis: B turned from y up to A's z up"
    to_y = space_change(points(up="y"), points(up="z"))
    np.testing.assert_array_equal(to_y.up_rotation @ [0.0, 0.0, 1.0], up)
    assert to_y.notes[-1] == "up axis: B turned from z up to A's y up"
    for rotation in (to_z.up_rotation, to_y.up_rotation):
        np.testing.assert_array_equal(rotation @ rotation.T, np.eye(3))
        assert np.linalg.det(rotation) == 1.0
    told = space_change(points(up="y"), points(up="y"), up_b="Z")  # what the caller says wins
    np.testing.assert_array_equal(told.up_rotation, to_y.up_rotation)
    assert told.up_b == "z" and told.notes == (
        "units: neither file states them; taken as the same",
        "up axis: B turned from z up to A's y up",
    )
    assert space_change(points(up="y"), points(up="z"), up_b="y").notes[-1] == "up axis: y on both sides"
    with pytest.raises(ValueError, match="the up axis must be one of y, z, not 'X'"):
        space_change(points(), points(), up_b="X")


def test_defaults_frozen_and_keywords():
    track = Track(("p",), np.zeros((2, 1, 3)), None, np.zeros(1, dtype=bool), 30.0)
    assert (track.units, track.up, track.size, track.label, track.source_unit) == (None, "y", 1.0, "", None)
    same = dataclasses.replace(track)  # compared by identity (its arrays have no single truth value)
    assert track == track and track != same and len({track, same}) == 2
    change = space_change(track, track)
    for frozen, field in ((track, "size"), (change, "scale")):
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(frozen, field, 2.0)
    with pytest.raises(TypeError):
        track_of_points(["p"], np.zeros((2, 1, 3)), 30.0, "mm")
    with pytest.raises(TypeError):
        track_of_motion(walk(), False)
    with pytest.raises(TypeError):
        space_change(track, track, 2.0)
