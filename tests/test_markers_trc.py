"""TRC files (core.markers.trc) and the MarkerSet conversions: real files read and round
tripped, where each header error points, files of exactly five lines, short and single rows,
header rows paired by position, the text written line by line; read_markers picks the reader
by the file's suffix."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats.frames import MAX_ABS_VALUE
from gmr_studio.core.markers import read_markers
from gmr_studio.core.markers.markerset import Z_UP_TO_Y_UP, MarkerSet, split_subject
from gmr_studio.core.markers.trc import read_trc, trc_text, write_trc
from tests.conftest import shared_files

TRC = (
    "PathFileType\t4\t(X/Y/Z)\tt.trc\n"
    "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames\n"
    "100\t100\t3\t2\tmm\t100\t1\t3\n"
    "Frame#\tTime\tS:A\t\t\tB\t\t\n"
    "\t\tX1\tY1\tZ1\tX2\tY2\tZ2\n"
    "\n"
    "1\t0\t1\t2\t3\t4\t5\t6\n"
    "2\t0.01\t1.5\t2.5\t3.5\t\t\t\n"
    "3\t0.02\t2\t3\t4\t4\t5\t6\t\n"
)


def test_small_tab_file_with_a_gap_and_a_subject():
    markers = read_trc("t.trc", TRC.encode())
    assert markers.labels == ("A", "B") and markers.subjects == ("S", "")
    assert markers.rate == 100 and markers.units == "mm" and markers.first_frame == 1
    np.testing.assert_array_equal(markers.positions[0], [[1, 2, 3], [4, 5, 6]])
    assert list(markers.present[:, 1]) == [True, False, True]
    assert markers.index("S:A") == 0 and markers.index("B") == 1


def test_comma_separated_is_the_same():
    comma = read_trc("c.trc", TRC.replace("\t", ",").encode())
    np.testing.assert_array_equal(comma.positions, read_trc("t.trc", TRC.encode()).positions)


#: what each shared TRC holds (frames, markers, rate), read off the files; a file added to the
#: folder without an entry here fails the test until its facts are written down
TRC_FACTS = {
    "opensim-core_dataWithBlanksForMissingMarkers.trc": (464, 40, 250.0),
    "opensim-core_markers_walk.trc": (238, 41, 100.0),
    "opensim_gait2392_subject01_walk1.trc": (151, 41, 60.0),
    "pyomeca_markers_comma_delimited.trc": (93, 51, 100.0),  # its header says 652 (a note says so)
}


@pytest.mark.parametrize("path", shared_files("trc/*.trc"))
def test_real_files_read_and_round_trip(path):
    markers = read_markers(path)
    assert (markers.n_frames, markers.n_markers, markers.rate) == TRC_FACTS[path.name]
    assert markers.units == "mm"
    again = read_trc("again.trc", trc_text(markers).encode())
    np.testing.assert_allclose(again.positions, markers.positions, rtol=1e-9, equal_nan=True)
    assert again.labels == markers.labels and again.rate == markers.rate


@pytest.mark.parametrize(
    ("change", "line", "column", "message"),
    [
        (("PathFileType", "PathType"), 1, 1, "expected 'PathFileType'"),
        (("100\t100\t3\t2\tmm", "100\t100\t3\t2\tfurlong"), 3, 13, "unknown Units 'furlong'"),
        (("100\t100\t3\t2\tmm", "0\t100\t3\t2\tmm"), 3, 1, "positive DataRate"),
        (("\t2.5\t3.5", "\tx\t3.5"), 8, 12, "expected a number, found 'x'"),
        (("4\t5\t6\t\n", "4\t5\t6\t7\n"), 9, 20, "a row has 9 fields, expected 8"),
        (("S:A\t\t\tB", "S:A\t\t\t"), 4, 1, "NumMarkers says 2, but the fourth line names 1"),
    ],
)
def test_bad_trc_files(change, line, column, message):
    with pytest.raises(MotionFileError) as info:
        read_trc("bad.trc", TRC.replace(*change).encode())
    assert (info.value.line, info.value.column) == (line, column), str(info.value)
    assert message in info.value.message


def test_unprintable_bytes_in_a_message_are_shown_escaped(tmp_path):
    for change, message in [
        (("100\t100\t3\t2\tmm", "\x00\t100\t3\t2\tmm"), "3:1: expected a positive DataRate, found '\\x00'"),
        (("100\t100\t3\t2\tmm", "100\t100\t3\t2\tm\x1bm"), "3:13: unknown Units 'm\\x1bm'"),
        (("\t2.5\t3.5", "\t2\x075\t3.5"), "8:12: expected a number, found '2\\x075'"),
    ]:
        path = tmp_path / "bad.trc"
        path.write_bytes(TRC.replace(*change).encode())
        with pytest.raises(MotionFileError) as info:
            read_markers(path)
        assert str(info.value).startswith(f"{path}:{message}"), str(info.value)
        assert str(info.value).isprintable(), str(info.value)


def test_units_axes_and_resampling():
    markers = MarkerSet(
        labels=["A"], positions=[[[1000.0, 2000.0, 3000.0]], [[2000.0, 2000.0, 3000.0]]], rate=10, units="mm"
    )
    metres = markers.in_units("m")
    np.testing.assert_allclose(metres.positions[0, 0], [1, 2, 3])
    y_up = metres.transformed(Z_UP_TO_Y_UP)
    np.testing.assert_allclose(y_up.positions[0, 0], [1, 3, -2])  # z (up) becomes y
    faster = metres.resampled(20)
    assert faster.n_frames == 3 and faster.rate == 20
    np.testing.assert_allclose(faster.positions[:, 0, 0], [1, 1.5, 2])


def test_one_nan_coordinate_makes_the_whole_sample_a_gap():
    markers = MarkerSet(labels=["A"], positions=[[[1.0, np.nan, 3.0]]], rate=1, units="m")
    assert np.isnan(markers.positions).all()
    assert split_subject("Daphnee:ASISr") == ("Daphnee", "ASISr") and split_subject("LASI") == ("", "LASI")


def repeated_tabs(text: str) -> str:
    """The same TRC with the header's value row (and the column-name row) separated by
    doubled tabs, as some OpenSim examples are written: ``100.0<TAB><TAB>100.0<TAB><TAB>...``."""
    lines = text.split("\n")
    lines[2] = "\t\t".join(field.strip() for field in lines[2].split("\t"))
    lines[3] = "\t\t".join(field for field in lines[3].split("\t") if field)
    return "\n".join(lines)


@pytest.mark.parametrize("path", shared_files("trc/opensim_*.trc"))
def test_header_rows_with_repeated_tabs_read_by_key_names(path, tmp_path):
    original = path.read_text()
    layout = repeated_tabs(original)
    assert "60.00\t\t60.00\t\t151\t\t41\t\tmm" in layout  # the layout that was refused
    (tmp_path / "tabs.trc").write_text(layout)
    markers, expected = read_markers(tmp_path / "tabs.trc"), read_markers(path)
    assert (markers.rate, markers.units, markers.n_markers) == (60.0, "mm", 41)
    assert markers.labels == expected.labels and markers.notes == expected.notes == ()
    np.testing.assert_array_equal(markers.positions, expected.positions)


def test_header_keys_and_values_both_with_repeated_tabs_and_an_empty_value():
    doubled = TRC.replace("NumFrames\tNumMarkers", "NumFrames\t\t\tNumMarkers").replace(
        "100\t100\t3\t2\tmm", "100\t\t100\t3\t\t\t2\t\tmm"
    )
    markers = read_trc("t.trc", doubled.encode())
    assert (markers.rate, markers.units, markers.n_markers, markers.n_frames) == (100.0, "mm", 2, 3)
    # a value left empty on purpose: fields pair by position, the error points at its column
    empty = TRC.replace("100\t100\t3\t2\tmm\t100\t1\t3", "100\t100\t3\t2\tfurlong\t100\t\t3")
    with pytest.raises(MotionFileError) as info:
        read_trc("e.trc", empty.encode())
    assert (info.value.line, info.value.column) == (3, 13) and "unknown Units 'furlong'" in info.value.message


def test_the_reader_is_picked_by_the_suffix_in_any_case(tmp_path):
    path = tmp_path / "walk.TRC"
    path.write_text(TRC)
    markers = read_markers(path)
    expected = read_trc("walk.trc", TRC.encode())
    assert markers.n_frames == 3 and markers.labels == expected.labels
    np.testing.assert_array_equal(markers.positions, expected.positions)


def test_the_options_go_to_the_reader():
    # the bytes in hand: no file of that name exists
    markers = read_markers("nowhere/in_hand.trc", data=TRC.encode())
    np.testing.assert_array_equal(markers.positions[0], [[1, 2, 3], [4, 5, 6]])


@pytest.mark.parametrize(("name", "suffix"), [("walk.mkr", ".mkr"), ("walk", ""), ("walk.trc.gz", ".gz")])
def test_a_suffix_no_reader_takes_is_refused(tmp_path, name, suffix):
    path = tmp_path / name
    path.write_text(TRC)  # a TRC's text, but the name decides
    with pytest.raises(MotionFileError) as info:
        read_markers(path)
    assert info.value.message == f"unknown marker format '{suffix}': expected one of .c3d, .trc"
    assert info.value.path == str(path) and info.value.line is None


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
