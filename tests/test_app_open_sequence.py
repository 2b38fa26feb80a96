"""Opening a file in the window: its first frame is drawn before the work it does not need
(the quality checks, the foot contacts), which follows at once and fills the docks with
what the core computes, the Problems list once per document."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.core.analysis.contacts import foot_contacts
from gmr_studio.core.checks import run_checks
from gmr_studio.core.kinematics.convention import pre_from_post
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.checks_walk import clean_walk
from tests.conftest import shared_path

pytestmark = pytest.mark.gui

WALK = "cmu/subject01/01_01.bvh"
studio = app_fixtures.studio


def watch_open(window) -> list[tuple[str, bool]]:
    """The events of an opening, in order, each with whether the foot contacts were there:
    'drawn' for each render of the view, 'shown' for the state's document_shown, 'checked'
    when the checks publish their findings."""
    events: list[tuple[str, bool]] = []

    def note(event: str) -> None:
        events.append((event, window.contact_bars.strip.contacts is not None))

    window.view.scene.plotter.ren_win.AddObserver("EndEvent", lambda *_: note("drawn"))
    window.state.document_shown.connect(lambda: note("shown"))
    window.problems.changed.connect(lambda: None if window.problems.running else note("checked"))
    return events


def test_the_first_frame_is_drawn_before_the_checks_and_contacts_start(studio, qtbot):
    events = watch_open(studio)
    open_file(studio, shared_path(WALK))
    qtbot.waitUntil(lambda: studio.state.shown, timeout=10000)
    studio.problems.wait()
    qtbot.waitUntil(lambda: studio.contact_bars.strip.contacts is not None, timeout=10000)
    names = [name for name, _ in events]
    first_drawn = names.index("drawn")
    assert events[first_drawn] == ("drawn", False)  # drawn without the contacts
    assert first_drawn < names.index("shown") < names.index("checked")


def test_once_shown_the_docks_hold_what_the_core_computes(studio, qtbot):
    changes: list[tuple[bool, int]] = []
    studio.problems.changed.connect(lambda: changes.append((studio.problems.running, len(studio.problems.findings))))
    open_file(studio, shared_path(WALK))
    studio.problems.wait()
    qtbot.waitUntil(lambda: studio.contact_bars.strip.contacts is not None, timeout=10000)
    state, problems = studio.state, studio.problems
    expected = run_checks(state.motion, problems.settings, positions=state.positions)
    assert [(f.kind, f.start, f.end, f.joints) for f in problems.findings] == [
        (f.kind, f.start, f.end, f.joints) for f in expected
    ]
    assert [change for change in changes if not change[0]] == [(False, len(expected))]  # listed once
    assert studio.problems_panel.table.rowCount() == len(problems.shown)
    contacts = foot_contacts(state.motion, state.positions)
    assert studio.contact_bars.strip.contacts.names == contacts.names
    np.testing.assert_array_equal(studio.contact_bars.strip.contacts.planted, contacts.planted)


def test_without_a_view_a_document_is_shown_as_it_opens(qtbot):
    state = StudioState()
    shown: list[bool] = []
    state.document_changed.connect(lambda: shown.append(state.shown))
    state.document_shown.connect(lambda: shown.append(state.shown))
    state.open_document(Snapshot.of(pre_from_post(clean_walk(30.0, seconds=0.5))), None)
    assert shown == [False, True]
    state.first_frame_drawn()  # said again: nothing more
    assert shown == [False, True]
