"""The C3D reader's own rules (core.markers.c3d) on conditions no real file holds: the
header's checks and announced frames on 512-byte headers written here, the child process's
command and exits with ``subprocess.run`` stood in for, and ezc3d's decoded points turned into
a marker set (gaps, computed samples, notes, labels, analysis outputs).

Private names: the reader's steps after ezc3d (``_marker_set``, ``_labels``...) and the
child-process call are reached directly, because the only public way in is a C3D file that
ezc3d decodes, and these conditions (a hostile header, a crashing child, residual patterns)
cannot be written as one."""

from __future__ import annotations

import io
import json
import os
import struct
import subprocess
import sys

import numpy as np
import pytest

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.markers import c3d as c3d_module
from gmr_studio.core.markers.c3d import _check_header, _clean, _labels, _marker_set, _output_kinds, read_c3d


def header_bytes(block: int = 2, processor: int = 84, first: int = 1, last: int = 10, size: int = 1024) -> bytes:
    """A C3D's first ``size`` bytes: the parameter section at ``block``, its processor byte,
    the header's first and last frame (16-bit, big-endian for SGI)."""
    data = bytearray(size)
    data[0], data[1] = block, 0x50
    data[6:10] = struct.pack(">HH" if processor == 86 else "<HH", first, last)
    start = (block - 1) * 512
    if start + 3 < size:
        data[start + 3] = processor
    return bytes(data)


def checked(tmp_path, data: bytes) -> tuple[int, int]:
    path = tmp_path / "h.c3d"
    path.write_bytes(data)
    return _check_header(path, str(path))


def header_error(tmp_path, data: bytes) -> str:
    with pytest.raises(MotionFileError) as info:
        checked(tmp_path, data)
    return info.value.message


@pytest.mark.parametrize(
    ("first", "last", "announced"),
    [(1, 10, 10), (5, 5, 1), (7, 0xFFFE, 0xFFFE - 7 + 1), (1, 0xFFFF, 0), (10, 9, 0), (0, 0, 1)],
)
@pytest.mark.parametrize("processor", [84, 85, 86])
def test_the_frames_the_header_announces(tmp_path, first, last, announced, processor):
    data = header_bytes(processor=processor, first=first, last=last)
    assert checked(tmp_path, data) == (1024, announced)


def test_the_parameter_section_may_end_the_file(tmp_path):
    """Block 2 starts at byte 512: a file of 516 bytes holds its first four bytes, 515 does not."""
    assert checked(tmp_path, header_bytes(size=516)) == (516, 10)
    assert "(block 2) lies outside the file" in header_error(tmp_path, header_bytes(size=515))
    assert "(block 3) lies outside the file" in header_error(tmp_path, header_bytes(block=3, size=1027))
    assert checked(tmp_path, header_bytes(block=3, size=1028)) == (1028, 10)
    # block 1 is the header itself: its byte 4 is read as the processor
    data = bytearray(header_bytes(block=1))
    assert data[3] == 84 and checked(tmp_path, bytes(data)) == (1024, 10)


def test_the_headers_own_errors(tmp_path):
    assert header_error(tmp_path, b"") == "the file is empty: expected a C3D header of 512 bytes"
    assert header_error(tmp_path, header_bytes()[:511]) == (
        "the file has 511 bytes: a C3D starts with a header of 512 bytes"
    )
    assert checked(tmp_path, header_bytes(size=512, block=1)) == (512, 10)
    wrong = bytearray(header_bytes())
    wrong[1] = 0x51
    assert header_error(tmp_path, bytes(wrong)) == "byte 2 is 81, not 80 (0x50): this is not a C3D file"
    message = header_error(tmp_path, header_bytes(processor=87))
    assert message == "unknown processor type 87 in the parameters: expected 84 (Intel), 85 (DEC), 86 (SGI/MIPS)"
    assert "unknown processor type 83" in header_error(tmp_path, header_bytes(processor=83))
    assert "(block 0) lies outside" in header_error(tmp_path, header_bytes(block=0))


def test_computed_must_be_keep_or_drop(tmp_path):
    with pytest.raises(ValueError, match="computed must be 'keep' or 'drop', not 'yes'"):
        read_c3d(tmp_path / "absent.c3d", computed="yes")


class FakeRun:
    """``subprocess.run`` stood in for: records the call, answers as told."""

    def __init__(self, returncode=0, stdout=b"", stderr=b"", timeout=False):
        self.answer = (returncode, stdout, stderr)
        self.timeout, self.calls = timeout, []

    def __call__(self, command, **options):
        self.calls.append((command, options))
        if self.timeout:
            raise subprocess.TimeoutExpired(command, options["timeout"])
        return subprocess.CompletedProcess(command, *self.answer)


def decoded_archive(points, residuals, meta) -> bytes:
    buffer = io.BytesIO()
    np.savez(buffer, points=points, residuals=residuals, meta=np.array(json.dumps(meta)))
    return buffer.getvalue()


def base_meta(**changes) -> dict:
    return {"labels": ["A", "B"], "units": "mm", "rate": 100.0, "first_frame": 1, **changes}


def test_the_child_process_command_and_limits(tmp_path, monkeypatch):
    data = header_bytes(first=1, last=2, size=2_500_000)
    path = tmp_path / "big.c3d"
    path.write_bytes(data)
    points = np.arange(12, dtype=float).reshape(2, 2, 3)
    fake = FakeRun(stdout=decoded_archive(points, np.ones((2, 2)), base_meta()))
    monkeypatch.setattr(c3d_module.subprocess, "run", fake)
    markers = read_c3d(path)
    np.testing.assert_array_equal(markers.positions, points)
    assert markers.notes == ()  # 2 frames announced, 2 read
    ((command, options),) = fake.calls
    memory = max(4 << 30, 64 * 2_500_000)
    assert command == [
        sys.executable,
        "-m",
        "gmr_studio.core.markers.c3d_worker",
        str(path.resolve()),
        str(memory),
        "12",
        str(os.getpid()),
    ]
    assert options["timeout"] == 6 * 12.5 and options["capture_output"] is True
    assert options["stdin"] == subprocess.DEVNULL
    assert options["env"]["OMP_NUM_THREADS"] == options["env"]["OPENBLAS_NUM_THREADS"] == "1"
    # a file of 100 MB asks for 6.4 GB, above the 4 GB floor; a timeout given is used as it is
    # (private: a 100 MB file would be needed to reach this size through read_markers)
    fake.calls.clear()
    again = c3d_module._decode_in_child(path, str(path), 100_000_000, 3.4)
    np.testing.assert_array_equal(again["points"], points)
    ((command, options),) = fake.calls
    assert command[4:6] == ["6400000000", "3"] and options["timeout"] == 6 * 3.4


def test_the_child_processs_exits(tmp_path, monkeypatch):
    path = tmp_path / "x.c3d"
    path.write_bytes(header_bytes())
    cases = [
        (FakeRun(timeout=True), "ezc3d did not finish reading the file in 60 s: the file is probably corrupt"),
        (FakeRun(3, stderr=b"line one\n  bad header  \n\n"), "ezc3d rejects the file: bad header"),
        (FakeRun(3, stderr=b"gmr: ours"), "ours"),
        (FakeRun(-11), "ezc3d crashed reading the file (signal 11): the file is corrupt"),
        (FakeRun(1, stderr=b"odd"), "ezc3d crashed reading the file (exit status 1) (odd): the file is corrupt"),
        (FakeRun(2, stderr=b" \n"), "ezc3d crashed reading the file (exit status 2): the file is corrupt"),
    ]
    for fake, message in cases:
        monkeypatch.setattr(c3d_module.subprocess, "run", fake)
        with pytest.raises(MotionFileError) as info:
            read_c3d(path)
        assert info.value.message == message


def test_the_last_line_of_a_message():
    assert _clean("first\n  second: iostream error \n\n") == "second"
    assert _clean("  \n") == "no reason given"


def test_errors_of_the_in_process_read(tmp_path, monkeypatch):
    from gmr_studio.core.markers import c3d_worker

    path = tmp_path / "x.c3d"
    path.write_bytes(header_bytes())

    def own(_):
        raise c3d_worker.OwnError("this SGI file is damaged")

    def theirs(_):
        raise RuntimeError("gmr: looks like ours\nbad block")

    monkeypatch.setattr(c3d_worker, "decode_c3d", own)
    with pytest.raises(MotionFileError) as info:
        read_c3d(path, isolate=False)
    assert info.value.message == "this SGI file is damaged"
    monkeypatch.setattr(c3d_worker, "decode_c3d", theirs)
    with pytest.raises(MotionFileError) as info:
        read_c3d(path, isolate=False)
    assert info.value.message == "ezc3d rejects the file: bad block"
    for error in (OSError, ValueError, MemoryError, IndexError):

        def raising(_, error=error):
            raise error("x")

        monkeypatch.setattr(c3d_worker, "decode_c3d", raising)
        with pytest.raises(MotionFileError):
            read_c3d(path, isolate=False)


def decoded(points, residuals, **meta) -> dict:
    full = base_meta(announced_frames=len(points), **meta)
    return {"points": np.asarray(points, dtype=float), "residuals": np.asarray(residuals, dtype=float), "meta": full}


def test_the_in_process_read_gets_the_announced_frames(tmp_path, monkeypatch):
    from gmr_studio.core.markers import c3d_worker

    path = tmp_path / "x.c3d"
    path.write_bytes(header_bytes(first=3, last=7))
    given = decoded(np.ones((4, 2, 3)), np.ones((4, 2)))
    given["meta"].pop("announced_frames")
    monkeypatch.setattr(c3d_worker, "decode_c3d", lambda _: given)
    markers = read_c3d(path, isolate=False)
    assert markers.notes == ("the header announces 5 frames, the file holds 4: it may be truncated",)


def marker_set(points, residuals, computed="keep", **meta):
    return _marker_set(decoded(points, residuals, **meta), "f.c3d", computed, None)


def two_markers():
    """Two markers, three frames: A measured (residual 2) but at frame 1 interpolated
    (residual 0), B with residual 0 throughout and at the origin in frame 2."""
    points = np.arange(1.0, 19.0).reshape(3, 2, 3)
    points[2, 1] = 0.0
    residuals = np.array([[2.0, 0.0], [0.0, 0.0], [2.0, 0.0]])
    return points, residuals


def test_the_zero_residual_rules_on_exact_samples():
    points, residuals = two_markers()
    kept = marker_set(points, residuals)
    # the file records residuals (A's): every zero-residual sample is computed, kept but
    # the one at exactly the origin
    np.testing.assert_array_equal(kept.present, [[True, True], [True, True], [True, False]])
    np.testing.assert_array_equal(kept.computed, [[False, True], [True, True], [False, False]])
    assert kept.notes == (
        "1 samples at exactly (0, 0, 0) with no residual read as gaps",
        "3 samples with residual 0 (50% of the markers' samples: computed by the capture software, not measured) "
        "kept and marked computed",
    )
    np.testing.assert_array_equal(kept.positions[:2], points[:2])
    dropped = marker_set(points, residuals, "drop")
    np.testing.assert_array_equal(dropped.present, [[True, False], [False, False], [True, False]])
    assert not dropped.computed.any() and dropped.notes[1].endswith("read as gaps")
    # no positive residual anywhere: kept, except the sample at exactly the origin
    none = marker_set(points, np.zeros((3, 2)))
    np.testing.assert_array_equal(none.present, [[True, True], [True, True], [True, False]])
    assert none.notes == ("1 samples at exactly (0, 0, 0) with no residual read as gaps",)
    assert not none.computed.any()
    np.testing.assert_array_equal(marker_set(points, np.zeros((3, 2)), "drop").present, none.present)
    # a measured sample at the origin is kept
    measured = marker_set(points, np.full((3, 2), 0.5))
    assert measured.present.all() and measured.notes == ()


def test_invalid_samples_are_gaps_in_every_reading():
    points, residuals = two_markers()
    residuals = np.ones((3, 2))
    residuals[1, 0] = -0.5
    points[2, 1] = [np.inf, 1.0, 2.0]
    for rule in ("keep", "drop"):
        markers = marker_set(points, residuals, rule)
        np.testing.assert_array_equal(markers.present, [[True, True], [False, True], [True, False]])
        assert markers.notes == ()
        assert np.isnan(markers.positions[1, 0]).all() and np.isnan(markers.positions[2, 1]).all()
    assert marker_set(points, np.ones((3, 2)), "drop").present.sum() == 5  # a NaN-free sample counts


def test_a_sample_at_the_origin_with_an_invalid_residual_is_counted_once():
    points = np.zeros((2, 1, 3))
    markers = marker_set(points, [[-1.0], [0.0]], labels=["A"])
    assert not markers.present.any()
    assert markers.notes == ("1 samples at exactly (0, 0, 0) with no residual read as gaps",)
    partly = np.zeros((1, 1, 3))
    partly[0, 0, 2] = 1e-9
    assert marker_set(partly, [[0.0]], labels=["A"]).present.all()


@pytest.mark.parametrize("rate", [0.0, -100.0, float("nan"), float("inf")])
def test_a_rate_that_is_not_positive(rate):
    with pytest.raises(MotionFileError) as info:
        marker_set(np.ones((1, 2, 3)), np.ones((1, 2)), rate=rate)
    assert info.value.message == (
        f"the point rate is {rate:g}: the file does not say how many frames per second it holds; "
        "give the rate it was captured at with --rate HZ"
    )


def test_units_known_and_not():
    assert marker_set(np.ones((1, 2, 3)), np.ones((1, 2)), units=" Metres ").units == "m"
    odd = marker_set(np.ones((1, 2, 3)), np.ones((1, 2)), units=" deg ")
    assert odd.units == "mm" and odd.notes == ("POINT:UNITS is 'deg', not a length unit known here: read as mm",)


def test_the_notes_on_frame_counts():
    one = np.ones((3, 2, 3)), np.ones((3, 2))
    fewer = _marker_set({**decoded(*one), "meta": base_meta(announced_frames=5)}, "f.c3d")
    assert fewer.notes == ("the header announces 5 frames, the file holds 3: it may be truncated",)
    unknown = _marker_set({**decoded(*one), "meta": base_meta(announced_frames=0)}, "f.c3d")
    assert unknown.notes == ()
    long = {"where": "POINT:LONG_FRAMES", "announced": 70000, "read": 3}
    noted = _marker_set(
        {**decoded(*one), "meta": base_meta(announced_frames=5, long_frames=long, notes=["earlier"])}, "f", "auto"
    )
    assert noted.notes == (
        "earlier",
        "POINT:LONG_FRAMES gives 70000 frames, more than the header's 16-bit frame numbers hold: 3 frames read "
        "(the file ends there: it may be truncated)",
    )
    whole = dict(long, read=70000)
    complete = _marker_set({**decoded(*one), "meta": base_meta(announced_frames=5, long_frames=whole)}, "f")
    assert complete.notes[0].endswith(": 70000 frames read")
    meta = base_meta(announced_frames=3, first_frame=12, parameters={"KneeWidth": 100.0})
    fields = _marker_set({**decoded(*one), "meta": meta}, "src.c3d")
    assert (fields.first_frame, fields.source, fields.parameters, fields.rate) == (
        12,
        "src.c3d",
        {"KneeWidth": 100.0},
        100.0,
    )


def test_labels_blank_missing_and_repeated():
    notes: list[str] = []
    subjects, labels = _labels(["S:A", "  ", "S:A", "A", "S:A", "A~2"], 7, notes)
    assert subjects == ["S", "", "S", "", "S", "", ""]
    assert labels == ["A", "M002", "A~2", "A", "A~3", "A~2", "M007"]
    assert notes == [
        "POINT:LABELS names 6 of the 7 points: the others are named M001...",
        "point 3 repeats the label 'S:A': renamed 'A~2'",
        "point 5 repeats the label 'S:A': renamed 'A~3'",
    ]
    exact: list[str] = []
    assert _labels(["A", "B", "C"], 3, exact) == (["", "", ""], ["A", "B", "C"]) and exact == []
    assert _labels(["A", "B", "C"], 2, exact) == (["", ""], ["A", "B"]) and exact == []


def test_output_kinds_by_label_or_bare_label():
    groups = {"ANGLES": ["LHipAngles", "Sam:LKneeAngles"], "COFM": ["CentreOfMass", "LHipAngles"]}
    raw = ["Sam:LHipAngles", "LKneeAngles", "Sam:LKneeAngles", " CentreOfMass ", "LASI", ""]
    assert _output_kinds(raw, 7, groups) == ["angles", "", "angles", "cofm", "", "", ""]


def test_outputs_are_kept_out_of_the_markers():
    points = np.arange(1.0, 1.0 + 2 * 4 * 3).reshape(2, 4, 3)
    residuals = np.array([[1.0, 0.0, 1.0, 0.0], [1.0, 0.0, 0.0, -1.0]])
    markers = marker_set(
        points,
        residuals,
        labels=["S:LASI", "S:LHipAngles", "RASI", "LHipForce"],
        output_groups={"ANGLES": ["LHipAngles"], "FORCES": ["LHipForce"]},
        output_units={"ANGLES": "deg", "Forces": "N"},
    )
    assert markers.labels == ("LASI", "RASI") and markers.subjects == ("S", "")
    np.testing.assert_array_equal(markers.positions[0], points[0, [0, 2]])
    # the markers record residuals: RASI's zero is computed; the outputs' zeros never are
    np.testing.assert_array_equal(markers.present, [[True, True], [True, True]])
    np.testing.assert_array_equal(markers.computed, [[False, False], [False, True]])
    outputs = markers.outputs
    assert outputs.labels == ("LHipAngles", "LHipForce") and outputs.subjects == ("S", "")
    assert outputs.kinds == ("angles", "forces") and outputs.units == {"angles": "deg", "forces": "N"}
    np.testing.assert_array_equal(outputs.values[:, 0], points[:, 1])
    np.testing.assert_array_equal(outputs.values[0, 1], points[0, 3])
    assert np.isnan(outputs.values[1, 1]).all()  # invalid (negative residual)
    assert markers.notes == (
        "1 samples with residual 0 (25% of the markers' samples: computed by the capture software, not measured) "
        "kept and marked computed",
        "2 analysis outputs (1 angles, 1 forces) kept out of the markers",
    )


def test_outputs_with_zero_residuals_do_not_make_a_file_record_residuals():
    """Only the markers' residuals say whether the file records them: an output's positive
    residual leaves the markers' zeros kept."""
    points = np.ones((1, 2, 3))
    markers = marker_set(points, [[0.0, 5.0]], labels=["LASI", "LHipAngles"], output_groups={"ANGLES": ["LHipAngles"]})
    assert markers.present.all() and markers.labels == ("LASI",) and markers.outputs.units == {}
    assert markers.notes == ("1 analysis outputs (1 angles) kept out of the markers",)
    plain = marker_set(points, [[1.0, 1.0]])
    assert plain.outputs is None and plain.labels == ("A", "B")


def test_a_missing_file_and_a_reason_without_text(tmp_path, monkeypatch):
    with pytest.raises(MotionFileError) as info:
        read_c3d(tmp_path / "absent.c3d")
    assert info.value.message == "cannot read the file: No such file or directory"

    def refuse(*args, **kwargs):
        raise OSError("the disk went away")

    path = tmp_path / "x.c3d"
    path.write_bytes(header_bytes())
    monkeypatch.setattr(type(path), "open", refuse)
    with pytest.raises(MotionFileError) as info:
        read_c3d(path)
    assert info.value.message == "cannot read the file: the disk went away"


def test_a_signal_numbered_one_and_an_archive_that_asks_for_pickles(tmp_path, monkeypatch):
    path = tmp_path / "x.c3d"
    path.write_bytes(header_bytes())
    monkeypatch.setattr(c3d_module.subprocess, "run", FakeRun(-1))
    with pytest.raises(MotionFileError) as info:
        read_c3d(path)
    assert info.value.message == "ezc3d crashed reading the file (signal 1): the file is corrupt"
    # the child's output is data, never code: an object array (a pickle) is refused
    buffer = io.BytesIO()
    np.savez(buffer, points=np.array([object()], dtype=object), meta=np.array("{}"))
    monkeypatch.setattr(c3d_module.subprocess, "run", FakeRun(stdout=buffer.getvalue()))
    with pytest.raises(ValueError, match="allow_pickle"):
        read_c3d(path)


def test_ezc3ds_first_sentence_is_quoted():
    text = c3d_module.rejection("MIPS processor type not supported yet. Please open a GitHub issue, thanks")
    assert text.startswith("this kind of C3D cannot be read here (ezc3d: MIPS processor type not supported yet);")


@pytest.mark.parametrize("rate", [0.5, 1.0])
def test_rates_of_a_hertz_or_less(rate):
    assert marker_set(np.ones((1, 2, 3)), np.ones((1, 2)), rate=rate).rate == rate


def test_options_are_keywords_only(tmp_path):
    with pytest.raises(TypeError):
        read_c3d(tmp_path / "x.c3d", "gap")


def test_a_header_announcing_one_frame():
    one = _marker_set(decoded(np.ones((3, 2, 3)), np.ones((3, 2))) | {"meta": base_meta(announced_frames=1)}, "f")
    assert one.notes == ("the header announces 1 frames, the file holds 3: it may be truncated",)
