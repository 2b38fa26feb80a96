"""The pictures of docs/checks.md (core.checks.figures): the quantity each one plots, on the clean
walk with planted defects, and the picture of a real take."""

from __future__ import annotations

import struct

import numpy as np
import pytest

from gmr_studio.core.checks import CheckSettings, figures
from gmr_studio.core.checks.figures import EXAMPLES, Example, figure, measured
from gmr_studio.core.checks.run import check_data
from gmr_studio.core.shared_data import PROJECT_ROOT
from tests.checks_walk import clean_walk
from tests.conftest import shared_path
from tests.test_checks import CM, with_translation


def _measured(motion, kind: str, joint: str | None, start: int = 0):
    settings = CheckSettings()
    whole, inner = check_data(motion, settings)
    return measured(Example("walk.bvh", kind, joint, 0, 10), whole, inner, settings, start)


def _shift(frames, axis: int, size: float):
    def shift(f):
        out = np.zeros((f.size, 3))
        out[np.isin(f, frames), axis] = size
        return out

    return shift


def _rested(motion, n: int = 10):
    rotations = motion.rotations.copy()
    rotations[:n] = np.eye(3)
    return motion.replace(rotations=rotations)


def test_the_distance_a_foot_slid_from_the_first_frame_reported():
    """The right toe moved 2 cm forward (Z, across the Y up axis) from frame 110 on; rest
    frames 0-9 unmeasured."""
    motion = with_translation(_rested(clean_walk(120.0, unit=CM)), "RightFoot", _shift(range(110, 600), 2, 2.0))
    values, label = _measured(motion, "foot-skate", "RightToe", 100)
    assert label == "horizontal distance from frame 100 (file units)"
    assert np.isnan(values[:10]).all() and values[100] == 0.0
    assert values[115] == pytest.approx(2.0, abs=1e-9)
    assert values.shape == (600,)


def test_the_deviation_of_a_pop():
    motion = with_translation(_rested(clean_walk(120.0, unit=CM)), "LeftHand", _shift([200], 0, 5.0))
    values, label = _measured(motion, "pop", "LeftHand")
    assert label == "deviation from the neighbours' midpoint (file units)"
    assert np.isnan(values[:11]).all() and np.isnan(values[-1])
    assert not np.isnan(values[11:-1]).any()
    assert values[200] == pytest.approx(5.0, rel=0.01) and values[199] == pytest.approx(2.5, rel=0.02)


def test_the_depth_of_a_foot_below_its_contacts():
    motion = with_translation(clean_walk(120.0, unit=CM), "RightFoot", _shift(range(95, 111), 1, -4.0))
    values, label = _measured(motion, "penetration", "RightToe")
    assert label == "depth below its contact level (file units)"
    assert values[100] == pytest.approx(4.0, rel=0.01) and abs(values[130]) < 0.5


def test_the_rest_fraction_and_no_picture_for_other_kinds():
    values, label = _measured(_rested(clean_walk(120.0, unit=CM)), "rest-pose", None)
    assert label == "fraction of the moving joints at rest"
    assert (values[:10] == 1.0).all() and (values[10:] < 0.6).all()
    with pytest.raises(ValueError, match="no picture for 'flip'"):
        _measured(clean_walk(30.0, seconds=1.0), "flip", "Head")


def _png_size(data: bytes) -> tuple[int, int]:
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", data[16:24])


def test_main_writes_one_picture_per_example(tmp_path, monkeypatch):
    """Into the folder given (first argument, else sys.argv's, else docs/images)."""
    written = []
    monkeypatch.setattr(figures, "EXAMPLES", EXAMPLES[-1:])
    monkeypatch.setattr(figures, "figure", lambda example: b"png of " + example.kind.encode())
    monkeypatch.setattr(figures, "atomic_write_bytes", lambda path, data: written.append((path, data)))
    assert figures.main([str(tmp_path), "ignored"]) == 0
    monkeypatch.setattr("sys.argv", ["figures", str(tmp_path / "argv")])
    assert figures.main() == 0
    assert figures.main([]) == 0
    assert written == [
        (tmp_path / "checks-rest-pose.png", b"png of rest-pose"),
        (tmp_path / "argv" / "checks-rest-pose.png", b"png of rest-pose"),
        (PROJECT_ROOT / "docs" / "images" / "checks-rest-pose.png", b"png of rest-pose"),
    ]


def test_every_example_has_its_picture_in_the_docs():
    """docs/checks.md shows one picture per example (docs/images/checks-KIND.png)."""
    pictures = {p.name for p in (PROJECT_ROOT / "docs" / "images").iterdir()}
    assert {f"checks-{e.kind}.png" for e in EXAMPLES} <= pictures


@pytest.mark.parametrize("example", EXAMPLES, ids=[e.kind for e in EXAMPLES])
def test_the_picture_of_each_example(example, monkeypatch):
    """docs/checks.md's pictures: 900 x 340 pixels, the measured quantity over the example's
    frames, the findings of its kind (and joint) there
    shaded over their frames and labelled at the top, titled with the file, kind and joint."""
    pyplot = pytest.importorskip("matplotlib.pyplot", reason="matplotlib comes with the bench extra")
    from gmr_studio.core.checks import run_checks
    from gmr_studio.core.formats import read_motion

    drawn = []
    subplots = pyplot.subplots

    def recorded(*args, **kwargs):
        drawn.append(subplots(*args, **kwargs))
        return drawn[-1]

    monkeypatch.setattr(pyplot, "subplots", recorded)
    motion = read_motion(shared_path(example.file))
    assert _png_size(figure(example)) == (900, 340)
    (_, axes), settings = drawn[0], CheckSettings()
    shown = [
        f
        for f in run_checks(motion, settings)
        if f.kind == example.kind
        and (example.joint is None or example.joint in f.names)
        and f.start <= example.last
        and f.end >= example.first
    ]
    assert shown, "each picture shows a finding"
    whole, inner = check_data(motion, settings)
    values, label = measured(example, whole, inner, settings, shown[0].start)
    frames = np.arange(example.first, example.last + 1)
    (line,) = axes.lines
    np.testing.assert_array_equal(line.get_xdata(), frames)
    np.testing.assert_array_equal(line.get_ydata(), values[frames])
    assert axes.get_xlim() == (example.first - 0.5, example.last + 0.5)
    spans = [(patch.get_x(), patch.get_x() + patch.get_width()) for patch in axes.patches]
    assert spans == [(f.start - 0.5, f.end + 0.5) for f in shown]
    assert [(t.xy, t.get_text()) for t in axes.texts] == [
        ((f.start, 1.0), f"{f.severity}: {f.value:.3g} {f.units}") for f in shown
    ]
    name = example.file.rsplit("/", 1)[-1]
    assert axes.get_title() == f"{name}: {example.kind}" + (f", {example.joint}" if example.joint else "")
    assert (axes.get_xlabel(), axes.get_ylabel()) == ("frame", label)
