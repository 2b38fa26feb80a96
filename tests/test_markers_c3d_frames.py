"""The long-capture reader (core.markers.c3d_frames) on data sections written here sample by
sample: the frame count from each place the standard keeps it, and the 3D points and
residuals of Intel, DEC and SGI files, float and integer, with analog values between the
frames, against the numbers written."""

from __future__ import annotations

import struct

import numpy as np
import pytest

from gmr_studio.core.markers.c3d_frames import analog_values_per_frame, parameter_frame_count, read_points

INTEL, DEC, SGI = 84, 85, 86


def entry(values, kind: int = 2) -> dict:
    """One parameter as ezc3d maps it (type 2 int16, 4 float, -1 text)."""
    return {"value": np.asarray(values), "type": kind}


@pytest.mark.parametrize(
    ("parameters", "expected"),
    [
        ({}, None),
        ({"POINT": {}}, None),
        ({"POINT": {"FRAMES": entry([], 4)}}, None),
        ({"POINT": {"FRAMES": entry([70000.0], 4)}}, (70000, "POINT:FRAMES (floating point)")),
        ({"POINT": {"FRAMES": entry([-25536])}}, (40000, "POINT:FRAMES")),
        ({"POINT": {"FRAMES": entry([-1]), "LONG_FRAMES": entry([90000.0], 4)}}, (90000, "POINT:LONG_FRAMES")),
        ({"POINT": {"LONG_FRAMES": entry([12])}}, (12, "POINT:LONG_FRAMES")),
        (
            {"POINT": {"FRAMES": entry([5000.0], 4), "LONG_FRAMES": entry([9.0], 4)}},
            (5000, "POINT:FRAMES (floating point)"),
        ),
    ],
)
def test_the_frame_count_of_the_point_group(parameters, expected):
    assert parameter_frame_count(parameters) == expected


TRIAL = "TRIAL:ACTUAL_START_FIELD/ACTUAL_END_FIELD"


def trial(start, end, frames=None) -> dict:
    out = {"TRIAL": {"ACTUAL_START_FIELD": entry(start), "ACTUAL_END_FIELD": entry(end)}}
    if frames is not None:
        out["POINT"] = {"FRAMES": entry([frames])}
    return out


def test_the_frame_count_of_the_trial_group():
    # words low then high, each read unsigned: (2 + 1 * 65536) to (65535 + 1 * 65536)
    assert parameter_frame_count(trial([2, 1], [-1, 1], frames=-1)) == (65534, TRIAL)
    assert parameter_frame_count(trial([1, 0], [4464, 1])) == (70000, TRIAL)
    assert parameter_frame_count(trial([7, 0], [7, 0])) == (1, TRIAL)
    # ending before it starts, or a word missing: the point group's count, if any
    assert parameter_frame_count(trial([8, 0], [7, 0], frames=300)) == (300, "POINT:FRAMES")
    assert parameter_frame_count(trial([1], [7, 0], frames=300)) == (300, "POINT:FRAMES")
    assert parameter_frame_count(trial([1, 0], [7], frames=300)) == (300, "POINT:FRAMES")
    assert parameter_frame_count(trial([1, 0], [7, 0, 9])) == (7, TRIAL)
    only_start = {"TRIAL": {"ACTUAL_START_FIELD": entry([1, 0])}}
    assert parameter_frame_count(only_start) is None


def c3d_file(path, processor: int, samples: np.ndarray, *, scale: float, analog: int, data_start: int = 3, tail=b""):
    """A C3D's header, a parameter block that holds only its processor byte, and ``samples``
    (F, 4 M + analog) from block ``data_start`` on, as float32 (scale < 0) or int16 in the
    processor's format."""
    order = ">" if processor == SGI else "<"
    header = bytearray(512)
    header[0], header[1] = 2, 0x50
    header[4:6] = struct.pack(f"{order}H", analog)
    parameters = bytearray(512 * (data_start - 2))
    parameters[3] = processor
    if scale > 0:
        data = samples.astype(f"{order}i2").tobytes()
    elif processor == DEC:  # VAX F: 4 times the IEEE value, its 16-bit halves swapped
        data = (4 * samples).astype("<f4").view(np.uint8).reshape(-1, 4)[:, [2, 3, 0, 1]].tobytes()
    else:
        data = samples.astype(f"{order}f4").tobytes()
    path.write_bytes(bytes(header) + bytes(parameters) + data + tail)
    return path


def layout(n_points: int, scale: float, data_start: int = 3) -> dict:
    return {
        "POINT": {
            "USED": entry([n_points]),
            "SCALE": entry([scale], 4),
            "DATA_START": entry([data_start]),
        }
    }


#: the fourth word of each sample, and what it means: (word, residual byte or -1 for invalid)
WORDS = [(0x0203, 2), (-1, -1), (0, 0), (0x7F00, 127), (0x7FFF, 127), (-0x100, -1)]


def samples(n_frames: int, n_points: int, analog: int, fourth: list[int]) -> np.ndarray:
    """Whole numbers (exact as int16 and float32): x y z of point m in frame f, then its word,
    then the analog values (large, so that a frame read from the wrong place shows)."""
    out = np.zeros((n_frames, 4 * n_points + analog))
    for f in range(n_frames):
        for m in range(n_points):
            out[f, 4 * m : 4 * m + 3] = [100 * f + 10 * m + 1, -(100 * f + 10 * m + 2), 100 * f + 10 * m + 3]
            out[f, 4 * m + 3] = fourth[(f * n_points + m) % len(fourth)]
        out[f, 4 * n_points :] = 20000 + np.arange(analog)
    return out


@pytest.mark.parametrize("processor", [INTEL, DEC, SGI])
@pytest.mark.parametrize(("scale", "analog"), [(-1.0, 0), (-1.0, 3), (0.5, 0), (0.25, 5)])
def test_points_and_residuals_in_every_byte_order(tmp_path, processor, scale, analog):
    fourth = [word for word, _ in WORDS]
    written = samples(4, 3, analog, fourth)
    path = c3d_file(tmp_path / "p.c3d", processor, written, scale=scale, analog=analog)
    assert analog_values_per_frame(path) == analog
    points, residuals, count = read_points(path, layout(3, scale), 4)
    assert count == 4 and points.shape == (4, 3, 3) and residuals.shape == (4, 3)
    meaning = np.array([WORDS[i % len(WORDS)][1] for i in range(12)], dtype=float).reshape(4, 3)
    invalid = meaning < 0
    expected = written[:, : 4 * 3].reshape(4, 3, 4)[..., :3] * (1.0 if scale < 0 else scale)
    expected[invalid] = np.nan
    np.testing.assert_array_equal(points, expected)
    np.testing.assert_array_equal(residuals, np.where(invalid, -1.0, meaning * abs(scale)))


def test_a_float_word_of_32768_or_more_is_a_negative_16_bit_number(tmp_path):
    """Float files store the fourth word as a float: 40000 and 32768 are the 16-bit words
    -25536 and -32768 (invalid); 32767.4 rounds to 32767 (residual byte 127)."""
    written = samples(1, 4, 0, [40000.0, 32768.0, 32767.4, 512.6])
    path = c3d_file(tmp_path / "f.c3d", INTEL, written, scale=-2.0, analog=0)
    points, residuals, _ = read_points(path, layout(4, -2.0), 1)
    np.testing.assert_array_equal(residuals, [[-1.0, -1.0, 254.0, 4.0]])
    np.testing.assert_array_equal(np.isnan(points).all(axis=2), [[True, True, False, False]])


def test_a_file_that_ends_before_the_frames_asked(tmp_path):
    written = samples(3, 2, 1, [0x0100])
    path = c3d_file(tmp_path / "s.c3d", INTEL, written, scale=-1.0, analog=1, tail=b"\x01" * 35)
    points, residuals, count = read_points(path, layout(2, -1.0), 10)
    assert count == 3 and points.shape == (3, 2, 3)  # 35 bytes are not a frame of 36
    np.testing.assert_array_equal(points[2, 1], [211, -212, 213])
    np.testing.assert_array_equal(residuals, np.ones((3, 2)))
    points, _, count = read_points(path, layout(2, -1.0), 2)
    assert count == 2 and points.shape == (2, 2, 3)
    whole = c3d_file(tmp_path / "w.c3d", INTEL, written, scale=-1.0, analog=1, tail=b"\x01" * 36)
    assert read_points(whole, layout(2, -1.0), 10)[2] == 4


def test_a_data_section_later_in_the_file(tmp_path):
    written = samples(2, 1, 0, [0x0300])
    path = c3d_file(tmp_path / "l.c3d", SGI, written, scale=0.5, analog=0, data_start=5)
    points, residuals, count = read_points(path, layout(1, 0.5, data_start=5), 2)
    assert count == 2
    np.testing.assert_array_equal(points[:, 0], [[0.5, -1, 1.5], [50.5, -51, 51.5]])
    np.testing.assert_array_equal(residuals, [[1.5], [1.5]])
    # a data section said to start past the end holds no frame
    none = read_points(path, layout(1, 0.5, data_start=9), 2)
    assert none[2] == 0 and none[0].shape == (0, 1, 3)


def test_a_scale_of_zero_means_integer_samples(tmp_path):
    written = samples(3, 2, 0, [0x0100])
    path = c3d_file(tmp_path / "z.c3d", INTEL, written, scale=1.0, analog=0)  # 3 frames of 16 bytes
    points, residuals, count = read_points(path, layout(2, 0.0), 10)
    assert count == 3 and (points == 0).all() and (residuals == 0).all()


def test_the_first_value_of_each_parameter_is_read(tmp_path):
    written = samples(2, 1, 0, [0x0100])
    path = c3d_file(tmp_path / "v.c3d", INTEL, written, scale=-1.0, analog=0)
    parameters = {"POINT": {"USED": entry([1, 5]), "SCALE": entry([-1.0, 2.0], 4), "DATA_START": entry([3, 9])}}
    points, _, count = read_points(path, parameters, 2)
    assert count == 2
    np.testing.assert_array_equal(points[:, 0], written[:, :3])


def test_the_first_value_of_a_frame_count():
    assert parameter_frame_count({"POINT": {"FRAMES": entry([70000.0, 5.0], 4)}})[0] == 70000
    assert parameter_frame_count({"POINT": {"LONG_FRAMES": entry([90000.0, 5.0], 4)}})[0] == 90000
    assert parameter_frame_count({"POINT": {"FRAMES": entry([-25536, 5])}})[0] == 40000
