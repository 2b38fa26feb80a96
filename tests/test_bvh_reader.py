"""The BVH reader: every feature the format allows, and every bad file with its line and column."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.cli import main as cli_main
from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.rotations.euler import matrix_from_euler
from tests.conftest import shared_files, shared_path

SMALL = """HIERARCHY
ROOT Hips
{
\tOFFSET 0 0 0
\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
\tJOINT Spine
\t{
\t\tOFFSET 0 1 0
\t\tCHANNELS 3 Zrotation Xrotation Yrotation
\t\tEnd Site
\t\t{
\t\t\tOFFSET 0 2 0
\t\t}
\t}
}
MOTION
Frames: 2
Frame Time: 0.5
1 2 3 0 0 0 0 0 0
4 5 6 90 0 0 0 0 0
"""


def read(text: str | bytes, name: str = "test.bvh"):
    return read_bvh(name, text.encode() if isinstance(text, str) else text)


def error_of(text: str | bytes) -> MotionFileError:
    with pytest.raises(MotionFileError) as info:
        read(text)
    return info.value


def test_small_file_structure_and_values():
    motion = read(SMALL)
    assert motion.names == ("Hips", "Spine", "Spine_End")
    assert list(motion.parents) == [-1, 0, 1]
    assert motion.rotation_orders == ("ZXY", "ZXY", "")
    assert list(motion.has_translation) == [True, False, False]
    assert motion.frame_time == 0.5 and motion.n_frames == 2
    np.testing.assert_array_equal(motion.offsets[2], [0, 2, 0])  # End Site offset kept
    positions = world_positions(motion)
    np.testing.assert_allclose(positions[0], [[1, 2, 3], [1, 3, 3], [1, 5, 3]])
    # frame 1: hips turned 90 degrees about z carry the spine to -x
    np.testing.assert_allclose(positions[1], [[4, 5, 6], [3, 5, 6], [1, 5, 6]], atol=1e-12)


@pytest.mark.parametrize("newline", ["\r\n", "\r", "\n"])
def test_line_endings(newline):
    motion = read(SMALL.replace("\n", newline))
    np.testing.assert_allclose(world_positions(motion), world_positions(read(SMALL)))


def test_mixed_line_endings_tabs_and_scientific_notation():
    lines = SMALL.replace("1 2 3 0", "1e0\t2.0E+00\t3 0").split("\n")
    text = "\r\n".join(lines[:5]) + "\r" + "\n".join(lines[5:])
    text = text.replace("Frames: 2", "Frames:\t2")
    motion = read(text)
    np.testing.assert_allclose(world_positions(motion)[0, 0], [1, 2, 3])


def test_joint_names_with_punctuation_and_spaces():
    text = SMALL.replace("ROOT Hips", "ROOT mixamorig:Hips.001").replace("JOINT Spine", "JOINT l-spine  upper")
    motion = read(text)
    assert motion.names == ("mixamorig:Hips.001", "l-spine upper", "l-spine upper_End")


def test_mixed_rotation_orders_and_partial_channels():
    text = SMALL.replace("CHANNELS 3 Zrotation Xrotation Yrotation", "CHANNELS 2 Yrotation Xrotation")
    text = text.split("Frame Time: 0.5")[0] + "Frame Time: 0.5\n1 2 3 0 0 0 0 0\n4 5 6 0 0 0 30 40\n"
    motion = read(text)
    assert motion.rotation_orders == ("ZXY", "YX", "")
    expected = matrix_from_euler(np.radians([30.0, 40.0]), "YX")
    np.testing.assert_allclose(motion.rotations[1, 1], expected, atol=1e-15)


def test_position_channels_on_a_joint_replace_its_offset_in_any_order():
    text = SMALL.replace(
        "CHANNELS 3 Zrotation Xrotation Yrotation",
        "CHANNELS 6 Zrotation Xposition Xrotation Zposition Yrotation Yposition",
    )
    text = text.replace("1 2 3 0 0 0 0 0 0", "1 2 3 0 0 0 0 7 0 8 0 9").replace(
        "4 5 6 90 0 0 0 0 0", "4 5 6 0 0 0 0 7 0 8 0 9"
    )
    motion = read(text)
    assert motion.rotation_orders[1] == "ZXY" and motion.has_translation[1]
    np.testing.assert_array_equal(motion.translations[:, 1], [[7, 9, 8], [7, 9, 8]])
    np.testing.assert_allclose(world_positions(motion)[0, 1], [8, 11, 11])


def test_several_roots_and_zero_frames():
    text = SMALL.split("MOTION")[0].replace("ROOT Hips", "ROOT A") + SMALL.split("MOTION")[0].split("HIERARCHY\n")[
        1
    ].replace("ROOT Hips", "ROOT B").replace("JOINT Spine", "JOINT Spine2")
    motion = read(text + "MOTION\nFrames: 0\nFrame Time: 0.1\n")
    assert list(motion.roots) == [0, 3] and motion.n_frames == 0


def test_brace_on_the_same_line_and_trailing_blank_lines():
    text = SMALL.replace("ROOT Hips\n{", "ROOT Hips {") + "\n\n   \n"
    assert read(text).n_frames == 2


@pytest.mark.parametrize("path", shared_files("**/*.bvh"))
def test_real_files_load(path):
    motion = read_bvh(path)
    assert motion.n_frames > 0 and np.isfinite(motion.rotations).all()
    motion.check_invariants()


def test_cmu_01_01_structure():
    from tests.conftest import shared_path

    motion = read_bvh(shared_path("cmu/subject01/01_01.bvh"))
    assert motion.n_joints == 38 and motion.n_frames == 2752
    assert sum(n.endswith("_End") for n in motion.names) == 7
    assert motion.frame_time == pytest.approx(0.0083333)


# ------------------------------------------------------------------------ bad files
def assert_error(error: MotionFileError, line: int, column: int, *fragments: str) -> None:
    assert (error.line, error.column) == (line, column), str(error)
    for fragment in fragments:
        assert fragment in error.message, error.message
    assert str(error).startswith(f"test.bvh:{line}:{column}: ")


def test_truncated_hierarchy():
    text = "\n".join(SMALL.split("\n")[:9])
    assert_error(error_of(text), 10, 1, "unexpected end of file", "'}' closing JOINT 'Spine'")


def test_missing_closing_brace_before_motion():
    text = SMALL.replace("\t}\n}\nMOTION", "\t}\nMOTION")
    assert_error(error_of(text), 15, 1, "expected '}' closing ROOT 'Hips' (opened at line 2) before MOTION")


def test_extra_closing_brace():
    text = SMALL.replace("}\nMOTION", "}\n}\nMOTION")
    assert_error(error_of(text), 16, 1, "expected 'ROOT' or 'MOTION', found '}'")


def test_unknown_channel_name():
    text = SMALL.replace("CHANNELS 3 Zrotation Xrotation Yrotation", "CHANNELS 3 Zrotation Xrot Yrotation")
    assert_error(error_of(text), 9, 24, "unknown channel 'Xrot'", "Xposition")


def test_frame_with_too_many_values():
    text = SMALL.replace("4 5 6 90 0 0 0 0 0", "4 5 6 90 0 0 0 0 0 7")
    assert_error(error_of(text), 20, 20, "frame 2 has 10 values, expected 9")


def test_frame_with_too_few_values():
    text = SMALL.replace("1 2 3 0 0 0 0 0 0", "1 2 3 0 0 0 0 0")
    assert_error(error_of(text), 19, 16, "frame 1 has 8 values, expected 9")


def test_fewer_frames_than_promised():
    text = SMALL.replace("Frames: 2", "Frames: 5")
    assert_error(error_of(text), 21, 1, "ends after 2 frames", "'Frames:' on line 17 promised 5")


def test_more_frames_than_promised_are_read_and_said():
    """assimp's Boxing_Toes.bvh holds one row more than ``Frames:`` counts; Blender reads every
    row, and so do we, saying so in the motion's comments (the GMR header and ``gmr info``)."""
    motion = read(SMALL.replace("Frames: 2", "Frames: 1"))
    assert motion.n_frames == 2
    np.testing.assert_allclose(world_positions(motion), world_positions(read(SMALL)), rtol=0, atol=0)
    assert motion.comments == (
        "the MOTION section holds 2 frame lines, 1 more than the 1 that 'Frames:' on line 17 promises: "
        "all 2 were read (as Blender does)",
    )
    assert read(SMALL).comments == ()


def test_an_extra_frame_line_with_the_wrong_count_is_still_an_error():
    text = SMALL.replace("Frames: 2", "Frames: 1").replace("4 5 6 90 0 0 0 0 0", "4 5 6 90 0 0 0 0")
    assert_error(error_of(text), 20, 17, "frame 2 has 8 values, expected 9")


def test_a_gmr_file_with_more_frames_than_promised_is_refused():
    """GMR is the project's own format: its writer counts right, so extra rows mean damage."""
    from gmr_studio.core.formats.gmr import read_gmr
    from gmr_studio.core.formats.textmotion import format_text_motion
    from gmr_studio.core.kinematics.convention import pre_from_post

    text = "".join(format_text_motion(pre_from_post(read(SMALL)), "gmr")).replace("Frames: 2", "Frames: 1")
    with pytest.raises(MotionFileError, match="more frame lines than the 1 promised"):
        read_gmr("test.gmr", text.encode())


def test_the_assimp_boxing_take_with_one_row_too_many_reads_every_row():
    motion = read_bvh(shared_path("bvh/assimp_Boxing_Toes.bvh"))
    assert motion.n_frames == 3070 and motion.frame_rate == pytest.approx(100)
    assert "3070 frame lines, 1 more than the 3069" in motion.comments[-1]


def test_non_numeric_value():
    text = SMALL.replace("4 5 6 90", "4 5 six 90")
    assert_error(error_of(text), 20, 5, "frame 2, value 3: expected a number, found 'six'")


@pytest.mark.parametrize("bad", ["nan", "inf", "-Infinity"])
def test_non_finite_values_are_refused(bad):
    text = SMALL.replace("4 5 6 90", f"4 5 {bad} 90")
    assert_error(error_of(text), 20, 5, "expected a finite number")


def test_value_too_large_for_a_float():
    assert_error(error_of(SMALL.replace("4 5 6 90", "4 5 1e999 90")), 20, 5, "out of range")
    assert_error(error_of(SMALL.replace("4 5 6 90", "4 5 1e300 90")), 20, 5, "out of range")
    assert_error(error_of(SMALL.replace("OFFSET 0 1 0", "OFFSET 0 1e309 0")), 8, 12, "out of range")


def test_non_numeric_offset():
    assert_error(error_of(SMALL.replace("OFFSET 0 1 0", "OFFSET 0 one 0")), 8, 12, "expected a number for OFFSET")


def test_duplicate_joint_names():
    text = SMALL.replace("JOINT Spine", "JOINT Hips")
    assert_error(error_of(text), 6, 8, "joint name 'Hips' is used twice (first at line 2)")


def test_missing_hierarchy_keyword():
    assert_error(error_of(SMALL.replace("HIERARCHY", "HIERARCHIE")), 1, 1, "expected 'HIERARCHY'")


def test_bad_frames_and_frame_time_lines():
    assert_error(error_of(SMALL.replace("Frames: 2", "Frames: two")), 17, 9, "whole number of frames")
    assert_error(error_of(SMALL.replace("Frames: 2", "Frames: -2")), 17, 9, "whole number of frames")
    assert_error(error_of(SMALL.replace("Frame Time: 0.5", "Frame Time: 0")), 18, 13, "positive number of seconds")
    assert_error(error_of(SMALL.replace("Frames: 2", "Framez: 2")), 17, 1, "expected 'Frames: <count>'")


def test_unprintable_bytes_in_a_message_are_shown_escaped(tmp_path, capsys):
    """A file starting with NUL bytes says what it found, escaped, on one line; a long run is
    cut after 40 characters."""
    cases = [
        (
            "nul.bvh",
            b"\x00\x00\x00\x00" + SMALL.encode(),
            "1:1: expected 'HIERARCHY', found '\\x00\\x00\\x00\\x00HIERARCHY'",
        ),
        (
            "bell.bvh",
            SMALL.replace("Frames: 2", "Frames: \x07").encode(),
            "17:9: expected a whole number of frames after 'Frames:', found '\\x07'",
        ),
        ("tab.gmr", b"GMR 1\n\x01\x02\x1b[31m\n", "2:1: expected 'HIERARCHY', found '\\x01\\x02\\x1b[31m'"),
        ("zeros.bvh", b"\x00" * 5000, "1:1: expected 'HIERARCHY', found '" + "\\x00" * 40 + "...'"),
        (
            "value.bvh",
            SMALL.replace("4 5 6", "4 5\x006").encode(),
            "20:3: frame 2, value 2: expected a number, found '5\\x006'",
        ),
    ]
    for name, data, message in cases:
        (tmp_path / name).write_bytes(data)
        with pytest.raises(MotionFileError) as info:
            read_motion(tmp_path / name)
        assert str(info.value).startswith(f"{tmp_path / name}:{message}"), str(info.value)
        assert str(info.value).isprintable(), str(info.value)
    assert cli_main(["info", str(tmp_path / "nul.bvh")]) == 2
    assert capsys.readouterr().err == f"{tmp_path / 'nul.bvh'}:{cases[0][2]}\n"


def test_channel_count_larger_than_the_names_given():
    text = SMALL.replace("CHANNELS 3 Zrotation Xrotation Yrotation", "CHANNELS 4 Zrotation Xrotation Yrotation")
    assert_error(error_of(text), 10, 3, "unknown channel 'End'")


def test_missing_offset():
    text = SMALL.replace("\t\tOFFSET 0 1 0\n", "")
    assert_error(error_of(text), 13, 2, "JOINT 'Spine' (line 6) has no OFFSET")


def test_non_utf8_bytes_in_a_name():
    data = SMALL.encode().replace(b"Spine", b"Sp\xffine", 1)
    assert_error(error_of(data), 6, 10, "not UTF-8")


def test_empty_file_and_missing_file(tmp_path):
    assert_error(error_of(""), 1, 1, "unexpected end of file", "'HIERARCHY'")
    with pytest.raises(MotionFileError, match="cannot read the file"):
        read_bvh(tmp_path / "nothing.bvh")


def test_enormous_frame_claim_is_refused_without_allocating():
    error = error_of(SMALL.replace("Frames: 2", "Frames: 1000000000000"))
    assert "promised 1000000000000" in error.message
