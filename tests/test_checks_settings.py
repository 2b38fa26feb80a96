"""Findings and settings of the checks (core.checks.model): the JSON of a finding, every rule of
the settings' validation, limits met exactly, flags at the ends of a take."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from gmr_studio.core.checks.model import KINDS, CheckSettings, Finding, joint_flags, severity_levels


def _finding(**change) -> Finding:
    base = Finding("pop", (3,), ("LeftHand",), 10, 12, "warning", 1.23456789, "cm")
    return dataclasses.replace(base, **change)


def test_a_findings_json_and_level():
    assert _finding().to_dict() == {
        "kind": "pop",
        "joints": ["LeftHand"],
        "start": 10,
        "end": 12,
        "severity": "warning",
        "value": 1.234568,
        "units": "cm",
    }
    assert [_finding(severity=s).level for s in ("info", "warning", "error")] == [1, 2, 3]


def test_settings_keep_the_kinds_in_their_order():
    settings = CheckSettings(kinds=("teleport", "flip", "pop"))
    assert settings.kinds == ("pop", "flip", "teleport")
    assert settings.with_kinds(["jitter"]).kinds == ("jitter",)
    assert CheckSettings().kinds == KINDS
    with pytest.raises(ValueError, match="unknown check 'pops': expected some of foot-skate, penetration, pop,"):
        CheckSettings(kinds=("pop", "pops", "flips"))


@pytest.mark.parametrize(
    "limits", [(0.0, 0.0, 0.0), (0.0, 1.0, 2.0), (1.0, 1.0, 3.0), (1.0, 3.0, 3.0), (1.0, 2.0, math.inf)]
)
def test_limits_may_start_at_0_and_repeat(limits):
    assert CheckSettings(pop_limits=limits).pop_limits == limits


@pytest.mark.parametrize(
    "limits", [(-0.1, 1.0, 2.0), (2.0, 1.0, 3.0), (1.0, 3.0, 2.0), (1.0, 2.0), (1.0, 2.0, 3.0, 4.0)]
)
def test_limits_must_be_three_increasing_numbers_from_0(limits):
    with pytest.raises(ValueError, match="pop_limits must be three increasing numbers"):
        CheckSettings(pop_limits=limits)


@pytest.mark.parametrize("value", [0.0, -1.0, math.inf, math.nan])
def test_numbers_must_be_positive_and_finite(value):
    with pytest.raises(ValueError, match="pop_mad must be a positive number"):
        CheckSettings(pop_mad=value)


def test_numbers_and_limits_become_floats():
    settings = CheckSettings(pop_mad=6, pop_limits=[1, 2, 3], jitter_window="0.5")
    assert (settings.pop_mad, settings.pop_limits, settings.jitter_window) == (6.0, (1.0, 2.0, 3.0), 0.5)
    assert all(type(v) is float for v in (settings.pop_mad, *settings.pop_limits, settings.jitter_window))


def test_settings_dict_round_trip_and_defaults():
    data = CheckSettings().to_dict()
    assert data["kinds"] == list(KINDS)
    assert data["rest_limits"][2] is None  # no third level: an unbounded limit is written as null
    assert CheckSettings.from_dict(data) == CheckSettings()
    assert CheckSettings.from_dict({}) == CheckSettings()
    assert CheckSettings.from_dict({"kinds": ["pop"], "rest_limits": [2, None, None]}) == CheckSettings(
        kinds=("pop",), rest_limits=(2.0, math.inf, math.inf)
    )
    with pytest.raises(ValueError, match="unknown check setting 'a'"):
        CheckSettings.from_dict({"b": 1, "a": 2, "pop_mad": 3})


def test_severity_levels_at_the_limits_exactly():
    q = np.array([0.0, 0.99, 1.0, 1.5, 2.0, 2.5, 3.0, 10.0])
    levels = severity_levels(q, (1.0, 2.0, 3.0))
    np.testing.assert_array_equal(levels, [0, 0, 1, 1, 2, 2, 3, 3])
    assert levels.dtype == np.int8
    assert severity_levels(5, (1.0, 1.0, math.inf)) == 2
    for number in (*q, *q.tolist(), 2, math.nan, math.inf):  # numpy and Python numbers, one at a time
        level = severity_levels(number, (1.0, 2.0, 3.0))
        assert level == severity_levels(np.array([number]), (1.0, 2.0, 3.0))[0] and level.dtype == np.int8


def test_joint_flags_at_the_ends_and_overlapping():
    """A finding from before the first frame to past the last, one of the whole pose, and a
    milder one over a stronger one: the highest level wins, clipped to the take."""
    findings = [
        _finding(joints=(1,), start=-2, end=1, severity="info"),
        _finding(joints=(), start=3, end=3, severity="warning"),
        _finding(joints=(0, 2), start=2, end=9, severity="error"),
        _finding(joints=(2,), start=4, end=4, severity="info"),
    ]
    flags = joint_flags(findings, 5, 3)
    np.testing.assert_array_equal(
        flags,
        [[0, 1, 0], [0, 1, 0], [3, 0, 3], [3, 2, 3], [3, 0, 3]],
    )
    assert flags.dtype == np.int8


def test_settings_and_findings_are_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        CheckSettings().pop_mad = 3.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        _finding().value = 3.0
    assert len({CheckSettings(), CheckSettings()}) == 1
