"""C3D through ezc3d: the real files, files written here by ezc3d, and broken files."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.markers import c3d as c3d_module
from gmr_studio.core.markers import read_markers
from gmr_studio.core.markers.c3d import read_c3d
from tests.conftest import shared_files, shared_path

EB015 = "c3d/c3dorg_s01_Eb015pi_intel_int.c3d"


def write_c3d(path, labels, points, residuals, rate=100.0, units="mm", first_frame=0):
    """A float C3D written by ezc3d: points (F, M, 3), residuals (F, M)."""
    ezc3d = pytest.importorskip("ezc3d")
    c3d = ezc3d.c3d()
    c3d["parameters"]["POINT"]["RATE"]["value"] = [rate]
    c3d["parameters"]["POINT"]["LABELS"]["value"] = list(labels)
    c3d["parameters"]["POINT"]["UNITS"]["value"] = [units]
    data = np.ones((4, len(labels), len(points)))
    data[:3] = np.asarray(points, dtype=float).transpose(2, 1, 0)
    c3d["data"]["points"] = data
    c3d["data"]["meta_points"]["residuals"] = np.asarray(residuals, dtype=float).T[None]
    c3d["header"]["points"]["first_frame"] = first_frame
    c3d.write(str(path))
    return path


@pytest.mark.parametrize(
    ("relative", "n_frames", "n_markers", "rate", "units"),
    [
        ("cmu/subject01/01_01.c3d", 2751, 42, 120.0, "mm"),
        ("c3d/ezc3d_Vicon.c3d", 580, 51, 100.0, "mm"),
        ("c3d/ezc3d_Qualisys.c3d", 340, 55, 200.0, "mm"),
        ("c3d/c3dorg_s00_NexGen_test1_PiG_fullbody.c3d", 721, 40, 128.0, "m"),
        (EB015, 450, 26, 50.0, "mm"),
    ],
)
def test_real_files(relative, n_frames, n_markers, rate, units):
    markers = read_markers(shared_path(relative))
    assert markers.positions.shape == (n_frames, n_markers, 3)
    assert markers.rate == rate and markers.units == units
    assert len(set(zip(markers.subjects, markers.labels))) == n_markers
    # a gap is missing as a whole, every present sample is finite
    assert np.isfinite(markers.positions[markers.present]).all()
    assert np.isnan(markers.positions[~markers.present]).all()


def test_cmu_labels_gaps_and_the_computed_samples():
    """CMU 01_01: negative residuals are the 2.4% of gaps PROVENANCE quotes; the 859 samples
    of residual 0 (0.74%, the lab's gap filling) are kept and marked computed, and
    ``computed="drop"`` makes them gaps and changes nothing else."""
    path = shared_path("cmu/subject01/01_01.c3d")
    markers = read_c3d(path)
    assert {"LFHD", "RFHD", "C7", "T10", "LANK", "RTOE", "LFWT", "RBWT"} <= set(markers.labels)
    assert "RBAC-1" in markers.labels and markers.first_frame == 39
    assert abs((~markers.present).mean() - 0.024) < 0.001
    assert markers.computed.shape == (2751, 42) and markers.computed.sum() == 859
    assert not (markers.computed & ~markers.present).any()
    assert "859 samples with residual 0" in markers.notes[0] and "kept and marked computed" in markers.notes[0]
    dropped = read_c3d(path, computed="drop")
    np.testing.assert_array_equal(~dropped.present, ~markers.present | markers.computed)
    assert not dropped.computed.any() and "859 samples with residual 0" in dropped.notes[0]
    np.testing.assert_array_equal(dropped.positions[dropped.present], markers.positions[dropped.present])


def test_cmus_computed_samples_are_continuous_with_their_neighbours():
    """The computed samples of CMU 01_01 are where the marker is: stepping into one from a
    present neighbour is no longer than stepping between measured samples (medians 2.6 and
    4.5 mm), and none is farther from the measured samples around it than a marker moving
    at 5 m/s could go."""
    markers = read_c3d(shared_path("cmu/subject01/01_01.c3d"))
    steps = np.linalg.norm(np.diff(markers.positions, axis=0), axis=2)  # (F-1, M), NaN at gaps
    into = steps[markers.computed[1:] & markers.present[:-1]]
    between = steps[markers.measured[1:] & markers.measured[:-1]]
    assert into.size > 400 and np.median(into) <= np.median(between)
    frames, columns = np.nonzero(markers.computed)
    for f, m in zip(frames, columns):
        seen = np.flatnonzero(markers.measured[:, m])
        for g in (seen[seen < f][-1:], seen[seen > f][:1]):
            if g.size:
                speed = np.linalg.norm(markers.positions[f, m] - markers.positions[g[0], m]) / abs(f - g[0])
                assert speed * markers.rate < 5000.0  # mm/s


@pytest.mark.parametrize(
    ("relative", "gaps"),
    [("c3d/opensim-core_walking5.c3d", 0.455), ("c3d/ezc3d_Vicon.c3d", 0.010), ("c3d/c3dorg_s03_gait-pig.c3d", 0.159)],
)
def test_vicon_files_without_residuals_keep_every_valid_sample(relative, gaps):
    """Vicon Nexus writes residual 0 on every valid sample (no residual recorded): none is
    computed, nothing is dropped, and the gaps are the invalid samples alone."""
    path = shared_path(relative)
    markers = read_c3d(path)
    assert not markers.computed.any()
    assert (~markers.present).mean() == pytest.approx(gaps, abs=0.001)
    np.testing.assert_array_equal(read_c3d(path, computed="drop").present, markers.present)


def test_files_without_residuals_keep_every_sample():
    # Qualisys and the Plug-in Gait sample write residual 0 everywhere: no residual recorded
    for relative in ("c3d/ezc3d_Qualisys.c3d", "c3d/c3dorg_s00_NexGen_test1_PiG_fullbody.c3d"):
        markers = read_c3d(shared_path(relative))
        assert markers.present.all() and markers.notes == () and not markers.computed.any()


def test_subject_prefix_is_split():
    markers = read_c3d(shared_path("c3d/ezc3d_Vicon.c3d"))
    assert "Daphnee" in markers.subjects and "ASISr" in markers.labels
    m = markers.index("Daphnee:ASISr")
    assert markers.subjects[m] == "Daphnee" and markers.labels[m] == "ASISr"


@pytest.mark.parametrize("path", shared_files("c3d/*.c3d"))
def test_isolated_and_in_process_reads_agree(path):
    a, b = read_c3d(path), read_c3d(path, isolate=False)
    np.testing.assert_array_equal(a.positions, b.positions)
    assert (a.labels, a.subjects, a.rate, a.units, a.first_frame, a.notes) == (
        b.labels,
        b.subjects,
        b.rate,
        b.units,
        b.first_frame,
        b.notes,
    )


def test_written_file_with_residual_codes(tmp_path):
    rng = np.random.default_rng(4)
    points = rng.normal(size=(5, 3, 3)) * 100
    residuals = np.ones((5, 3))
    residuals[1, 0] = -1  # invalid: a gap
    residuals[2, 1] = 0  # computed by the capture software: kept, marked
    path = write_c3d(tmp_path / "w.c3d", ["Sam:LASI", "RASI", "RASI"], points, residuals, rate=250, first_frame=7)
    markers = read_c3d(path)
    assert markers.labels == ("LASI", "RASI", "RASI~2") and markers.subjects == ("Sam", "", "")
    assert markers.rate == 250 and markers.first_frame == 7 and markers.units == "mm"
    expected = points.copy()
    expected[1, 0] = np.nan
    np.testing.assert_allclose(markers.positions, expected, rtol=1e-6, atol=1e-4)  # stored as float32
    assert np.argwhere(markers.computed).tolist() == [[2, 1]]
    assert any("repeats the label" in note for note in markers.notes)
    expected[2, 1] = np.nan
    np.testing.assert_allclose(read_c3d(path, computed="drop").positions, expected, rtol=1e-6, atol=1e-4)


def test_only_computed_samples_no_marker_could_reach_are_gaps(tmp_path):
    """A marker walking at 1 m/s (10 mm a frame at 100 Hz), measured but at frames 3-5,
    whose residual is 0 (computed): frames 3 and 4 lie on its path (kept, computed), frame 5
    is 2 m off it (no marker gets there in 10 ms: a gap), and frame 7, at exactly
    (0, 0, 0) with residual 0, is a gap too (older writers' missing marker)."""
    frames = np.arange(10.0)
    path = np.column_stack([500.0 + 10.0 * frames, np.full(10, 200.0), np.full(10, 900.0)])
    path[5] += [0.0, 2000.0, 0.0]
    path[7] = 0.0
    residuals = np.ones(10)
    residuals[[3, 4, 5, 7]] = 0.0
    markers = read_c3d(write_c3d(tmp_path / "j.c3d", ["LASI"], path[:, None], residuals[:, None]))
    assert np.flatnonzero(~markers.present[:, 0]).tolist() == [5, 7]
    assert np.flatnonzero(markers.computed[:, 0]).tolist() == [3, 4]
    assert any("farther from the measured ones" in note for note in markers.notes)
    assert any("(0, 0, 0)" in note for note in markers.notes)


def test_one_frame_file_and_metres(tmp_path):
    path = write_c3d(tmp_path / "one.c3d", ["A", "B"], [[[1, 2, 3], [4, 5, 6]]], [[0, 0]], units="m")
    markers = read_c3d(path)
    assert markers.positions.shape == (1, 2, 3) and markers.units == "m" and markers.present.all()
    np.testing.assert_allclose(markers.in_units("mm").positions[0, 1], [4000, 5000, 6000], rtol=1e-6)


def mutated(tmp_path, name, changes: dict[int, int], length: int | None = None):
    data = bytearray(shared_path(EB015).read_bytes())
    for index, value in changes.items():
        data[index] = value
    path = tmp_path / name
    path.write_bytes(bytes(data[:length]))
    return path


@pytest.mark.parametrize(
    ("name", "changes", "length", "message"),
    [
        ("empty.c3d", {}, 0, "the file is empty"),
        ("short.c3d", {}, 100, "the file has 100 bytes"),
        ("key.c3d", {1: 0x99}, None, "this is not a C3D file"),
        ("proc.c3d", {512 + 3: 200}, None, "unknown processor type 200"),
        ("block.c3d", {0: 0}, None, "the parameter section (block 0) lies outside the file"),
        ("params.c3d", {}, 700, "ezc3d rejects the file"),
    ],
)
def test_broken_files_are_errors_not_crashes(tmp_path, name, changes, length, message):
    path = mutated(tmp_path, name, changes, length)
    with pytest.raises(MotionFileError) as error:
        read_markers(path)
    assert message in str(error.value) and str(error.value).startswith(str(path))


@pytest.mark.parametrize(
    ("name", "changes"),
    [
        ("segv.c3d", {2926: 174}),  # found by fuzzing: this byte makes ezc3d 1.7.2 segfault
        ("hang.c3d", {3152: 14}),  # and this one makes it loop
    ],
)
def test_files_that_crash_or_hang_ezc3d_are_errors(tmp_path, name, changes):
    path = mutated(tmp_path, name, changes)
    with pytest.raises(MotionFileError) as error:
        read_c3d(path, timeout=3)
    assert str(error.value).startswith(str(path))
    assert any(text in str(error.value) for text in ("crashed reading", "did not finish", "rejects the file"))


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("segv.c3d", "ezc3d crashed reading the file (signal 11): the file is corrupt"),
        ("hang.c3d", "ezc3d did not finish reading the file in 6 s: the file is probably corrupt"),
        ("odd.c3d", "ezc3d crashed reading the file (exit status 7) (something odd happened): the file is corrupt"),
    ],
)
def test_the_child_process_contract(tmp_path, monkeypatch, name, message):
    """Whatever the child does (a signal, a hang, an odd exit), the caller gets one error."""
    monkeypatch.setattr(c3d_module, "WORKER_MODULE", "tests.fake_c3d_worker")
    monkeypatch.setenv("PYTHONPATH", str(Path(__file__).resolve().parent.parent))
    path = tmp_path / name
    path.write_bytes(shared_path(EB015).read_bytes())
    with pytest.raises(MotionFileError) as error:
        read_c3d(path, timeout=1)
    assert str(error.value) == f"{path}: {message}"


def test_missing_file_and_truncated_data(tmp_path):
    with pytest.raises(MotionFileError, match="cannot read the file"):
        read_c3d(tmp_path / "absent.c3d")
    whole = shared_path(EB015).read_bytes()
    path = tmp_path / "cut.c3d"
    path.write_bytes(whole[: len(whole) - 40_000])
    markers = read_c3d(path)
    assert 0 < markers.n_frames < 450
    assert any("the header announces 450 frames" in note for note in markers.notes)


def _processes_reading(path) -> list[int]:
    """PIDs whose command line names ``path``."""
    import os

    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                cmdline = (entry / "cmdline").read_bytes()
            except OSError:
                continue
            if str(path).encode() in cmdline and int(entry.name) != os.getpid():
                found.append(int(entry.name))
    return found


def test_a_reader_killed_mid_read_leaves_no_ezc3d_child_behind(tmp_path):
    """Regression (fuzz run, seed 0, case c3d:713): a cut-short Plug-in Gait file makes ezc3d
    spin forever; when the reading process was killed, its child kept spinning."""
    import subprocess
    import sys
    import time

    # the case was the Plug-in Gait file cut after 1,031 bytes (written out here, so that new
    # files in the shared folder, which renumber the fuzz cases, leave the test's file as it was)
    source = shared_path("c3d/c3dorg_s00_NexGen_test1_PiG_fullbody.c3d")
    path = tmp_path / "spinning.c3d"
    path.write_bytes(source.read_bytes()[:1031])
    with pytest.raises(MotionFileError, match="did not finish reading the file in"):
        read_c3d(path, timeout=2)
    reader = subprocess.Popen(
        [sys.executable, "-c", f"from gmr_studio.core.markers.c3d import read_c3d; read_c3d({str(path)!r})"],
    )
    deadline = time.monotonic() + 20
    while not any(pid != reader.pid for pid in _processes_reading(path)) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert any(pid != reader.pid for pid in _processes_reading(path)), "the child never started"
    reader.kill()
    reader.wait()
    deadline = time.monotonic() + 30  # the kernel's SIGKILL of the orphan can lag on a loaded machine
    while _processes_reading(path) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert _processes_reading(path) == []


def write_long_c3d(path, n_frames: int, count_in: str, announced: int | None = None):
    """A C3D of ``n_frames`` frames written by ezc3d, whose 16-bit header and POINT:FRAMES
    saturate at 65535; the real count (``announced``, default ``n_frames``) goes where
    ``count_in`` says: POINT:LONG_FRAMES (float) or TRIAL:ACTUAL_START_FIELD/END_FIELD.
    Marker A is at (f, 2f, 3f) in frame f; B at f + 0.5 with gaps and zero residuals."""
    ezc3d = pytest.importorskip("ezc3d")
    announced = announced or n_frames
    c3d = ezc3d.c3d()
    c3d["parameters"]["POINT"]["RATE"]["value"] = [100.0]
    c3d["parameters"]["POINT"]["LABELS"]["value"] = ["A", "B"]
    c3d["parameters"]["POINT"]["UNITS"]["value"] = ["mm"]
    frame = np.arange(n_frames, dtype=float)
    points = np.stack([np.stack([frame, 2 * frame, 3 * frame], -1), np.stack([frame + 0.5] * 3, -1)], axis=1)
    residuals = np.ones((n_frames, 2))
    residuals[65_600::1000, 1] = -1  # invalid, all past 65,535
    residuals[66_001, 1] = 0  # computed: kept and marked, since the file records residuals
    data = np.ones((4, 2, n_frames))
    data[:3] = points.transpose(2, 1, 0)
    c3d["data"]["points"] = data
    c3d["data"]["meta_points"]["residuals"] = residuals.T[None]
    if count_in == "LONG_FRAMES":
        c3d.add_parameter("POINT", "LONG_FRAMES", float(announced))
    else:
        words = {"type": ezc3d.ezc3d.INT, "description": "", "is_locked": False}
        c3d["parameters"]["TRIAL"] = {
            "__METADATA__": {"DESCRIPTION": "", "IS_LOCKED": False},
            "ACTUAL_START_FIELD": {**words, "value": np.array([1, 0])},
            "ACTUAL_END_FIELD": {**words, "value": np.array([announced & 0xFFFF, announced >> 16])},
        }
    c3d.write(str(path))
    expected = points.copy()
    expected[residuals[:, :, None].repeat(3, 2) < 0] = np.nan
    return path, expected


@pytest.mark.parametrize(("count_in", "announced"), [("LONG_FRAMES", None), ("TRIAL", None), ("TRIAL", 80_000)])
def test_captures_longer_than_65535_frames_read_completely(tmp_path, count_in, announced):
    path, expected = write_long_c3d(tmp_path / "long.c3d", 70_000, count_in, announced)
    ezc3d = pytest.importorskip("ezc3d")
    assert ezc3d.c3d(str(path))["data"]["points"].shape[2] == 65_535  # what ezc3d alone reads
    markers = read_c3d(path)
    # a file shorter than announced: the whole frames it holds (ezc3d ends the data with zeros
    # to a 512-byte block boundary and one more block: read as gaps), and a note
    n_read = markers.n_frames
    assert n_read == 70_000 if announced is None else 70_000 <= n_read <= 70_000 + 512 // 32
    np.testing.assert_array_equal(markers.positions[:70_000], expected)  # integers, halves: exact in float32
    assert np.isnan(markers.positions[70_000:]).all()
    assert int((~markers.present[:70_000]).sum()) == 5
    assert np.argwhere(markers.computed).tolist() == [[66_001, 1]]
    note = next(n for n in markers.notes if "more than the header's 16-bit" in n)
    assert f"gives {announced or 70_000} frames" in note and f"{n_read} frames read" in note
    assert ("truncated" in note) == (announced is not None)
    in_process = read_c3d(path, isolate=False)
    np.testing.assert_array_equal(in_process.positions, markers.positions)


#: shared files whose frame layout ezc3d misreads (see test_evart_points_follow_the_headers_layout)
EZC3D_MISREADS = {"c3dio_c3dorg-sample11_evart.c3d"}


@pytest.mark.parametrize("path", shared_files("**/*.c3d"))
def test_numpy_point_decoder_agrees_with_ezc3d(path, tmp_path):
    """The decoder used past 65,535 frames gives ezc3d's numbers on every shared file (Intel
    float and integer, DEC, SGI through its Intel copy, analog channels interleaved), gaps
    and residuals included; where ezc3d misreads the layout, the next test decides."""
    ezc3d = pytest.importorskip("ezc3d")
    from gmr_studio.core.markers.c3d_byteorder import SGI, intel_from_sgi, processor_of
    from gmr_studio.core.markers.c3d_frames import parameter_frame_count, read_points

    readable = path
    if processor_of(path.read_bytes()) == SGI:  # ezc3d refuses SGI: it reads our Intel copy
        readable = tmp_path / "intel.c3d"
        readable.write_bytes(intel_from_sgi(path.read_bytes()))
    c3d = ezc3d.c3d(str(readable))
    xyz = np.asarray(c3d["data"]["points"], dtype=float)[:3].transpose(2, 1, 0)
    residuals = np.asarray(c3d["data"]["meta_points"]["residuals"], dtype=float)[0].T
    points, decoded_residuals, count = read_points(Path(path), c3d["parameters"], xyz.shape[0])
    assert count == xyz.shape[0] == parameter_frame_count(c3d["parameters"])[0]
    if path.name in EZC3D_MISREADS:
        np.testing.assert_array_equal(points[0], xyz[0])  # the first frame is where both start
        assert np.isnan(points).any(axis=2).sum() != np.isnan(xyz).any(axis=2).sum()
        return
    np.testing.assert_array_equal(points, xyz)
    np.testing.assert_array_equal(decoded_residuals, residuals)


def test_evart_points_follow_the_headers_layout():
    """EVaRT's sample 11 says ANALOG:RATE 1000 at 60 Hz; its header stores 476 analog values
    per frame (28 channels x 17). ezc3d sizes frames with 16 samples (1000 / 60 rounded down)
    and reads every frame after the first from the wrong place: markers jump up to 2.5 m
    between frames and the gaps land on the wrong samples. Which layout is right: (1) the
    file's size, data block 10 plus 243 frames of (4 x 22 + 476) int16 values, fills the
    file to its last block, where 16 samples would leave 14 kB unread; (2) with the header's
    layout no marker moves more than 62 mm between frames (3.7 m/s), and every gap is a
    sample the writer flagged (negative fourth word) and zeroed. The reader follows the
    header and says so."""
    path = shared_path("c3d/c3dio_c3dorg-sample11_evart.c3d")
    size = path.stat().st_size
    frame_bytes = 2 * (4 * 22 + 476)
    assert (10 - 1) * 512 + 243 * frame_bytes <= size < (10 - 1) * 512 + 243 * frame_bytes + 512
    markers = read_c3d(path)
    assert markers.n_frames == 243 and markers.n_markers == 22
    assert any("476 analog values per frame" in note for note in markers.notes)
    steps = np.linalg.norm(np.diff(markers.positions, axis=0), axis=2)
    assert np.nanmax(steps) < 65.0
    raw = np.fromfile(path, dtype="<i2", offset=9 * 512, count=243 * (88 + 476)).reshape(243, -1)[:, :88]
    flagged = raw.reshape(243, 22, 4)[..., 3] < 0
    np.testing.assert_array_equal(~markers.present, flagged)
    assert int(flagged.sum()) == 677


def test_an_sgi_file_reads_as_the_same_trial_written_by_a_dec_machine():
    """c3d.org's sample 02 exists as DEC floats and as SGI/MIPS big-endian integers (which
    ezc3d refuses). Read through its Intel copy, the SGI file has the DEC file's labels,
    rate and gaps, and its points within one integer step (POINT:SCALE, 0.281 mm)."""
    sgi = read_c3d(shared_path("c3d/c3dio_c3dorg-sample02_sgi_int.c3d"))
    dec = read_c3d(shared_path("c3d/c3dio_c3dorg-sample02_dec_real.c3d"))
    assert (sgi.labels, sgi.rate, sgi.units, sgi.n_frames) == (dec.labels, dec.rate, dec.units, dec.n_frames)
    np.testing.assert_array_equal(sgi.present, dec.present)
    both = sgi.present & dec.present
    assert np.abs(sgi.positions[both] - dec.positions[both]).max() <= 0.2812
    assert "written on an SGI/MIPS machine" in sgi.notes[0]


def test_the_intel_copy_of_an_sgi_file_swaps_numbers_never_text(tmp_path):
    """Byte-level check of the rewrite: the copy has processor 84, every parameter ezc3d reads
    from it equals what an independent big-endian parse of the SGI file gives (labels text
    unchanged, POINT:SCALE, RATE, USED), and the analog channels equal the DEC file's."""
    ezc3d = pytest.importorskip("ezc3d")
    from gmr_studio.core.markers.c3d_byteorder import INTEL, intel_from_sgi, processor_of

    data = shared_path("c3d/c3dio_c3dorg-sample02_sgi_int.c3d").read_bytes()
    intel = intel_from_sgi(data)
    assert len(intel) == len(data) and processor_of(intel) == INTEL
    assert intel[512 + 4 : 512 + 200].count(b"POINT") == data[512 + 4 : 512 + 200].count(b"POINT")
    copy = tmp_path / "intel.c3d"
    copy.write_bytes(intel)
    c3d = ezc3d.c3d(str(copy))
    point = c3d["parameters"]["POINT"]
    # the header's own big-endian words, read independently: points, analog values per frame,
    # first and last frame; and its big-endian float frame rate
    words = struct.unpack(">5H", data[2:12])
    assert (int(point["USED"]["value"][0]), words[1]) == (36, 356 // 89 * 16)
    assert words[2:4] == (1, 89) and struct.unpack(">f", data[20:24])[0] == 50.0
    assert float(point["RATE"]["value"][0]) == 50.0
    assert float(point["SCALE"]["value"][0]) == pytest.approx(0.28118187)
    dec = ezc3d.c3d(str(shared_path("c3d/c3dio_c3dorg-sample02_dec_real.c3d")))
    assert list(point["LABELS"]["value"]) == list(dec["parameters"]["POINT"]["LABELS"]["value"])
    np.testing.assert_array_equal(np.asarray(c3d["data"]["analogs"]), np.asarray(dec["data"]["analogs"]))


@pytest.mark.parametrize(
    ("cut", "message"),
    [(600, "this SGI/MIPS (big-endian) C3D is damaged: parameter DESCRIPTIONS"), (100, "")],
)
def test_a_damaged_sgi_file_gives_our_message(tmp_path, cut, message):
    data = bytearray(shared_path("c3d/c3dio_c3dorg-sample02_sgi_int.c3d").read_bytes())
    if cut == 600:
        data[512 + 2] = 1  # the parameter section said to be one block long: records run past it
    else:
        data = data[:cut]
    path = tmp_path / "bad.c3d"
    path.write_bytes(bytes(data))
    with pytest.raises(MotionFileError) as info:
        read_c3d(path)
    text = str(info.value)
    assert text.startswith(f"{path}: ") and "GitHub issue" not in text and message in text
    assert "ezc3d" not in text or cut == 100


def test_ezc3ds_requests_to_report_a_missing_feature_become_advice():
    from gmr_studio.core.markers.c3d import rejection

    text = rejection("MIPS processor type not supported yet, please open a GitHub issue to report that you want this")
    assert text == (
        "this kind of C3D cannot be read here (ezc3d: MIPS processor type not supported yet); export the trial "
        "again from the capture software as a PC (Intel) C3D, or convert it with a C3D editor such as Mokka"
    )
    assert rejection("gmr: ours") == "ours"
    assert rejection("bad header") == "ezc3d rejects the file: bad header"
