"""The GMR text format: write -> read round trips and bad files."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.edits.operations import shift_root, split, split_all
from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.formats.gmr import gmr_text, read_gmr, write_gmr
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import forward_kinematics
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.space.units import UNITS
from tests.conftest import random_motion, shared_files


def reread(motion):
    return read_gmr("round-trip.gmr", gmr_text(motion).encode())


def assert_same_motion(a, b, relative=1e-9):
    """Same names, structure and positions; joints matched by name."""
    index = [b.names.index(n) for n in a.names]
    names = lambda m, arr: [m.names[i] if i >= 0 else None for i in arr]  # noqa: E731
    assert names(a, a.parents) == names(b, b.parents[index])
    assert names(a, a.soft_parents) == names(b, b.soft_parents[index])
    assert [a.rotation_orders[j] for j in range(a.n_joints)] == [b.rotation_orders[i] for i in index]
    assert list(a.has_translation) == list(b.has_translation[index])
    pa, wa = forward_kinematics(a)
    pb, wb = forward_kinematics(b)
    assert np.abs(pa - pb[:, index]).max(initial=0) <= relative * a.size
    np.testing.assert_allclose(wa, wb[:, index], atol=1e-12)
    np.testing.assert_allclose(a.offsets, b.offsets[index], rtol=0, atol=0)  # offsets print exactly
    assert a.frame_time == b.frame_time and a.comments == b.comments and a.facts == b.facts


@pytest.mark.parametrize("path", shared_files("**/*.bvh"))
def test_round_trip_of_real_files_in_several_configurations(path, tmp_path):
    gmr = pre_from_post(read_bvh(path))
    far = gmr.names[int(np.argmax(gmr.depths))]
    for motion in (gmr, shift_root(gmr, far), split(split(gmr, 3), 5), split_all(gmr)):
        out = tmp_path / "motion.gmr"
        write_gmr(motion, out)
        assert_same_motion(motion, read_gmr(out))


def test_forest_with_soft_links_and_comments(rng):
    motion = split(random_motion(rng, [-1, 0, 1, 1, -1, 4], n_frames=5, translation_joints=(2,)), 3)
    motion = motion.replace(comments=("converted from test data",), facts=FileFacts(unit=UNITS["cm"], up_axis="z"))
    text = gmr_text(motion)
    assert text.startswith("GMR 1\n# units: cm\n# up axis: z\n# converted from test data\nHIERARCHY\n")
    assert "SOFTLINK j1" in text and text.count("ROOT ") == 3
    assert_same_motion(motion, reread(motion))


def test_write_is_exact_to_the_printed_precision(rng):
    motion = random_motion(rng, [-1, 0, 1, 2], n_frames=20)
    again = reread(motion)
    np.testing.assert_allclose(again.rotations, motion.rotations, atol=5e-15)
    np.testing.assert_allclose(again.translations, motion.translations, rtol=1e-14)


SMALL_GMR = """GMR 1
# a comment
HIERARCHY
ROOT A
{
\tOFFSET 0 0 0
\tCHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
\tJOINT B
\t{
\t\tOFFSET 0 1 0
\t\tCHANNELS 3 Zrotation Yrotation Xrotation
\t}
}
ROOT C
{
\tSOFTLINK B
\tOFFSET 0 0 0
\tCHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
}
MOTION
Frames: 1
Frame Time: 0.01
0 0 0 0 0 0 0 0 0 0 1 0 0 0 0
"""


def error_of(text: str) -> MotionFileError:
    with pytest.raises(MotionFileError) as info:
        read_gmr("bad.gmr", text.encode())
    return info.value


def test_small_file_reads():
    motion = read_gmr("ok.gmr", SMALL_GMR.encode())
    assert motion.names == ("A", "B", "C") and list(motion.soft_parents) == [-1, -1, 1]
    assert motion.comments == ("a comment",)


@pytest.mark.parametrize(
    ("change", "line", "column", "message"),
    [
        (("GMR 1", "BVH 1"), 1, 1, "expected 'GMR 1'"),
        (("GMR 1", "GMR 2"), 1, 1, "expected 'GMR 1'"),
        (("SOFTLINK B", "SOFTLINK Z"), 16, 11, "SOFTLINK names an unknown joint 'Z'"),
        (("\t\tOFFSET 0 1 0\n", "\t\tSOFTLINK A\n\t\tOFFSET 0 1 0\n"), 10, 12, "must join two different trees"),
        (("\t\tCHANNELS 3 Zrotation Yrotation Xrotation\n", ""), 11, 2, "GMR joint 'B' (line 8) needs rotation"),
        (("\t\tOFFSET 0 1 0\n", "\t\tOFFSET 0 1 0\n\t\tEnd Site\n"), 11, 3, "found 'End'"),
        (("\tSOFTLINK B\n", "\tSOFTLINK B\n\tSOFTLINK B\n"), 17, 2, "second SOFTLINK"),
    ],
)
def test_bad_gmr_files(change, line, column, message):
    error = error_of(SMALL_GMR.replace(*change))
    assert (error.line, error.column) == (line, column), str(error)
    assert message in error.message


def test_write_refuses_a_post_rotation_motion(rng):
    with pytest.raises(ValueError, match="pre-rotation"):
        gmr_text(random_motion(rng, [-1, 0], convention="post"))
