"""The C3D worker (core.markers.c3d_worker): the output groups and PROCESSING numbers of
parameter mappings written here, what ``decode_c3d`` takes from an ezc3d reading stood in
for (labels over several parameters, defaults, long captures, the analog layout's note), and
the worker process's exits."""

from __future__ import annotations

import io
import json
import os
import signal
import struct
import subprocess
import sys

import numpy as np
import pytest

from gmr_studio.core.markers import c3d_frames
from gmr_studio.core.markers.c3d_worker import REJECTED, decode_c3d, output_groups, processing_parameters


def text(*values) -> dict:
    return {"value": list(values), "type": -1}


def test_output_groups_named_by_the_standard_and_by_type_groups():
    point = {
        "TYPE_GROUPS": text("Angles", "ANGLES", "Cofm", " COFM ", "labels2", "ANGLE_UNITS", "", "UNITS", "Extra"),
        "ANGLES": text("LHipAngles", " ", " RKneeAngles "),
        "ANGLE_UNITS": text(" deg ", "rad"),
        "COFM": text("CentreOfMass"),
        "FORCES": {"value": [1, 2], "type": 2},  # numbers: not a list of points
        "MOMENTS": text(" ", ""),  # no label: no group
        "POWERS": text("LAnklePower"),
        "POWER_UNITS": text(),
        "SCALARS": text("LStep"),
        "LABELS2": text("A"),
        "UNITS": text("mm"),
    }
    groups, units = output_groups(point)
    assert groups == {
        "ANGLES": ["LHipAngles", "RKneeAngles"],
        "POWERS": ["LAnklePower"],
        "SCALARS": ["LStep"],
        "COFM": ["CentreOfMass"],
    }
    assert list(groups) == ["ANGLES", "POWERS", "SCALARS", "COFM"]
    assert units == {"ANGLES": "deg", "POWERS": "", "SCALARS": "", "COFM": ""}
    del point["TYPE_GROUPS"]
    assert list(output_groups(point)[0]) == ["ANGLES", "POWERS", "SCALARS"]
    assert output_groups({"REACTIONS": text("GRF"), "REACTION_UNITS": text("N")}) == (
        {"REACTIONS": ["GRF"]},
        {"REACTIONS": "N"},
    )


def test_the_numbers_of_the_processing_group():
    group = {
        "__METADATA__": "not a parameter",
        "Name": {"value": ["abc"]},  # not a number, before the numbers
        "KneeWidth": {"value": [105.0]},
        "Int": {"value": 3},
        "Legs": {"value": [1.0, 2.0]},
        "Missing": {"value": [float("nan")]},
        "Empty": {"value": []},
        "Nothing": {},
    }
    assert processing_parameters({"PROCESSING": group}) == {"KneeWidth": 105.0, "Int": 3.0}
    assert processing_parameters({"POINT": {}}) == {}


def fake_reading(n_frames=2, labels=("A", "B", "C"), point=None, analogs=None, parameters=None):
    """What ezc3d gives, as far as decode_c3d reads it: points (4, M, F), residuals (1, M, F)."""
    m = len(labels)
    xyz = np.arange(n_frames * m * 3, dtype=float).reshape(n_frames, m, 3)
    data = np.ones((4, m, n_frames))
    data[:3] = xyz.transpose(2, 1, 0)
    residuals = (np.arange(n_frames * m, dtype=float).reshape(n_frames, m) + 1).T[None]
    point = point if point is not None else {"LABELS": text(*labels[:2]), "LABELS2": text(*labels[2:])}
    reading = {
        "parameters": {"POINT": point, **(parameters or {})},
        "data": {"points": data, "meta_points": {"residuals": residuals}},
        "header": {
            "points": {"first_frame": 7, "frame_rate": 50.0},
            "analogs": analogs or {"size": 0, "frame_rate": 0.0},
        },
    }
    return reading, xyz, residuals[0].T


def decode(monkeypatch, tmp_path, reading, header_analog=0):
    """decode_c3d of an Intel file whose 1024 bytes hold a header only, ezc3d's reading of it
    stood in for by ``reading``."""
    ezc3d = pytest.importorskip("ezc3d")
    path = tmp_path / "f.c3d"
    header = bytearray(1024)
    header[0], header[1], header[512 + 3] = 2, 0x50, 84
    header[4:6] = struct.pack("<H", header_analog)
    path.write_bytes(bytes(header))
    monkeypatch.setattr(ezc3d, "c3d", lambda _: reading)
    return decode_c3d(path)


def test_what_decode_c3d_takes_from_ezc3d(monkeypatch, tmp_path):
    reading, xyz, residuals = fake_reading()
    reading["parameters"]["POINT"]["LABELS4"] = text("Z")  # after a missing LABELS3: not read
    reading["parameters"]["POINT"]["UNITS"] = text("m", "mm")
    reading["parameters"]["POINT"]["RATE"] = {"value": [120.0, 30.0], "type": 4}
    reading["parameters"]["PROCESSING"] = {"Mass": {"value": [70.0]}}
    decoded = decode(monkeypatch, tmp_path, reading)
    np.testing.assert_array_equal(decoded["points"], xyz)
    np.testing.assert_array_equal(decoded["residuals"], residuals)
    meta = decoded["meta"]
    assert meta["labels"] == ["A", "B", "C"] and meta["units"] == "m" and meta["rate"] == 120.0
    assert meta["first_frame"] == 7 and meta["parameters"] == {"Mass": 70.0} and meta["notes"] == []
    assert "long_frames" not in meta and meta["output_groups"] == {} and meta["output_units"] == {}
    json.dumps(meta)  # JSON-ready


def test_defaults_without_units_rate_or_residuals(monkeypatch, tmp_path):
    reading, _, _ = fake_reading(point={"LABELS": text("A", "B", "C")})
    reading["data"]["meta_points"]["residuals"] = np.zeros((0,))
    decoded = decode(monkeypatch, tmp_path, reading)
    meta = decoded["meta"]
    assert meta["units"] == "" and meta["rate"] == 50.0 and meta["labels"] == ["A", "B", "C"]
    np.testing.assert_array_equal(decoded["residuals"], np.zeros((2, 3)))
    assert decoded["points"].flags.c_contiguous


def frames_parameter(value: float) -> dict:
    return {"POINT": {"FRAMES": {"value": [value], "type": 4}}}


def test_a_longer_capture_than_ezc3d_read(monkeypatch, tmp_path):
    calls = []
    longer = np.full((5, 3, 3), 9.0), np.full((5, 3), 2.0), 4

    def read_points(path, parameters, n_frames):
        calls.append(n_frames)
        return longer

    monkeypatch.setattr(c3d_frames, "read_points", read_points)
    reading, _, _ = fake_reading()
    reading["parameters"]["POINT"]["FRAMES"] = {"value": [70000.0], "type": 4}
    decoded = decode(monkeypatch, tmp_path, reading)
    assert calls == [70000]
    assert decoded["meta"]["long_frames"] == {"announced": 70000, "where": "POINT:FRAMES (floating point)", "read": 4}
    np.testing.assert_array_equal(decoded["points"], longer[0])
    # as many frames as ezc3d read: nothing more to read
    reading["parameters"]["POINT"]["FRAMES"] = {"value": [2.0], "type": 4}
    assert "long_frames" not in decode(monkeypatch, tmp_path, reading)["meta"] and calls == [70000]


@pytest.mark.parametrize(
    ("analogs", "header_analog", "note"),
    [
        ({"size": 4, "frame_rate": 100.0}, 8, None),  # 4 channels x 2 samples a frame (at 50 Hz)
        (
            {"size": 4, "frame_rate": 100.0},
            10,
            "the header stores 10 analog values per frame, ezc3d expected 8 (from ANALOG:RATE / POINT:RATE): "
            "points decoded by the header's layout",
        ),
        ({"size": 0, "frame_rate": 100.0}, 10, None),  # no analog channel
        ({"size": 3, "frame_rate": 150.0}, 9, None),  # 3 x (150 / 50)
    ],
)
def test_the_analog_layout_note(monkeypatch, tmp_path, analogs, header_analog, note):
    calls = []

    def read_points(path, parameters, n_frames):
        calls.append(n_frames)
        return np.zeros((n_frames, 3, 3)), np.zeros((n_frames, 3)), n_frames

    monkeypatch.setattr(c3d_frames, "read_points", read_points)
    reading, xyz, _ = fake_reading(analogs=analogs)
    decoded = decode(monkeypatch, tmp_path, reading, header_analog=header_analog)
    assert decoded["meta"]["notes"] == ([note] if note else [])
    assert calls == ([2] if note else [])
    if not note:
        np.testing.assert_array_equal(decoded["points"], xyz)


def test_an_analog_note_at_one_frame_a_second(monkeypatch, tmp_path):
    monkeypatch.setattr(
        c3d_frames, "read_points", lambda path, parameters, n: (np.zeros((n, 3, 3)), np.zeros((n, 3)), n)
    )
    reading, _, _ = fake_reading(analogs={"size": 4, "frame_rate": 2.0})
    reading["header"]["points"]["frame_rate"] = 1.0
    notes = decode(monkeypatch, tmp_path, reading, header_analog=10)["meta"]["notes"]
    assert notes and notes[0].startswith("the header stores 10 analog values per frame, ezc3d expected 8")


def test_no_analog_note_without_a_point_rate(monkeypatch, tmp_path):
    reading, _, _ = fake_reading(analogs={"size": 4, "frame_rate": 200.0})
    reading["header"]["points"]["frame_rate"] = 0.0
    reading["parameters"]["POINT"]["RATE"] = {"value": [100.0], "type": 4}
    assert decode(monkeypatch, tmp_path, reading, header_analog=3)["meta"]["notes"] == []


def worker(*arguments) -> subprocess.CompletedProcess:
    command = [sys.executable, "-m", "gmr_studio.core.markers.c3d_worker", *map(str, arguments)]
    return subprocess.run(command, capture_output=True, timeout=60, stdin=subprocess.DEVNULL)


def test_the_worker_process(tmp_path):
    """One written file through the worker: with its memory limit (no parent named),
    with its parent, with another process named as the parent (it leaves at once), with an
    address space too small to load ezc3d (refused), and with no CPU time (killed)."""
    from tests.test_markers_c3d import write_c3d

    points = np.arange(18, dtype=float).reshape(3, 2, 3)
    path = write_c3d(tmp_path / "w.c3d", ["A", "B"], points, np.ones((3, 2)), rate=60.0)
    done = worker(path, 4 << 30, "soon")  # a time limit that is not a number: none set
    assert done.returncode == 0, done.stderr
    with np.load(io.BytesIO(done.stdout)) as archive:
        np.testing.assert_allclose(archive["points"], points, rtol=1e-6)
        meta = json.loads(str(archive["meta"]))
    assert meta["labels"] == ["A", "B"] and meta["rate"] == 60.0
    orphan = worker(path, 4 << 30, 20, os.getppid())
    assert (orphan.returncode, orphan.stdout, orphan.stderr) == (REJECTED, b"", b"")
    small = worker(path, 50_000_000)
    assert small.returncode == REJECTED and small.stdout == b"" and small.stderr.strip()
    # a limit of -2 s is 0 s of CPU time once the backstop's 2 s are added: SIGXCPU at once
    assert worker(path, 4 << 30, -2).returncode == -signal.SIGXCPU


def run_worker_here(*arguments) -> int:
    """``python -m gmr_studio.core.markers.c3d_worker ARGUMENTS`` run in this process (so that
    ezc3d can be stood in for): its exit status."""
    import runpy
    import warnings

    with pytest.MonkeyPatch.context() as patch, warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # runpy: the module is imported already
        patch.setattr(sys, "argv", ["c3d_worker", *map(str, arguments)])
        with pytest.raises(SystemExit) as exit_:
            runpy.run_module("gmr_studio.core.markers.c3d_worker", run_name="__main__")
    return exit_.value.code


def test_the_workers_refusals(tmp_path, capsys, monkeypatch):
    """In this process: ezc3d's own message on a file it refuses, and what the worker says
    of ezc3d running out of memory or failing otherwise."""
    ezc3d = pytest.importorskip("ezc3d")
    bad = tmp_path / "bad.c3d"
    bad.write_bytes(b"\x02\x50" + bytes(600))
    assert run_worker_here(bad) == REJECTED
    out = capsys.readouterr()
    assert out.out == "" and out.err.strip() and not out.err.startswith("gmr: ")
    # too short for a header: not taken for an SGI file, ezc3d says what is wrong
    short = tmp_path / "short.c3d"
    short.write_bytes(b"\x02\x50" + bytes(98))
    with pytest.raises(Exception) as theirs:
        ezc3d.c3d(str(short))
    assert run_worker_here(short) == REJECTED
    assert capsys.readouterr().err == f"{theirs.value}\n"
    for error, message in [
        (MemoryError(), "the file asks for more memory than any C3D needs\n"),
        (RuntimeError("odd"), "odd\n"),
    ]:

        def failing(_, error=error):
            raise error

        monkeypatch.setattr(ezc3d, "c3d", failing)
        assert run_worker_here(bad) == REJECTED
        assert capsys.readouterr().err == message


def test_labels_over_ninety_nine_parameters(monkeypatch, tmp_path):
    """LABELS, LABELS2 ... LABELS99 are read (25,000 points at most); no further."""
    point = {"LABELS": text("L1"), **{f"LABELS{k}": text(f"L{k}") for k in range(2, 101)}}
    reading, _, _ = fake_reading(labels=("A",), point=point)
    assert decode(monkeypatch, tmp_path, reading)["meta"]["labels"] == [f"L{k}" for k in range(1, 100)]


def test_an_sgi_file_read_through_its_intel_copy():
    from tests.conftest import shared_path

    decoded = decode_c3d(shared_path("c3d/c3dio_c3dorg-sample02_sgi_int.c3d"))
    assert decoded["points"].shape == (89, 36, 3) and decoded["meta"]["rate"] == 50.0
    assert decoded["meta"]["notes"] == [
        "written on an SGI/MIPS machine (big-endian): read in Intel byte order, numbers unchanged"
    ]
