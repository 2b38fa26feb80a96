"""TRC files and the MarkerSet conversions."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.markers import read_markers
from gmr_studio.core.markers.markerset import Z_UP_TO_Y_UP, MarkerSet, split_subject
from gmr_studio.core.markers.trc import read_trc, trc_text
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
