"""The built skeleton's motion (core/markers/built_motion.py): which bone carries each marker,
the closed form's frame time and note, and how the refinement is run (its iterations split
around the markers' placement, the weights, the bones kept rigid), on generated markers."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gmr_studio.core.markers import refine
from gmr_studio.core.markers.built_motion import markers_to_built_motion, role_bones
from gmr_studio.core.markers.sets import SetMatch, set_by_name
from tests.test_markers_build import generated_markers


@pytest.fixture(scope="module")
def full_body():
    markers, _ = generated_markers("plug-in-gait-full", n_frames=4, seed=1)
    return markers


@pytest.fixture
def runs(monkeypatch):
    """The refinement's runs and the markers' placements, recorded as they are made."""
    record: dict[str, list] = {"refine": [], "attach": []}
    real_refine, real_attach = refine.refine_motion, refine.attach_markers

    def refine_motion(motion, targets, bones, offsets, weights=None, iterations=5, fixed=()):
        out = real_refine(motion, targets, bones, offsets, weights, iterations, fixed=fixed)
        record["refine"].append(dict(motion=motion, weights=weights, iterations=iterations, fixed=fixed, out=out))
        return out

    def attach_markers(motion, targets, bones):
        record["attach"].append(motion)
        return real_attach(motion, targets, bones)

    monkeypatch.setattr(refine, "refine_motion", refine_motion)
    monkeypatch.setattr(refine, "attach_markers", attach_markers)
    return record


def test_each_marker_rides_on_its_segments_bone(full_body):
    built = markers_to_built_motion(full_body)
    names = built.built.skeleton.names
    carried = role_bones(built.built.set_match, names)
    expected = {
        "LASI": "pelvis", "RPSI": "pelvis", "LKNE": "LKJC", "RTHI": "RKJC", "LTIB": "LAJC", "RANK": "RAJC",
        "LHEE": "LTOE", "RTOE": "RTOE", "C7": "thorax", "RBAK": "thorax", "CLAV": "thorax", "LFHD": "head",
        "RSHO": "RSJC", "LELB": "LEJC", "RWRA": "RWJC", "LFIN": "LHAND",
    }  # fmt: skip
    assert {label: names[carried[label]] for label in expected} == expected
    assert set(carried) == set(full_body.labels)
    assert built.labels == tuple(label for label in full_body.labels if label in carried)  # file order
    np.testing.assert_array_equal(built.bones, [carried[label] for label in built.labels])


def test_a_mean_label_gives_each_part_to_the_first_role_using_it():
    definition = set_by_name("plug-in-gait-full")
    match = SetMatch(definition, {"LANK": "LANK+LX", "LKNE": "LX", "RKNE": "RKNE", "LTOE": "LTOE"}, (), 1.0, ())
    names = ("pelvis", "LKJC", "LAJC", "RKJC")
    assert role_bones(match, names) == {"LANK": 2, "LX": 2, "RKNE": 3}  # no LTOE bone: left out


def test_the_closed_form_keeps_the_markers_rate_and_says_where_it_comes_from(full_body, runs):
    built = markers_to_built_motion(full_body.replace(rate=120.0))
    assert built.result.motion.frame_time == pytest.approx(1 / 120.0, rel=1e-15)
    assert built.result.motion.comments == ("from markers (memory): skeleton built from set plug-in-gait-full",)
    named = markers_to_built_motion(full_body.replace(source="walk.c3d"))
    assert named.result.motion.comments[0] == "from markers walk.c3d: skeleton built from set plug-in-gait-full"
    assert built.refinement is None and runs["refine"] == [] and runs["attach"] == []  # not refined by default
    with pytest.raises(dataclasses.FrozenInstanceError):
        built.labels = ()  # type: ignore[misc]
    assert built != dataclasses.replace(built) and len({built, built}) == 1


def test_the_refinement_runs_then_places_the_markers_and_runs_twice_more(full_body, runs):
    built = markers_to_built_motion(full_body, refine=True)
    first, placed = runs["refine"]
    assert (first["iterations"], placed["iterations"]) == (3, 2)
    assert runs["attach"][1] is first["out"].motion and placed["motion"] is first["out"].motion
    assert built.refinement.iterations == 5 and built.result.motion is placed["out"].motion
    np.testing.assert_array_equal(built.refinement.residuals_before, first["out"].residuals_before)
    np.testing.assert_array_equal(built.refinement.residuals, placed["out"].residuals)
    skeleton = built.built.skeleton
    rigid = tuple(skeleton.joint_index(n) for n in ("pelvis_front", "LHJC", "RHJC"))
    assert first["fixed"] == rigid and placed["fixed"] == rigid
    np.testing.assert_array_equal(first["weights"], np.ones(len(built.labels)))


@pytest.mark.parametrize(
    ("iterations", "place_markers", "split"),
    [(1, True, [1]), (2, True, [1, 1]), (3, True, [1, 2]), (6, True, [4, 2]), (5, False, [5]), (1, False, [1])],
)
def test_how_the_iterations_are_split(full_body, runs, iterations, place_markers, split):
    built = markers_to_built_motion(full_body, refine=True, iterations=iterations, place_markers=place_markers)
    assert [run["iterations"] for run in runs["refine"]] == split
    assert len(runs["attach"]) == len(split) and built.refinement.iterations == iterations


def test_weights_name_markers_and_the_others_weigh_one(full_body, runs):
    built = markers_to_built_motion(full_body, refine=True, weights={"LKNE": 3.0, "NOPE": 2.0})
    expected = np.where(np.array(built.labels) == "LKNE", 3.0, 1.0)
    for run in runs["refine"]:
        np.testing.assert_array_equal(run["weights"], expected)
