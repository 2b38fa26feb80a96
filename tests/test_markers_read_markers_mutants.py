"""read_markers, the readers' entry point (core/markers/__init__.py), on what the file tests
leave open (mutation testing, docs/reliability.md): the reader picked by the suffix in any
case, the options handed to it, and the refusal of a suffix no reader takes."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.markers import MARKER_READERS, read_markers
from gmr_studio.core.markers.c3d import read_c3d
from gmr_studio.core.markers.trc import read_trc
from tests.test_markers_trc import TRC


def test_the_reader_is_picked_by_the_suffix_in_any_case(tmp_path):
    assert MARKER_READERS == {".trc": read_trc, ".c3d": read_c3d}
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
