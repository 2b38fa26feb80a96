"""The checks that apply to raw markers (C3D, TRC): pops, jitter, frozen and duplicated frames.

A marker set has no skeleton, no feet and no rotations, so only the checks of points run
(:data:`MARKER_KINDS`), each marker a joint of its own. Gaps (NaN) are no finding: a frame
with a missing neighbour has no deviation, a step into or out of a gap moves no marker. The
size is the median over the frames of the cloud's largest extent (NaN ignored).
"""

from __future__ import annotations

import warnings

import numpy as np

from gmr_studio.core.checks.context import CheckData
from gmr_studio.core.checks.model import CheckSettings, Finding
from gmr_studio.core.checks.run import CHECKS
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.model.motion import Motion, check_joint_name
from gmr_studio.core.space.units import unit_named

#: the checks that apply to markers
MARKER_KINDS = ("pop", "jitter", "frozen", "duplicate")


def marker_size(positions: np.ndarray) -> float:
    """Median over the frames of the largest extent of the present markers: (F, M, 3) -> float."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        extent = np.nanmax(np.nanmax(positions, axis=1) - np.nanmin(positions, axis=1), axis=1)
        size = float(np.nanmedian(extent)) if extent.size else float("nan")
    return size if np.isfinite(size) and size > 0 else 1.0


def _names(labels: tuple[str, ...]) -> list[str]:
    """The labels as joint names: a label the formats cannot carry, or repeated, becomes ``markerN``."""
    names: list[str] = []
    for m, label in enumerate(labels):
        try:
            name = check_joint_name(label)
        except ValueError:
            name = f"marker{m + 1}"
        names.append(name if name not in names else f"marker{m + 1}")
    return names


def marker_motion(markers: MarkerSet) -> Motion:
    """The markers as a motion of M roots (identity rotations, positions as translations,
    NaN in the gaps), its units stated in its comments."""
    n_frames, n_markers = markers.positions.shape[:2]
    return Motion(
        names=_names(markers.labels),
        parents=np.full(n_markers, -1),
        offsets=np.zeros((n_markers, 3)),
        rotation_orders=["XYZ"] * n_markers,
        has_translation=np.ones(n_markers, bool),
        rotations=np.broadcast_to(np.eye(3), (n_frames, n_markers, 3, 3)),
        translations=markers.positions,
        frame_time=1.0 / markers.rate,
        facts=FileFacts(unit=unit_named(markers.units)),
    )


def run_marker_checks(markers: MarkerSet, settings: CheckSettings | None = None) -> tuple[Motion, list[Finding]]:
    """The marker checks of ``settings.kinds`` (:data:`MARKER_KINDS`); returns the markers as
    a motion (:func:`marker_motion`, whose joints the findings name) and the findings."""
    settings = settings or CheckSettings()
    motion = marker_motion(markers)
    data = CheckData(motion, markers.positions, marker_size(markers.positions))
    found: list[Finding] = []
    for kind in settings.kinds:
        if kind in MARKER_KINDS:
            found.extend(CHECKS[kind](data, settings))
    return motion, sorted(found, key=lambda f: (f.start, f.kind, f.end, f.joints))
