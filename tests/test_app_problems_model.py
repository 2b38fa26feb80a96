"""The app's model of the quality checks, without a window (app/model/problems.py): the level
colours, the limits in the panel's units, the settings and the level shown as remembered, the
lines and counts the dock shows, the checks run in a worker on every new motion (edits, undo,
settings) with failures said not raised, and what the dock, the timeline and the view ask.

Where a test needs particular findings the checks are stood in for (:func:`checks_find`):
the model runs the stand-in in its worker exactly as it runs the real checks."""

from __future__ import annotations

import json
import threading
import time

import numpy as np
import pytest
from PyQt6.QtCore import QSettings

from gmr_studio.app.model import problems as problems_module
from gmr_studio.app.model.problems import (
    LEVEL_COLOURS,
    LIMITS,
    SETTINGS_KEY,
    SHOWN_KEY,
    CheckJob,
    Problems,
    count_text,
    finding_line,
    load_settings,
    shown_limits,
    with_limits,
)
from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.core.checks import KINDS, CheckSettings, Finding, joint_flags, run_checks
from gmr_studio.core.kinematics.convention import pre_from_post
from tests.checks_walk import clean_walk
from tests.test_checks import with_translation

pytestmark = pytest.mark.gui  # a QApplication (signals, the worker thread)


def knocked_walk(*frames: int):
    """The clean walk (30 Hz, metres, 1 s) in the GMR form with the left hand knocked 5 cm at
    ``frames``: a pop and a stretched bone at each."""

    def knock(f):
        shift = np.zeros((f.size, 3))
        shift[np.isin(f, frames)] = [0.0, 0.05, 0.0]
        return shift

    return pre_from_post(with_translation(clean_walk(30.0, seconds=1.0), "LeftHand", knock))


def finding(kind="pop", severity="warning", start=3, end=None, names=("LeftHand",), value=1.0) -> Finding:
    joints = tuple(range(len(names)))
    return Finding(kind, joints, tuple(names), start, start if end is None else end, severity, value, "cm")


def found_at(model: Problems) -> list[tuple[str, int]]:
    return [(f.kind, f.start) for f in model.findings]


@pytest.fixture
def checks_find(monkeypatch):
    """Stand in for the checks: after ``checks_find(findings)`` every run finds ``findings``."""
    found: list[Finding] = []

    def run_checks(motion, settings, positions=None, threads=None) -> list[Finding]:
        return list(found)

    monkeypatch.setattr(problems_module, "run_checks", run_checks)
    return lambda findings: found.__setitem__(slice(None), findings)


def store(tmp_path, **values) -> QSettings:
    settings = QSettings(str(tmp_path / "settings.ini"), QSettings.Format.IniFormat)
    for key, value in values.items():
        settings.setValue(key, value)
    settings.sync()
    return settings


def _model(tmp_path=None):
    """A state, its problems (remembered in a file when ``tmp_path``), and the signals said."""
    state = StudioState()
    model = Problems(state, store(tmp_path) if tmp_path is not None else None)
    said = []
    model.changed.connect(lambda: said.append("changed"))
    model.settings_changed.connect(lambda: said.append("settings"))
    return state, model, said


def open_checked(state: StudioState, model: Problems, motion) -> Snapshot:
    """Open ``motion`` as a new document and wait for its checks."""
    snapshot = Snapshot.of(motion)
    state.open_document(snapshot, None)
    model.wait()
    return snapshot


# -------------------------------------------------------------------- what is shown
def test_the_level_colours_are_light_blue_orange_and_red():
    assert set(LEVEL_COLOURS) == {1, 2, 3}
    assert all(0.0 <= c <= 1.0 for colour in LEVEL_COLOURS.values() for c in colour)
    r, g, b = LEVEL_COLOURS[1]
    assert b == 1.0 and b > g > r >= 0.5  # info: a light blue
    r, g, b = LEVEL_COLOURS[2]
    assert r == 1.0 and 0.5 <= g < 0.7 and b == 0.0  # warning: orange
    r, g, b = LEVEL_COLOURS[3]
    assert r > 0.9 and 0.0 < g == b < 0.2  # error: red


def test_the_limits_in_the_panels_units():
    """docs/checks.md's table, lengths in % of the size."""
    documented = {
        "foot-skate": (1.0, 3.0, 8.0),
        "penetration": (2.0, 4.0, 8.0),
        "pop": (0.5, 1.0, 3.0),
        "jitter": (0.2, 0.4, 1.0),
        "flip": (45.0, 90.0, 150.0),
        "bone-length": (1.0, 2.5, 10.0),
        "frozen": (0.2, 0.5, 2.0),
        "duplicate": (1.0, 1.0, 3.0),
        "teleport": (5.0, 10.0, 20.0),
        "rest-pose": (1.0, 1.0, np.inf),
    }
    for kind, limits in documented.items():
        assert shown_limits(CheckSettings(), kind) == pytest.approx(limits, rel=1e-12), kind
    assert set(LIMITS) == set(KINDS)
    changed = with_limits(CheckSettings(), "teleport", (2.0, 4.0, 50.0))
    assert changed.teleport_limits == pytest.approx((0.02, 0.04, 0.5), rel=1e-12)
    assert with_limits(CheckSettings(), "frozen", (0.3, 0.6, 3.0)).frozen_limits == (0.3, 0.6, 3.0)
    assert changed.pop_limits == CheckSettings().pop_limits
    with pytest.raises(ValueError):
        with_limits(CheckSettings(), "flip", (90.0, 45.0, 150.0))


def test_the_panels_units_cannot_be_changed_by_accident():
    with pytest.raises(AttributeError):  # dataclasses.FrozenInstanceError
        LIMITS["pop"].factor = 1.0
    assert len({LIMITS[kind] for kind in KINDS}) == len(KINDS)  # hashable: frozen


def test_the_counts_worst_first():
    assert count_text([]) == "none"
    many = [finding(severity="info")] * 17 + [finding(severity="warning")] * 2 + [finding(severity="error")]
    assert count_text(many) == "1 error, 2 warnings, 17 info"
    one_each = [finding(severity=s) for s in ("warning", "info", "error", "error")]
    assert count_text(one_each) == "2 errors, 1 warning, 1 info"
    assert count_text([finding(severity="info")]) == "1 info"


def test_the_line_of_a_finding():
    assert finding_line(finding(start=300, value=4.99612)) == "pop (warning) 300: LeftHand, 4.996 cm"
    three = finding("flip", "error", 3, 5, ("A", "B", "C"), 123456.0)
    assert finding_line(three) == "flip (error) 3-5: A, B, C, 1.235e+05 cm"
    four = finding("pop", "info", 7, 7, ("A", "B", "C", "D"), 0.5)
    assert finding_line(four) == "pop (info) 7: A, B, C, ..., 0.5 cm"
    assert finding_line(finding("duplicate", names=(), value=2)) == "duplicate (warning) 3: whole pose, 2 cm"


# ---------------------------------------------------------------------- remembered
def test_the_remembered_settings(tmp_path):
    assert load_settings(None) == CheckSettings()
    assert load_settings(store(tmp_path)) == CheckSettings()
    chosen = CheckSettings(kinds=("pop", "flip"), flip_limits=(40, 80, 170))
    assert load_settings(store(tmp_path, **{SETTINGS_KEY: json.dumps(chosen.to_dict())})) == chosen
    for unreadable in ("{not json", '{"pop_limits": 5}', '{"pop_mad": "eight"}', '{"nope": 1}'):
        assert load_settings(store(tmp_path, **{SETTINGS_KEY: unreadable})) == CheckSettings(), unreadable


@pytest.mark.parametrize(("stored", "level"), [(None, 1), ("1", 1), ("2", 2), ("3", 3), ("0", 1), ("4", 1), ("x", 1)])
def test_the_level_shown_as_remembered(qtbot, tmp_path, stored, level):
    settings = store(tmp_path) if stored is None else store(tmp_path, **{SHOWN_KEY: stored})
    assert Problems(StudioState(), settings).min_level == level


def test_the_level_shown_is_clamped_and_remembered(qtbot, tmp_path):
    state, model, said = _model(tmp_path)
    model.set_min_level(1)  # as it is: nothing said, nothing written
    assert said == [] and model.store.value(SHOWN_KEY) is None
    model.set_min_level(0)
    assert said == [] and model.min_level == 1
    model.set_min_level(7)
    assert (model.min_level, said, int(model.store.value(SHOWN_KEY))) == (3, ["changed"], 3)
    model.set_min_level(2)
    assert (model.min_level, said, int(model.store.value(SHOWN_KEY))) == (2, ["changed", "changed"], 2)
    assert Problems(state, store(tmp_path)).min_level == 2
    _, unstored, _ = _model()
    unstored.set_min_level(3)
    assert unstored.min_level == 3


def test_settings_set_remembered_and_checked_again(qtbot, tmp_path):
    state, model, said = _model(tmp_path)
    open_checked(state, model, knocked_walk(12))
    said.clear()
    model.set_settings(CheckSettings())  # as it is: nothing said, nothing written, not run
    assert said == [] and model.store.value(SETTINGS_KEY) is None and not model.running
    model.set_kind_enabled("bone-length", False)
    kinds = tuple(k for k in KINDS if k != "bone-length")
    assert model.settings.kinds == kinds and said[:2] == ["settings", "changed"] and model.running
    assert json.loads(model.store.value(SETTINGS_KEY)) == CheckSettings(kinds=kinds).to_dict()
    model.wait()
    assert found_at(model) == [("pop", 12)]
    model.set_kind_enabled("pop", False)
    model.set_kind_enabled("bone-length", True)
    assert model.settings.kinds == tuple(k for k in KINDS if k != "pop")
    model.set_kind_enabled("flip", True)  # on already
    assert model.settings.kinds == tuple(k for k in KINDS if k != "pop")
    model.wait()
    assert found_at(model) == [("bone-length", 12)]
    model.reset_settings()
    assert model.settings == CheckSettings()
    model.wait()
    assert found_at(model) == [("pop", 12), ("bone-length", 12)]
    assert load_settings(store(tmp_path)) == CheckSettings()
    _, unstored, _ = _model()
    unstored.set_settings(CheckSettings(kinds=("pop",)))
    assert unstored.settings.kinds == ("pop",)


# ------------------------------------------------------------------------ running
def _run_job(snapshot, settings=None):
    job = CheckJob(snapshot, settings or CheckSettings())
    said = []
    job.done.connect(lambda *args: said.append(("done", *args)))
    job.failed.connect(lambda *args: said.append(("failed", *args)))
    job.run()  # in this thread: the signals are delivered at once
    return job, said


def test_the_job_gives_the_findings_and_their_flags(qtbot):
    snapshot = Snapshot.of(knocked_walk(12))
    settings = CheckSettings(kinds=("pop",))
    job, said = _run_job(snapshot, settings)
    ((what, sender, findings, flags),) = said
    assert (what, sender) == ("done", job)
    assert findings == run_checks(snapshot.motion, settings, positions=snapshot.positions)
    assert [(f.kind, f.start) for f in findings] == [("pop", 12)]
    np.testing.assert_array_equal(flags, joint_flags(findings, 30, snapshot.motion.n_joints))


def test_a_check_that_fails_is_said_not_raised(qtbot, monkeypatch):
    def broken(*args, **kwargs):
        raise ZeroDivisionError("a check's bug")

    monkeypatch.setattr(problems_module, "run_checks", broken)
    job, said = _run_job(Snapshot.of(knocked_walk(12)))
    assert said == [("failed", job, "checks failed: ZeroDivisionError: a check's bug")]
    state = StudioState()
    messages = []
    state.message.connect(messages.append)
    model = Problems(state)
    open_checked(state, model, knocked_walk(12))
    assert (model.findings, model.flags, model.running) == ([], None, False)
    assert model.error == messages[-1] == "checks failed: ZeroDivisionError: a check's bug"


def test_a_new_model_has_nothing_and_is_not_running(qtbot):
    model = Problems(StudioState())
    assert (model.findings, model.flags, model.running, model.error) == ([], None, False, "")
    assert not model.frame_levels().size


def test_edits_run_again_and_undo_is_at_once(qtbot):
    state, model, said = _model()
    first, second = Snapshot.of(knocked_walk(12)), Snapshot.of(knocked_walk(20))
    state.open_document(first, None)
    assert model.running and model.findings == [] and model.flags is None and said == ["changed"]
    model.wait()
    expected = run_checks(first.motion, CheckSettings(), positions=first.positions)
    assert model.findings == expected and not model.running and model.error == ""
    np.testing.assert_array_equal(model.flags, joint_flags(expected, 30, first.motion.n_joints))
    state.apply_snapshot(second)
    assert model.running
    model.wait()
    assert found_at(model) == [("pop", 20), ("bone-length", 20)]
    state.apply_snapshot(first)  # as an undo does: kept with the snapshot, no run
    assert not model.running and model.findings == expected
    model.set_settings(CheckSettings(kinds=("pop",)))  # kept with other settings: run again
    assert model.running
    model.wait()
    assert found_at(model) == [("pop", 12)]
    state.snapshot = None
    model.refresh()
    assert (model.findings, model.flags, model.running) == ([], None, False)


def test_an_edit_while_the_checks_run_gets_its_own_findings(qtbot):
    state, model, _ = _model()
    first, second = Snapshot.of(knocked_walk(12)), Snapshot.of(knocked_walk(20))
    state.open_document(first, None)
    state.apply_snapshot(second)  # before the first run is done
    assert model.running
    model.wait()
    assert found_at(model) == [("pop", 20), ("bone-length", 20)] and not model.running
    state.apply_snapshot(first)  # the first run's findings were kept with its snapshot
    assert not model.running and found_at(model) == [("pop", 12), ("bone-length", 12)]
    state.open_document(second, None)
    model.set_settings(CheckSettings(kinds=("bone-length",)))  # while it runs: its settings are old
    model.wait()
    assert found_at(model) == [("bone-length", 20)]


def test_back_to_a_checked_motion_while_another_is_checked(qtbot):
    """Undo to a motion already checked while the edit's checks run: the kept findings are
    shown at once and stay when the stale run ends (its findings kept for a redo)."""
    state, model, _ = _model()
    first, second = Snapshot.of(knocked_walk(12)), Snapshot.of(knocked_walk(20))
    state.open_document(first, None)
    model.wait()
    kept = list(model.findings)
    state.apply_snapshot(second)  # the edit: a run starts
    state.apply_snapshot(first)  # the undo: from what was kept
    assert model.findings == kept and not model.running
    model.wait()
    assert model.findings == kept and not model.running
    state.apply_snapshot(second)  # the redo: the stale run's findings, at once
    assert not model.running and found_at(model) == [("pop", 20), ("bone-length", 20)]


def test_a_refresh_asked_while_the_checks_run_gets_a_run_of_its_own(qtbot, monkeypatch):
    """The first run fails (say, out of memory), the motion is asked for again meanwhile:
    it is checked again after it, and its findings shown, not the stale failure."""
    calls = []

    def fails_once(*args, **kwargs):
        calls.append(1)
        if len(calls) == 1:
            raise MemoryError("transient")
        return run_checks(*args, **kwargs)

    monkeypatch.setattr(problems_module, "run_checks", fails_once)
    state, model, _ = _model()
    state.open_document(Snapshot.of(knocked_walk(12)), None)
    model.refresh()  # the same motion asked for while its run is in flight
    model.wait()
    assert len(calls) == 2 and model.error == ""
    assert found_at(model) == [("pop", 12), ("bone-length", 12)]


def test_shutting_down_waits_for_the_checks_in_flight(qtbot, monkeypatch):
    """The window closes while the checks run: it waits for them (a running thread must not
    be destroyed); with nothing running it returns at once."""
    started, finished = threading.Event(), []

    def slow(*args, **kwargs):
        started.set()
        time.sleep(0.2)
        finished.append(1)
        return []

    monkeypatch.setattr(problems_module, "run_checks", slow)
    state, model, _ = _model()
    model.shutdown()  # nothing running
    state.open_document(Snapshot.of(knocked_walk()), None)
    assert started.wait(5)
    model.shutdown()
    assert finished == [1]
    model.wait()
    assert not model.running


# ------------------------------------------------------------------------ queries
def test_what_the_dock_timeline_and_view_ask(qtbot, checks_find):
    state, model, _ = _model()
    open_checked(state, model, knocked_walk())
    assert model.findings == [] and not model.frame_levels().any() and model.frame_levels().shape == (30,)
    found = [
        finding("pop", "info", 3, 5, value=1.0),
        finding("flip", "warning", 6, 6, ("A", "B"), value=2.0),
        finding("teleport", "error", 8, 9, ("A", "B", "C"), value=3.0),
    ]
    checks_find(found)
    open_checked(state, model, knocked_walk())
    assert model.shown == found
    assert model.at_frames(5, 7) == found[:2] and model.at_frames(1, 3) == found[:1]
    assert model.at_frames(7, 7) == [] and model.at_frames(9, 20) == found[2:] and model.at_frames(0, 2) == []
    levels = np.zeros(30, np.int8)
    levels[3:6], levels[6], levels[8:10] = 1, 2, 3
    np.testing.assert_array_equal(model.frame_levels(), levels)
    assert model.frame_levels().dtype == np.int8
    model.set_min_level(2)
    assert model.shown == found[1:] and model.at_frames(3, 6) == found[1:2]
    np.testing.assert_array_equal(model.frame_levels(), np.where(levels >= 2, levels, 0))
    model.set_min_level(3)
    assert model.shown == found[2:]
    np.testing.assert_array_equal(model.frame_levels(), np.where(levels == 3, 3, 0))


def test_the_tooltip_of_frames(qtbot, checks_find):
    state, model, _ = _model()
    eight = [finding(start=s, names=(f"J{s}",)) for s in range(8)]
    checks_find(eight)
    open_checked(state, model, knocked_walk())
    lines = model.describe(0, 7).split("\n")
    assert lines == [finding_line(f) for f in eight[:6]] + ["... and 2 more"]
    assert model.describe(0, 5).split("\n") == [finding_line(f) for f in eight[:6]]
    assert model.describe(0, 7, most=7).split("\n") == [finding_line(f) for f in eight[:7]] + ["... and 1 more"]
    assert model.describe(2, 2) == finding_line(eight[2]) and model.describe(9, 9) == ""
