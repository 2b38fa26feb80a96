"""Bad ASF and AMC files: one MotionFileError each, with the line, column and what was expected."""

from __future__ import annotations

import re

import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.acclaim import read_amc, read_asf
from tests.test_acclaim import SKELETON

ASF_CASES = {
    "unknown child in hierarchy": (
        SKELETON.replace("hip knee\n", "hip kneee\n"),
        "60:9: unknown bone 'kneee' in :hierarchy (not in :bonedata)",
    ),
    "unknown parent in hierarchy": (
        SKELETON.replace("spine head", "spin head"),
        "62:5: unknown bone 'spin' in :hierarchy (not in :bonedata)",
    ),
    "cycle": (
        SKELETON.replace("root hip spine", "root hip").replace("spine head", "spine head\n    head spine"),
        "63:10: bone 'spine' is in a cycle in :hierarchy: it never reaches 'root'",
    ),
    "orphan": (
        SKELETON.replace("root hip spine", "root hip"),
        "57:1: bones not in :hierarchy (no parent): spine; every bone must hang from the root",
    ),
    "two parents": (
        SKELETON.replace("spine head", "spine head\n    hip head"),
        "63:9: bone 'head' has a second parent (first given at line 62)",
    ),
    "root as a child": (
        SKELETON.replace("spine head", "spine head root"),
        "62:16: 'root' cannot be a child (it is the top of the hierarchy)",
    ),
    "missing hierarchy": (
        SKELETON.split(":hierarchy")[0],
        "57:1: the file has no :hierarchy section (an ASF needs :root, :bonedata and :hierarchy)",
    ),
    "missing bonedata": (
        re.sub(r":bonedata.*?(?=:hierarchy)", "", SKELETON, flags=re.S),
        "23:1: the file has no :bonedata section",
    ),
    "missing root": (
        re.sub(r":root.*?(?=:bonedata)", "", SKELETON, flags=re.S),
        "59:1: the file has no :root section",
    ),
    "missing end of hierarchy": (SKELETON.rsplit("end", 1)[0], "63:1: expected 'end' closing :hierarchy"),
    "direction with two numbers": (
        SKELETON.replace("direction 0 -2 0", "direction 0 -2"),
        "20:18: 'direction' needs 3 numbers (x y z), found 2",
    ),
    "unknown dof": (
        SKELETON.replace("dof rz rx", "dof rz rq"),
        "34:13: expected a dof from rx ry rz tx ty tz l, found 'rq'",
    ),
    "dof twice": (SKELETON.replace("dof rz rx", "dof rz rz"), "34:13: dof 'rz' appears twice"),
    "limits do not match the dofs": (
        SKELETON.replace("limits (-10 170) (0 1)", "limits (-10 170)"),
        "35:6: 'limits' needs one (min max) pair per dof (2 pairs), found 2 numbers",
    ),
    "unknown bone keyword": (
        SKELETON.replace("     length 2.5", "     lenght 2.5"),
        "32:6: expected id, name, direction, length, axis, dof, limits, bodymass, cofmass or end in a bone, "
        "found 'lenght'",
    ),
    "unknown section": (SKELETON.replace(":units", ":unitz"), "4:1: expected a section keyword"),
    "section twice": (SKELETON + ":units\n", "64:1: second :units section (the first is at line 4)"),
    "bone name twice": (SKELETON.replace("name spine", "name knee"), "45:11: bone name 'knee' is used twice"),
    "bone without end": (
        SKELETON.replace("     dof ry\n  end\n", "     dof ry\n"),
        "56:1: expected 'end' closing the bone opened at line 50",
    ),
    "bad axis order": (
        SKELETON.replace("axis 15 -5 40 ZYX", "axis 15 -5 40 ZYY"),
        "33:20: expected a rotation order such as XYZ (the three axes, once each), found 'ZYY'",
    ),
    "not a number": (
        SKELETON.replace("length 3\n", "length 3x\n"),
        "21:13: expected a number for 'length', found '3x'",
    ),
    "bad root order": (
        SKELETON.replace("order RZ TX", "order RZ QX"),
        "12:13: expected one of TX TY TZ RX RY RZ in the root order",
    ),
    "bone without name": (
        SKELETON.replace("     name stretch\n", ""),
        "37:1: the bone opened at line 37 has no 'name'",
    ),
    "bad angle unit": (SKELETON.replace("angle deg", "angle grad"), "7:9: expected 'deg' or 'rad' after 'angle'"),
    "bone named root": (SKELETON.replace("name spine", "name root"), "45:11: a bone cannot be named 'root'"),
    # found by fuzzing: int('--1') raised a bare ValueError instead of a MotionFileError
    "id not a whole number": (SKELETON.replace("id 1\n", "id --1\n"), "18:9: expected a whole number after 'id'"),
    # found by the long fuzz run: a huge direction overflowed the norm (a RuntimeWarning, then inf)
    "direction out of range": (
        SKELETON.replace("direction 0 -2 0", "direction 0 -2e200 0"),
        "20:18: '-2e200' is out of range (at most 1e+12)",
    ),
}


@pytest.mark.parametrize("case", list(ASF_CASES))
def test_bad_asf(case):
    text, expected = ASF_CASES[case]
    with pytest.raises(MotionFileError) as error:
        read_asf("bad.asf", text.encode())
    assert str(error.value).startswith("bad.asf:" + expected), str(error.value)


GOOD_AMC = """\
:FULLY-SPECIFIED
:DEGREES
1
root 1 2 3 4 5 6
hip 1 2 3
knee 1 2
stretch 1 2 3 4
head 5
2
root 1 2 3 4 5 6
head 5
knee 1 2
hip 1 2 3
stretch 1 2 3 4
"""

AMC_CASES = {
    "unknown bone": (
        GOOD_AMC.replace("head 5\nknee", "neck 5\nknee"),
        "11:1: unknown bone 'neck': expected a frame number or a bone of skeleton.asf",
    ),
    "too few values": (
        GOOD_AMC.replace("knee 1 2\nstretch", "knee 1\nstretch"),
        "6:7: bone 'knee' has 2 dof (rz rx): expected 2 values, found 1",
    ),
    "too many values": (
        GOOD_AMC.replace("hip 1 2 3\nstretch", "hip 1 2 3 4\nstretch"),
        "13:11: bone 'hip' has 3 dof (rx ry rz): expected 3 values, found 4",
    ),
    "bone missing from a frame": (
        GOOD_AMC.replace("head 5\nknee", "knee"),
        "9:1: frame 2 has no line for bone 'head' (ry): every bone with dofs must appear in every frame",
    ),
    "bone twice in a frame": (
        GOOD_AMC.replace("head 5\nknee", "head 5\nhead 5\nknee"),
        "12:1: bone 'head' appears twice in frame 2 (first at line 11)",
    ),
    "not a number": (GOOD_AMC.replace("knee 1 2\nhip", "knee 1 x2\nhip"), "12:8: expected a number, found 'x2'"),
    "nan": (GOOD_AMC.replace("knee 1 2\nhip", "knee 1 nan\nhip"), "12:8: expected a number, found 'nan'"),
    "hexadecimal": (GOOD_AMC.replace("knee 1 2\nhip", "knee 1 0x2\nhip"), "12:8: expected a number, found '0x2'"),
    "overflow": (
        GOOD_AMC.replace("knee 1 2\nhip", "knee 1 1e999\nhip"),
        "12:8: expected a finite number, found '1e999'",
    ),
    "out of range": (
        GOOD_AMC.replace("knee 1 2\nhip", "knee 1 1e300\nhip"),
        "12:8: '1e300' is out of range (at most 1e+12)",
    ),
    "frame numbers jump": (
        GOOD_AMC.replace("\n2\n", "\n3\n"),
        "9:1: frame number 3: expected 2 (frames count up by one)",
    ),
    "data before the first frame": (
        GOOD_AMC.replace(":DEGREES\n1\n", ":DEGREES\n"),
        "3:1: expected a frame number before the data of bone 'root'",
    ),
    "unknown header keyword": (
        GOOD_AMC.replace(":DEGREES", ":DEGREEZ"),
        "2:1: expected :FULLY-SPECIFIED, :DEGREES, :RADIANS or a frame number, found ':DEGREEZ'",
    ),
    "text after a frame number": (
        GOOD_AMC.replace("\n2\n", "\n2 x\n"),
        "9:3: expected only the frame number on its line, found 'x'",
    ),
    "values for a bone without dofs": (
        GOOD_AMC.replace("head 5\nknee", "head 5\nspine 1\nknee"),
        "12:7: bone 'spine' has 0 dof (none): expected 0 values, found 1",
    ),
}


@pytest.mark.parametrize("case", list(AMC_CASES))
def test_bad_amc(case):
    skeleton = read_asf("skeleton.asf", SKELETON.encode())
    text, expected = AMC_CASES[case]
    with pytest.raises(MotionFileError) as error:
        read_amc("bad.amc", skeleton, data=text.encode())
    assert str(error.value).startswith("bad.amc:" + expected), str(error.value)
    # the same error with CRLF line endings and a comment line (columns and lines unchanged)
    crlf = text.replace("\n", "\r\n").replace(":DEGREES", ":DEGREES # ok", 1) if "DEGREEZ" not in text else None
    if crlf is not None and "DEGREES #" in crlf:
        with pytest.raises(MotionFileError) as again:
            read_amc("bad.amc", skeleton, data=("# comment\r\n" + crlf).encode())
        line, column = expected.split(":")[:2]
        assert (again.value.line, again.value.column) == (int(line) + 1, int(column))


def test_unprintable_bytes_in_a_message_are_shown_escaped(tmp_path):
    """What an ASF or AMC reader found is quoted with its control characters escaped; in an
    AMC's frames every byte up to the space separates values, whichever it is."""
    (tmp_path / "nul.asf").write_bytes(b"\x00\x00" + SKELETON.encode())
    (tmp_path / "skeleton.asf").write_text(SKELETON)
    (tmp_path / "delete.amc").write_bytes(GOOD_AMC.replace("hip 1 2 3\nknee", "hip 1 2 3\x7f\nknee", 1).encode())
    (tmp_path / "zero_width.amc").write_bytes(GOOD_AMC.replace("head 5", "\u200bhead 5", 1).encode())
    (tmp_path / "bell.amc").write_bytes(GOOD_AMC.replace("hip 1 2 3\nknee", "hip 1 2\x073\nknee", 1).encode())
    (tmp_path / "short.amc").write_bytes(GOOD_AMC.replace("hip 1 2 3\nknee", "hip 1 2 \x07\nknee", 1).encode())
    for path, asf, message in [
        (
            "nul.asf",
            None,
            "1:1: expected a section keyword (:version, :name, :units, :documentation, :root, "
            ":bonedata, :hierarchy, :skin), found '\\x00\\x00'",
        ),
        ("delete.amc", "skeleton.asf", "5:9: expected a number, found '3\\x7f'"),
        ("zero_width.amc", "skeleton.asf", "8:1: unknown bone '\\u200bhead': expected a frame number or a bone"),
        ("short.amc", "skeleton.asf", "5:8: bone 'hip' has 3 dof (rx ry rz): expected 3 values, found 2"),
    ]:
        with pytest.raises(MotionFileError) as error:
            read_motion(tmp_path / path, asf=asf and tmp_path / asf)
        assert str(error.value).startswith(f"{tmp_path / path}:{message}"), str(error.value)
        assert str(error.value).isprintable(), str(error.value)
    bell = read_motion(tmp_path / "bell.amc", asf=tmp_path / "skeleton.asf")
    assert bell.n_frames == 2  # 'hip 1 2<BEL>3' holds three values, as 'hip 1 2 3' does


def test_good_amc_reads_and_a_bone_without_dofs_may_be_listed():
    skeleton = read_asf("skeleton.asf", SKELETON.encode())
    assert read_amc("good.amc", skeleton, data=GOOD_AMC.encode()).n_frames == 2
    listed = GOOD_AMC.replace("head 5\nknee", "head 5\nspine\nknee")
    assert read_amc("good.amc", skeleton, data=listed.encode()).n_frames == 2


def test_skeleton_beside_the_amc(tmp_path, capsys):
    amc = tmp_path / "walk.amc"
    amc.write_text(GOOD_AMC)
    with pytest.raises(MotionFileError, match=r"no \.asf skeleton beside this AMC"):
        read_motion(amc)
    (tmp_path / "a.asf").write_text(SKELETON)
    (tmp_path / "b.asf").write_text(SKELETON)
    with pytest.raises(MotionFileError, match=r"several .asf skeletons beside this AMC \(a.asf, b.asf\)"):
        read_motion(amc)
    assert read_motion(amc, asf=tmp_path / "b.asf").n_frames == 2
    # the command line reports it as one line, exit code 2
    assert main(["info", str(amc)]) == 2
    assert "name one with --asf" in capsys.readouterr().err


def test_unreadable_files(tmp_path):
    with pytest.raises(MotionFileError, match="cannot read the file"):
        read_asf(tmp_path / "missing.asf")
    with pytest.raises(MotionFileError, match="cannot read the file"):
        read_amc(tmp_path / "missing.amc", read_asf("s.asf", SKELETON.encode()))
