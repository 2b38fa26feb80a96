"""A file's own rotation channels (core.model.channels.FileChannels) against an independent
computation: BVH channels intrinsic in file order, AMC dofs applied in file order about the
ASF frame C (``C R_last ... R_first C^T``), both turned back into the file's columns, and the
rule that says whether a file's values still make a motion's rotations."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.model.channels import FILE_MATCH_TOLERANCE, FileChannels
from gmr_studio.core.rotations.euler import euler_from_matrix, nearest_rotation


def about(axis: str, degrees: np.ndarray) -> np.ndarray:
    """(F, 3, 3) rotations by ``degrees`` (F,) about the fixed axis ``axis`` (X, Y or Z),
    written out element by element (no Euler code shared with the module)."""
    a = np.radians(degrees)
    c, s = np.cos(a), np.sin(a)
    one, zero = np.ones_like(a), np.zeros_like(a)
    rows = {
        "X": [[one, zero, zero], [zero, c, -s], [zero, s, c]],
        "Y": [[c, zero, s], [zero, one, zero], [-s, zero, c]],
        "Z": [[c, -s, zero], [s, c, zero], [zero, zero, one]],
    }[axis]
    return np.moveaxis(np.array(rows), -1, 0)


def degrees(rotations: np.ndarray, order: str) -> np.ndarray:
    return np.degrees(euler_from_matrix(rotations, order))


@pytest.fixture
def angles(rng) -> np.ndarray:
    """(6, 3) degrees: outer angles anywhere in (-170, 170), the middle one within (-80, 80)
    (one Euler solution: the round trips are exact)."""
    values = rng.uniform(-170.0, 170.0, size=(6, 3))
    values[:, 1] = rng.uniform(-80.0, 80.0, size=6)
    return values


@pytest.fixture
def frame_c(rng) -> np.ndarray:
    return nearest_rotation(rng.normal(size=(3, 3)))


def test_bvh_channels_turn_intrinsically_in_file_order(angles):
    channels = FileChannels(orders={"Hips": "ZXY"}, angles={"Hips": angles})
    expected = about("Z", angles[:, 0]) @ about("X", angles[:, 1]) @ about("Y", angles[:, 2])
    np.testing.assert_allclose(channels.rotations("Hips"), expected, atol=1e-14)
    np.testing.assert_allclose(channels.rotations("Hips", frame=4), expected[4], atol=1e-14)
    assert channels.intrinsic_order("Hips") == "ZXY" and channels.convention == "post"
    order, values = channels.of("Hips", 4)
    assert order == "ZXY" and np.array_equal(values, angles[4])


def test_amc_dofs_apply_in_file_order_about_the_asf_frame(angles, frame_c):
    # dofs "rx rz ry": first about x, then z, then y, fixed axes of the bone's frame C
    channels = FileChannels(orders={"lfemur": "XZY"}, angles={"lfemur": angles}, kind="amc", axes={"lfemur": frame_c})
    local = about("Y", angles[:, 2]) @ about("Z", angles[:, 1]) @ about("X", angles[:, 0])
    expected = frame_c @ local @ frame_c.T
    np.testing.assert_allclose(channels.rotations("lfemur"), expected, atol=1e-14)
    np.testing.assert_allclose(channels.rotations("lfemur", frame=2), expected[2], atol=1e-14)
    assert channels.intrinsic_order("lfemur") == "YZX" and channels.convention == "pre"
    assert channels.of("lfemur", 2) is None  # an AMC's values need rotations(): no BVH pair


def test_an_amc_joint_without_an_asf_frame_turns_about_the_motions_axes(angles):
    channels = FileChannels(orders={"root": "XYZ"}, angles={"root": angles}, kind="amc")
    expected = about("Z", angles[:, 2]) @ about("Y", angles[:, 1]) @ about("X", angles[:, 0])
    np.testing.assert_allclose(channels.rotations("root"), expected, atol=1e-14)


def test_a_one_dof_amc_elbow_is_its_one_column(rng, frame_c):
    bend = rng.uniform(0.0, 150.0, size=(5, 1))
    channels = FileChannels(orders={"lradius": "X"}, angles={"lradius": bend}, kind="amc", axes={"lradius": frame_c})
    expected = frame_c @ about("X", bend[:, 0]) @ frame_c.T
    np.testing.assert_allclose(channels.rotations("lradius"), expected, atol=1e-14)
    assert channels.label_of("lradius") == ("Xrotation",)


@pytest.mark.parametrize("kind", ["bvh", "amc"])
def test_angles_from_gives_the_file_columns_back(kind, angles, frame_c):
    axes = {"j": frame_c} if kind == "amc" else {}
    channels = FileChannels(orders={"j": "YXZ"}, angles={"j": angles}, kind=kind, axes=axes)
    back = channels.angles_from("j", channels.rotations("j"), degrees)
    np.testing.assert_allclose(back, angles, atol=1e-9)
    # another motion's rotations (an edit): the columns that make exactly those
    other = nearest_rotation(np.eye(3) + 0.3 * np.random.default_rng(5).normal(size=(6, 3, 3)))
    remade = FileChannels(
        orders={"j": "YXZ"}, angles={"j": channels.angles_from("j", other, degrees)}, kind=kind, axes=axes
    )
    np.testing.assert_allclose(remade.rotations("j"), other, atol=1e-12)


def test_still_make_holds_within_the_tolerance_only(angles, frame_c):
    channels = FileChannels(orders={"j": "ZYX"}, angles={"j": angles}, kind="amc", axes={"j": frame_c})
    made = channels.rotations("j")
    assert channels.still_make("j", made) and channels.still_make("j", made[3], frame=3)
    nudged = made.copy()
    nudged[2, 0, 1] += 0.5 * FILE_MATCH_TOLERANCE
    assert channels.still_make("j", nudged)
    nudged[2, 0, 1] += 2 * FILE_MATCH_TOLERANCE
    assert not channels.still_make("j", nudged)  # an edit moved frame 2
    assert not channels.still_make("j", made[:-1])  # other frames: another motion
    assert not channels.still_make("j", made[2], frame=3)


def test_labels_are_the_files_or_the_axes_and_a_joint_without_channels_has_none(angles):
    channels = FileChannels(
        orders={"a": "ZXY", "b": "XY"},
        angles={"a": angles, "b": angles[:, :2]},
        labels={"b": ("rx", "ry")},
    )
    assert channels.label_of("a") == ("Zrotation", "Xrotation", "Yrotation")
    assert channels.label_of("b") == ("rx", "ry")
    assert channels.label_of("End Site") == () and channels.of("End Site", 0) is None


def test_file_channels_are_frozen_and_compared_by_identity(angles):
    channels = FileChannels(orders={"j": "ZXY"}, angles={"j": angles})
    with pytest.raises(AttributeError):
        channels.kind = "amc"  # a frozen record: what was read stays what was read
    twin = FileChannels(orders={"j": "ZXY"}, angles={"j": angles})
    assert channels == channels and channels != twin  # by identity: arrays are not compared
    assert len({channels, twin}) == 2  # hashable by identity (dicts of arrays are not)
