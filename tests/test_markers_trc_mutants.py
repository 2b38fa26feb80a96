"""The TRC reader and writer (core.markers.trc) on the conditions the file tests leave open
(mutation testing, docs/reliability.md): where each header error points, files of exactly five
lines, short and single rows, header rows paired by position, and the text written, line by line."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats.frames import MAX_ABS_VALUE
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.markers.trc import read_trc, trc_text, write_trc
from tests.test_markers_trc import TRC


def error(text: str | bytes) -> MotionFileError:
    with pytest.raises(MotionFileError) as info:
        read_trc("bad.trc", text if isinstance(text, bytes) else text.encode())
    return info.value


def where(text: str | bytes) -> tuple[int, int | None, str]:
    found = error(text)
    return found.line, found.column, found.message


@pytest.mark.parametrize("line", [1, 2, 3, 4])
def test_bytes_that_are_not_utf8_in_each_header_line(line):
    lines = TRC.encode().split(b"\n")
    lines[line - 1] = lines[line - 1][:3] + b"\xff" + lines[line - 1][3:]
    assert where(b"\n".join(lines)) == (line, 4, "bytes that are not UTF-8 text")


def test_a_file_of_exactly_the_five_header_lines_has_no_frames():
    header = "\n".join(TRC.split("\n")[:5])
    markers = read_trc("h.trc", header.encode())
    assert markers.n_frames == 0 and markers.n_markers == 2 and markers.first_frame == 1
    assert markers.notes == ("the header says NumFrames 3; the file holds 0 frames",)
    four = "\n".join(TRC.split("\n")[:4])
    assert where(four) == (4, 1, "unexpected end of file: a TRC header has five lines")


def test_the_rows_may_start_right_after_the_header():
    markers = read_trc("t.trc", TRC.replace("Z2\n\n", "Z2\n").encode())
    assert markers.n_frames == 3 and markers.first_frame == 1
    np.testing.assert_array_equal(markers.positions[0], [[1, 2, 3], [4, 5, 6]])


@pytest.mark.parametrize(
    ("change", "line", "column", "message"),
    [
        (("\tNumMarkers\t", "\tNumMarkerz\t"), 2, 1, "the header has no NumMarkers"),
        (("\tUnits\t", "\tUnitz\t"), 2, 1, "the header has no Units"),
        (("DataRate\tCameraRate", "DataRat\tCameraRat"), 2, 1, "the header has no DataRate: use --rate HZ"),
        (("100\t100\t3\t2", "abc\t100\t3\t2"), 3, 1, "expected a positive DataRate, found 'abc': use --rate HZ"),
        (("100\t100\t3\t2", "100\t100\t3\t2.0"), 3, 11, "expected a whole NumMarkers, found '2.0'"),
        (("Frame#\tTime", "Frame\tTime"), 4, 1, "expected 'Frame#' and 'Time' to start the fourth line"),
    ],
)
def test_where_each_header_error_points(change, line, column, message):
    assert where(TRC.replace(*change)) == (line, column, message)


def test_a_camera_rate_stands_in_for_the_data_rate_and_any_positive_rate_is_read():
    markers = read_trc("t.trc", TRC.replace("DataRate\t", "Rate\t").replace("100\t100\t3", "100\t0.5\t3").encode())
    assert markers.rate == 0.5
    assert read_trc("t.trc", TRC.replace("100\t100\t3", "0.25\t100\t3").encode()).rate == 0.25


def test_the_frame_count_note_only_for_a_whole_count():
    assert read_trc("t.trc", TRC.encode()).notes == ()
    more = read_trc("t.trc", TRC.replace("100\t100\t3\t2", "100\t100\t5\t2").encode())
    assert more.notes == ("the header says NumFrames 5; the file holds 3 frames",)
    assert read_trc("t.trc", TRC.replace("100\t100\t3\t2", "100\t100\tn/a\t2").encode()).notes == ()
    absent = TRC.replace("\tNumFrames\t", "\tFrames\t")
    assert read_trc("t.trc", absent.encode()).notes == ()


def test_header_values_left_empty_pair_by_position():
    """An empty CameraRate: seven values for eight keys, paired by their columns."""
    markers = read_trc("t.trc", TRC.replace("100\t100\t3\t2\tmm", "100\t\t3\t2\tmm").encode())
    assert (markers.rate, markers.n_markers, markers.units) == (100.0, 2, "mm")
    # a key column left empty too: keys and values keep their columns
    lines = TRC.split("\n")
    lines[1], lines[2] = "DataRate\t\tNumMarkers\tUnits\tNumFrames", "100\t\t2\tmm\t"
    markers = read_trc("t.trc", "\n".join(lines).encode())
    assert (markers.rate, markers.n_markers, markers.units, markers.notes) == (100.0, 2, "mm", ())


def test_rows_with_their_last_fields_left_off_are_gaps():
    short = TRC.replace("2\t0.01\t1.5\t2.5\t3.5\t\t\t\n", "2\t0.01\t1.5\t2.5\n")
    markers = read_trc("t.trc", short.encode())
    np.testing.assert_array_equal(markers.present, [[True, True], [False, False], [True, True]])
    np.testing.assert_array_equal(markers.positions[2], [[2, 3, 4], [4, 5, 6]])


def test_a_single_row():
    one = TRC.split("\n")[:7]
    markers = read_trc("t.trc", "\n".join(one).encode())
    assert markers.n_frames == 1
    np.testing.assert_array_equal(markers.positions[0], [[1, 2, 3], [4, 5, 6]])


def test_values_beyond_the_range_and_rows_without_frame_numbers():
    big = TRC.replace("\t2.5\t3.5", "\t1e300\t3.5")
    assert where(big) == (8, 12, f"'1e300' is out of range (at most {MAX_ABS_VALUE:g})")
    numberless = TRC.replace("2\t0.01\t1.5", "\t0.01\t1.5").replace("3\t0.02\t2", "\t0.02\t2")
    assert where(numberless) == (8, 1, "a row has no frame number")


def test_a_bad_value_after_a_gap_is_the_one_named():
    text = TRC.replace("3\t0.02\t2\t3\t4\t4\t5\t6", "3\t0.02\t2\t3\t4\t4\tx\t6")
    assert where(text) == (9, 16, "expected a number, found 'x'")


def small_set(**changes) -> MarkerSet:
    positions = np.array([[[0.1234567891234, 2.0, 3.0], [4.0, 5.0, 6.0]], [[1.0, 2.0, 3.0], [np.nan] * 3]])
    fields = {"labels": ["A", "B"], "subjects": ["S", ""], "positions": positions, "rate": 3.0, "units": "mm"}
    return MarkerSet(**{**fields, "first_frame": 5, **changes})


def test_the_text_written_line_by_line():
    lines = trc_text(small_set()).split("\n")
    assert lines[0] == "PathFileType\t4\t(X/Y/Z)\tmarkers.trc"
    assert lines[2] == "3\t3\t2\t2\tmm\t3\t5\t2"
    assert lines[3] == "Frame#\tTime\tS:A\t\t\tB"
    assert lines[4] == "\t\tX1\tY1\tZ1\tX2\tY2\tZ2"
    assert lines[6] == "5\t0\t0.1234567891\t2\t3\t4\t5\t6"
    assert lines[7] == "6\t0.3333333333\t1\t2\t3\t\t\t"
    assert lines[8:] == [""]
    named = trc_text(small_set(source="/data/walk.c3d")).split("\n")[0]
    assert named == "PathFileType\t4\t(X/Y/Z)\twalk.c3d"


def test_write_trc_writes_the_text_with_ten_digits(tmp_path):
    write_trc(small_set(), tmp_path / "w.trc")
    assert (tmp_path / "w.trc").read_text() == trc_text(small_set(), 10)
    assert "\t0.1234567891\t" in trc_text(small_set())
    assert "\t0.12345679\t" in trc_text(small_set(), 8)
