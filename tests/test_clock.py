"""A motion's clock (core/timebase/clock.py): the rate a rounded frame time stands for (issue 40.8),
the same in ``gmr info`` and the app's timeline."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.formats import read_motion_with_channels
from gmr_studio.core.timebase.clock import frame_time_rounding, frames_per_frame, nominal_rate, rate_text
from tests.conftest import shared_files


@pytest.mark.parametrize(
    ("printed", "meant"),
    [
        ("0.008333", 120.0),  # 120.0048 taken literally
        (".0083333", 120.0),  # CMU's cgspeed BVH
        ("0.033333", 30.0),  # MocapBank: 30.0003 literally
        ("0.0333333", 30.0),  # Mixamo's BVH
        ("0.0166667", 60.0),
        ("0.01", 100.0),
        ("0.0417", 24.0),
        ("0.0333667", 30000 / 1001),  # NTSC 29.97
        ("0.041666661142086496", 24.0),  # a glTF's 32-bit key times
    ],
)
def test_a_rounded_frame_time_shows_the_rate_its_authors_meant(printed, meant):
    frame_time = float(printed)
    assert nominal_rate(frame_time) == pytest.approx(meant, rel=1e-12)
    assert abs(1.0 / nominal_rate(frame_time) - frame_time) <= frame_time_rounding(frame_time)


@pytest.mark.parametrize(
    "printed",
    [
        "0.0166",  # 60.241 Hz: no whole number's frame time rounds to it
        "0.03",  # one digit: anything from 29 to 40 Hz, none singled out
        "0.0083",  # 120.48 Hz: 1/120 s is 0.0083333, further than the rounding
    ],
)
def test_a_frame_time_no_nice_rate_rounds_to_keeps_its_exact_rate(printed):
    assert nominal_rate(float(printed)) == 1.0 / float(printed)


def test_the_rounding_is_half_a_unit_of_the_last_printed_decimal():
    assert frame_time_rounding(0.008333) == pytest.approx(5e-7)
    assert frame_time_rounding(0.0083333) == pytest.approx(5e-8)
    assert frame_time_rounding(0.04) == pytest.approx(5e-3)
    # a time computed in full precision keeps single precision's rounding (glTF stores floats)
    assert frame_time_rounding(1 / 24) == pytest.approx(1e-6 / 24)


@pytest.mark.parametrize(
    ("frame_time", "rate", "every"),
    [
        (0.0083333, 60.0, 2),  # 120 Hz printed to 7 decimals: 2.000008 frames, two as meant
        (0.0083333, 40.0, 3),
        (0.0083333, 120.0, 1),
        (0.008333, 30.0, 4),  # to 6 decimals: 4.0002 frames, within the rounding
        (0.0083333, 100.0, None),  # 1.2 frames: no whole number
        (0.03333, 15.0, None),  # 30.003 Hz: 2.0002 frames, beyond the rounding counted
        (1 / 30, 15.0 * (1 + 1e-5), None),  # an exact float time: beyond its 32-bit rounding
        (0.01, 1000.0, None),  # upsampling: a tenth of a frame
    ],
)
def test_a_rate_divides_a_frame_time_to_within_its_rounding(frame_time, rate, every):
    assert frames_per_frame(frame_time, rate) == every


def test_rate_text_is_the_nominal_rate_without_trailing_zeros():
    assert (rate_text(0.008333), rate_text(0.0333667), rate_text(0.0166)) == ("120", "29.97", "60.241")


@pytest.mark.parametrize("path", shared_files("bvh/*.bvh") + shared_files("cmu/subject01/01_01.bvh"))
def test_info_shows_the_nominal_rate_and_the_exact_one(path, capsys):
    """Every shared BVH's rate is a whole number within its printed frame time's rounding;
    ``gmr info`` shows it, the exact rate beside it, and both in its JSON."""
    motion, _ = read_motion_with_channels(path)
    assert main(["info", str(path), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["frame_rate"] == motion.frame_rate
    assert info["nominal_rate"] == nominal_rate(motion.frame_time) == np.rint(motion.frame_rate)
    assert main(["info", str(path)]) == 0
    frames_line = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("frames:"))
    assert f"at {rate_text(motion.frame_time)} Hz" in frames_line
    assert f"{motion.frame_rate:.6g} Hz exactly" in frames_line
