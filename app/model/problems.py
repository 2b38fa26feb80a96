"""The document's problems: the quality checks of :mod:`core.checks` on the open motion.

:class:`Problems` runs :func:`core.checks.run_checks` on the document's snapshot (its cached
world positions, so no forward kinematics is repeated) whenever the document or its motion
changes (an edit such as trimming the T-pose frames or resampling, an undo), in a worker
thread: on a long take they take long enough to be felt, and must not freeze the window.
Results are kept per snapshot, so an undo shows the earlier findings at once. The settings
(which kinds, the thresholds: a :class:`core.checks.CheckSettings`) are remembered in the
window's QSettings as JSON (``checks/settings``).

``findings`` is the list for the current document, ``skipped`` the frames some checks left
out and why (:func:`core.checks.skipped_frames`: the rest pose at the ends), and ``flags``
the findings' (F, J) int8 severity levels (:func:`core.checks.joint_flags`: 0 none, 1
info, 2 warning, 3 error) for the timeline's flags and the joints drawn in a warning colour;
``changed`` is emitted when they are replaced (emptied as soon as the motion changes, filled when the checks are done).
A new document is checked once its first frame is drawn (``StudioState.document_shown``): the
checks must not delay it.
``min_level`` is what the dock lists, the timeline flags and the view colours: every
finding (1), warnings and errors (2) or errors (3); remembered too (``checks/shown``).
"""

from __future__ import annotations

import dataclasses
import json
import weakref

import numpy as np
from PyQt6.QtCore import QObject, QSettings, QThread, pyqtSignal

from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.core.checks import KINDS, CheckSettings, Finding, Skipped, joint_flags, run_checks, skipped_frames
from gmr_studio.core.checks.report import skipped_text

SETTINGS_KEY = "checks/settings"
SHOWN_KEY = "checks/shown"  # the lowest severity level shown (1 info, 2 warning, 3 error)
#: the colours of the severity levels 1-3 (info, warning, error) in the dock, on the
#: timeline and in the view, RGB in [0, 1]
LEVEL_COLOURS: dict[int, tuple[float, float, float]] = {
    1: (0.55, 0.80, 1.00),
    2: (1.00, 0.60, 0.00),
    3: (0.95, 0.12, 0.12),
}


@dataclasses.dataclass(frozen=True)
class LimitField:
    """How one kind's limits are shown and edited: the :class:`CheckSettings` field, the
    factor from its stored value to the shown one, and the shown unit."""

    field: str
    factor: float
    unit: str


#: per kind: its (info, warning, error) limits as the settings panel shows them
LIMITS: dict[str, LimitField] = {
    "foot-skate": LimitField("skate_limits", 100.0, "% of size slid"),
    "penetration": LimitField("penetration_limits", 100.0, "% of size deep"),
    "pop": LimitField("pop_limits", 100.0, "% of size"),
    "jitter": LimitField("jitter_limits", 100.0, "% of size RMS"),
    "flip": LimitField("flip_limits", 1.0, "deg"),
    "bone-length": LimitField("bone_limits", 1.0, "% change"),
    "frozen": LimitField("frozen_limits", 1.0, "s held"),
    "duplicate": LimitField("duplicate_limits", 1.0, "frames"),
    "teleport": LimitField("teleport_limits", 100.0, "% of size"),
    "rest-pose": LimitField("rest_limits", 1.0, "frames"),
}


def shown_limits(settings: CheckSettings, kind: str) -> tuple[float, float, float]:
    """``kind``'s limits in the panel's units (inf: never)."""
    limit = LIMITS[kind]
    return tuple(v * limit.factor for v in getattr(settings, limit.field))


def with_limits(settings: CheckSettings, kind: str, shown: tuple[float, float, float]) -> CheckSettings:
    """``settings`` with ``kind``'s limits set from the panel's units; ValueError if bad."""
    limit = LIMITS[kind]
    return dataclasses.replace(settings, **{limit.field: tuple(v / limit.factor for v in shown)})


def load_settings(settings: QSettings | None) -> CheckSettings:
    """The remembered check settings (defaults when none or unreadable)."""
    text = settings.value(SETTINGS_KEY) if settings is not None else None
    if not text:
        return CheckSettings()
    try:
        return CheckSettings.from_dict(json.loads(str(text)))
    except (ValueError, TypeError):
        return CheckSettings()


def count_text(findings: list[Finding]) -> str:
    """``"2 warnings, 17 info"``: the findings counted by severity, worst first."""
    counts = {s: sum(f.severity == s for f in findings) for s in ("error", "warning", "info")}
    parts = [f"{n} {s}{'s' if n != 1 and s != 'info' else ''}" for s, n in counts.items() if n]
    return ", ".join(parts) if parts else "none"


def finding_line(finding: Finding) -> str:
    """``"pop (warning) 300: LeftHand, 4.996 file units"``."""
    frames = f"{finding.start}" if finding.start == finding.end else f"{finding.start}-{finding.end}"
    joints = ", ".join(finding.names[:3]) + (", ..." if len(finding.names) > 3 else "") or "whole pose"
    return f"{finding.kind} ({finding.severity}) {frames}: {joints}, {finding.value:.4g} {finding.units}"


def skipped_lines(skipped: list[Skipped]) -> list[str]:
    """``"frame 0 (the rest pose at the start) is left out of every check but rest-pose"``:
    one line per stretch of frames some checks left out (:func:`core.checks.report.skipped_text`)."""
    return [skipped_text(s.to_dict()) for s in skipped]


class CheckJob(QThread):
    """Runs the checks of one snapshot in a worker thread; ``done(job, findings, flags)``
    (and ``job.skipped``: the frames some checks left out) or ``failed(job, message)``."""

    done = pyqtSignal(object, object, object)
    failed = pyqtSignal(object, str)

    def __init__(self, snapshot: Snapshot, settings: CheckSettings, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.snapshot = snapshot
        self.settings = settings
        self.skipped: list[Skipped] = []

    def run(self) -> None:
        motion = self.snapshot.motion
        try:
            # one thread: a job in the background leaves the other cores to the window
            findings = run_checks(motion, self.settings, positions=self.snapshot.positions, threads=1)
            self.skipped = skipped_frames(motion, self.settings)
            flags = joint_flags(findings, motion.n_frames, motion.n_joints)
        except Exception as exc:  # a check's bug must not take the window down: say it
            self.failed.emit(self, f"checks failed: {type(exc).__name__}: {exc}")
        else:
            self.done.emit(self, findings, flags)


class Problems(QObject):
    """The findings of the document's motion under :attr:`settings` (see the module)."""

    changed = pyqtSignal()  # findings and flags replaced (or the checks started: emptied)
    settings_changed = pyqtSignal()

    def __init__(self, state: StudioState, settings: QSettings | None = None, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.state = state
        self.store = settings
        self.settings = load_settings(settings)
        shown = settings.value(SHOWN_KEY) if settings is not None else None
        self.min_level = int(shown) if str(shown) in ("1", "2", "3") else 1
        self.findings: list[Finding] = []
        self.skipped: list[Skipped] = []
        self.flags: np.ndarray | None = None  # (F, J) int8 of the document as it is, or None
        self.running = False
        self.error = ""
        self._job: CheckJob | None = None
        self._wanted = False  # another run is needed when the job in flight is done
        #: snapshot -> (settings, findings, flags, skipped)
        self._cache: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
        state.document_changed.connect(self._on_document_changed)
        state.document_shown.connect(self.refresh)  # a new document is checked once it is drawn
        state.motion_changed.connect(self.refresh)

    # ------------------------------------------------------------------ settings
    def set_settings(self, settings: CheckSettings) -> None:
        """Check with ``settings`` from now on (remembered) and check again."""
        if settings == self.settings:
            return
        self.settings = settings
        if self.store is not None:
            self.store.setValue(SETTINGS_KEY, json.dumps(settings.to_dict()))
            self.store.sync()
        self.settings_changed.emit()
        self.refresh()

    def set_kind_enabled(self, kind: str, enabled: bool) -> None:
        kinds = [k for k in KINDS if (k in self.settings.kinds and k != kind) or (k == kind and enabled)]
        self.set_settings(self.settings.with_kinds(kinds))

    def reset_settings(self) -> None:
        self.set_settings(CheckSettings())

    def set_min_level(self, level: int) -> None:
        """Show the findings of ``level`` (1 info, 2 warning, 3 error) and worse (remembered)."""
        level = int(min(max(level, 1), 3))
        if level == self.min_level:
            return
        self.min_level = level
        if self.store is not None:
            self.store.setValue(SHOWN_KEY, level)
            self.store.sync()
        self.changed.emit()

    # -------------------------------------------------------------------- running
    def _on_document_changed(self) -> None:
        """Another document: its findings are to come (the checks start once its first frame
        is drawn, ``StudioState.document_shown``)."""
        self._publish([], None, running=self.state.snapshot is not None)

    def refresh(self) -> None:
        """Check the document as it is now (at once from the cache, else in the worker)."""
        snapshot = self.state.snapshot
        cached = self._cache.get(snapshot) if snapshot is not None else None
        if snapshot is None or (cached is not None and cached[0] == self.settings):
            self._wanted = False
            self._publish(*(cached[1:] if cached is not None else ([], None)))
            return
        if not (self.running and not self.findings):  # emptied already: nothing to replace
            self._publish([], None, running=True)
        if self._job is not None:
            self._wanted = True  # the job in flight checks an older motion: run again after it
            return
        self._start(snapshot)

    def _start(self, snapshot: Snapshot) -> None:
        self._wanted = False
        job = CheckJob(snapshot, self.settings, self)
        job.done.connect(self._on_job_done)
        job.failed.connect(self._on_job_failed)
        self._job = job
        job.start()

    def _finish(self, job: CheckJob) -> bool:
        """Forget ``job``; True if its result is for the document as it is now."""
        job.wait()
        job.deleteLater()
        self._job = None
        current = job.snapshot is self.state.snapshot and job.settings == self.settings
        if self._wanted or not current:
            self.refresh()
            return False
        return True

    def _on_job_done(self, job: CheckJob, findings: list[Finding], flags: np.ndarray) -> None:
        self._cache[job.snapshot] = (job.settings, findings, flags, job.skipped)
        if self._finish(job):
            self._publish(findings, flags, job.skipped)

    def _on_job_failed(self, job: CheckJob, message: str) -> None:
        if self._finish(job):
            self._publish([], None, error=message)
            self.state.show_message(message)

    def _publish(
        self, findings: list[Finding], flags: np.ndarray | None, skipped=(), *, running=False, error=""
    ) -> None:
        self.findings, self.flags, self.running, self.error = list(findings), flags, running, error
        self.skipped = list(skipped)
        self.changed.emit()

    def wait(self) -> None:
        """Block until the checks of the current document are done and published (tests,
        screenshots): the worker's signals are delivered here. A document whose first frame
        is not drawn yet is taken as shown (``StudioState.first_frame_drawn``): checked now."""
        from PyQt6.QtCore import QCoreApplication

        self.state.first_frame_drawn()  # a document not drawn yet: its checks start now
        while self._job is not None:
            job = self._job
            job.wait()
            QCoreApplication.processEvents()  # its done/failed signal, queued to this thread
            if self._job is job:  # not delivered yet (another event loop level): take it
                QCoreApplication.sendPostedEvents()

    def shutdown(self) -> None:
        """Wait for a job in flight (the window closes: a running QThread must not be destroyed)."""
        if self._job is not None:
            self._job.wait()

    # -------------------------------------------------------------------- queries
    @property
    def shown(self) -> list[Finding]:
        """The findings at :attr:`min_level` or worse."""
        return [f for f in self.findings if f.level >= self.min_level]

    def at_frames(self, first: int, last: int) -> list[Finding]:
        """The shown findings that cover any frame of ``first..last`` (inclusive)."""
        return [f for f in self.shown if f.start <= last and f.end >= first]

    def describe(self, first: int, last: int, most: int = 6) -> str:
        """One line per shown finding covering ``first..last`` (at most ``most``), for a tooltip."""
        found = self.at_frames(first, last)
        lines = [finding_line(f) for f in found[:most]]
        if len(found) > most:
            lines.append(f"... and {len(found) - most} more")
        return "\n".join(lines)

    def frame_levels(self) -> np.ndarray:
        """(F,) int8: the worst level shown (:attr:`min_level` or worse) at each frame, 0
        where none (zeros without flags)."""
        if self.flags is None or not self.flags.size:
            return np.zeros(self.state.n_frames, np.int8)
        levels = self.flags.max(axis=1)
        return np.where(levels >= self.min_level, levels, 0).astype(np.int8)
