"""Marker maps renamed through joint-name maps (core/markers/joint_names.py), on synthetic
maps and skeletons: what is renamed (virtual markers, ``@NAME`` inputs, the pelvis, the
bones' starts) and what is not (real labels), which joint map is taken, and the refusals."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core import jointmap
from gmr_studio.core.errors import OperationError
from gmr_studio.core.jointmap import JointMap
from gmr_studio.core.markers.joint_names import rename_joints, through_joint_map
from gmr_studio.core.markers.markermap import MarkerMap, VirtualMarker

SKELETON = ["Hips", "LeftUpLeg", "RightUpLeg", "LeftLeg"]
TO_SKELETON = JointMap.from_pairs({"Hips": "root", "LeftUpLeg": "lhip", "RightUpLeg": "rhip", "LeftLeg": "knee"})


def lab_map(**changes) -> MarkerMap:
    """A calibrated map on a skeleton named root/lhip/rhip/knee, with one virtual marker
    (``extra``) no joint map pairs."""
    template = np.arange(9.0).reshape(3, 3)
    virtual = (
        VirtualMarker("root", "cluster", ("A", "B", "C"), np.ones(3), template, 1.5),
        VirtualMarker("lhip", "marker", ("D",)),
        VirtualMarker("rhip", "mean", ("E", "F")),
        VirtualMarker("knee", "cluster", ("@lhip", "G", "H"), np.zeros(3), template, 2.0),
        VirtualMarker("extra", "mean", ("@root", "I")),
    )
    fields = dict(
        name="lab", virtual=virtual, pelvis=("root", "lhip", "rhip"), units="mm",
        bone_starts={"knee": "lhip", "extra": "root"}, description="a lab's map",
    )  # fmt: skip
    return MarkerMap(**{**fields, **changes})


def test_a_map_naming_the_skeletons_pelvis_or_without_one_is_returned_as_is():
    named = lab_map()
    assert through_joint_map(named, ["root", "lhip", "rhip", "other"]) is named
    no_pelvis = lab_map(pelvis=None)
    assert through_joint_map(no_pelvis, SKELETON) is no_pelvis


def test_a_pelvis_only_map_is_returned_as_is_unless_it_has_a_home_or_a_cluster():
    kept = [v for v in lab_map().virtual if v.kind != "cluster"]
    plain = lab_map(virtual=(*kept, VirtualMarker("root", "mean", ("A", "B"))))
    assert through_joint_map(plain, SKELETON, TO_SKELETON) is plain
    homed = plain.replace(pelvis_home=np.eye(3))
    renamed = through_joint_map(homed, SKELETON, TO_SKELETON)
    assert renamed is not homed and renamed.pelvis == ("Hips", "LeftUpLeg", "RightUpLeg")
    clustered = lab_map()
    assert through_joint_map(clustered, SKELETON, TO_SKELETON).pelvis == ("Hips", "LeftUpLeg", "RightUpLeg")


def test_everything_named_after_a_joint_is_renamed_and_real_labels_are_not():
    renamed = through_joint_map(lab_map(), SKELETON, TO_SKELETON)
    assert renamed.names == ("Hips", "LeftUpLeg", "RightUpLeg", "LeftLeg", "extra")
    assert [v.markers for v in renamed.virtual] == [
        ("A", "B", "C"), ("D",), ("E", "F"), ("@LeftUpLeg", "G", "H"), ("@Hips", "I"),
    ]  # fmt: skip
    assert renamed.pelvis == ("Hips", "LeftUpLeg", "RightUpLeg")
    assert renamed.bone_starts == {"LeftLeg": "LeftUpLeg", "extra": "Hips"}
    assert renamed.renamed == "joint names through joint map 'explicit'; extra unpaired: they place no joint"
    before, after = lab_map().virtual[3], renamed.virtual[3]
    assert after.kind == "cluster" and after.rms == 2.0
    np.testing.assert_array_equal(after.offset, before.offset)
    np.testing.assert_array_equal(after.template, before.template)
    assert (renamed.name, renamed.units, renamed.description) == ("lab", "mm", "a lab's map")


def test_a_map_whose_joints_all_pair_notes_nothing_unpaired():
    whole = lab_map(virtual=lab_map().virtual[:4], bone_starts={})
    renamed = through_joint_map(whole, SKELETON, TO_SKELETON)
    assert renamed.renamed == "joint names through joint map 'explicit'"
    assert renamed.bone_starts == {}


def test_the_shipped_map_that_pairs_the_pelvis_and_the_most_joints_is_taken(monkeypatch):
    fewer = JointMap.from_pairs({"Hips": "root", "LeftUpLeg": "lhip", "RightUpLeg": "rhip"}, name="fewer")
    more = JointMap.from_pairs(TO_SKELETON.a_to_b, name="more")
    as_many = JointMap.from_pairs(TO_SKELETON.a_to_b, name="as-many")
    no_pelvis = JointMap.from_pairs({"LeftUpLeg": "lhip", "RightUpLeg": "rhip", "LeftLeg": "knee"}, name="partial")
    monkeypatch.setattr(jointmap, "available_joint_maps", lambda: [fewer, no_pelvis, more, as_many])
    renamed = through_joint_map(lab_map(), SKELETON)
    assert renamed.renamed.startswith("joint names through joint map 'more';")
    assert renamed.names[3] == "LeftLeg"
    monkeypatch.setattr(jointmap, "available_joint_maps", lambda: [no_pelvis, fewer])
    renamed = through_joint_map(lab_map(), SKELETON)
    assert renamed.renamed == (
        "joint names through joint map 'fewer'; knee, extra unpaired: they place no joint"
    )  # fmt: skip


def test_no_joint_map_pairing_the_pelvis_is_refused_saying_which_were_tried(monkeypatch):
    stranger = ["pelvis", "l_hip", "r_hip"]
    with pytest.raises(OperationError) as error:
        through_joint_map(lab_map(), stranger, "cmu")
    assert str(error.value) == (
        "marker map 'lab' places the joints of another skeleton (root, lhip, rhip are not joints of this one), "
        "and joint map 'cmu' does not pair them with this skeleton's joints"
    )
    with pytest.raises(OperationError, match=r"and any joint map \(cmu\) does not pair them"):
        through_joint_map(lab_map(), stranger)
    monkeypatch.setattr(jointmap, "available_joint_maps", lambda: [])
    with pytest.raises(OperationError, match=r"and any joint map \(none\) does not pair them"):
        through_joint_map(lab_map(), stranger)


def test_a_pelvis_paired_in_part_is_refused():
    half = JointMap.from_pairs({"Hips": "root", "LeftUpLeg": "lhip"})
    with pytest.raises(OperationError, match="places the joints of another skeleton"):
        through_joint_map(lab_map(), SKELETON, half)


def test_a_rename_onto_a_name_the_map_keeps_is_refused():
    """knee -> LeftLeg while a virtual marker the rename leaves is already called LeftLeg."""
    clashing = lab_map(virtual=(*lab_map().virtual, VirtualMarker("LeftLeg", "marker", ("J",))))
    with pytest.raises(OperationError, match=r"^renaming map 'lab': LeftLeg would name two joints$"):
        through_joint_map(clashing, SKELETON, TO_SKELETON)
    renamed = rename_joints(lab_map(), {"root": "Hips", "extra": "root"}, "by hand")
    assert renamed.names == ("Hips", "lhip", "rhip", "knee", "root")  # swapped onto a name it leaves
    assert renamed.virtual[3].markers == ("@lhip", "G", "H")  # an input not renamed keeps its name
    assert renamed.virtual[4].markers == ("@Hips", "I")
    assert renamed.renamed == "by hand; lhip, rhip, knee unpaired: they place no joint"
