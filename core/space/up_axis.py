"""The up axis: one rule, one representation, for every feature and the view.

An up axis is ``"y"`` or ``"z"`` (:data:`UP_AXES`); :func:`axis_index` gives its column
(1 or 2) where arrays are indexed. A motion's up axis (:func:`up_axis_of`) is what its file
states (:attr:`core.model.facts.FileFacts.up_axis`: a glTF, an AMASS file, a GMR file's
header, an edit that turned the world), else what its figure shows (:func:`detect_up_axis`:
the axis the figure spans more in its median frame, leaving out anchors). Contacts, checks,
curves, comparisons, exports, the view and the filmstrip all ask this function, so a Z-up BVH
(which cannot state its axis) is Z up everywhere.

Turning the world: :data:`Y_TO_Z` maps Y up to Z up, ``(x, y, z) -> (x, -z, y)`` (forward -Z
becomes +Y, as Blender converts BVH on import); :func:`up_turn` gives the rotation between
any two up axes.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from gmr_studio.core.model.motion import Motion

UP_AXES = ("y", "z")
#: Y up -> Z up: a rotation of +90 degrees about X
Y_TO_Z = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


def check_up_axis(axis: str) -> str:
    """``axis`` in lower case if it is an up axis ('y' or 'z', any case), else ValueError."""
    lowered = str(axis).lower()
    if lowered not in UP_AXES:
        raise ValueError(f"the up axis must be one of {', '.join(UP_AXES)}, not {axis!r}")
    return lowered


def axis_index(axis: str) -> int:
    """The column of an up axis in (..., 3) arrays: 1 for 'y', 2 for 'z'."""
    return 1 if check_up_axis(axis) == "y" else 2


def up_turn(source: str, target: str) -> np.ndarray:
    """(3, 3) the rotation of the world that makes ``target`` up where ``source`` was."""
    source, target = check_up_axis(source), check_up_axis(target)
    if source == target:
        return np.eye(3)
    return Y_TO_Z if target == "z" else Y_TO_Z.T


def up_axis_of(motion: Motion) -> str:
    """'y' or 'z': what the motion's file facts state, else :func:`detect_up_axis` on the
    joints that make the figure (leaving out :attr:`~core.model.motion.Motion.anchors`) at
    the frames :attr:`~core.model.motion.Motion.size` samples (the same frames whoever asks,
    so every feature gets the same answer)."""
    if motion.facts.up_axis is not None:
        return motion.facts.up_axis
    points = motion.sampled_positions
    anchors = motion.anchors
    return detect_up_axis(points[:, ~anchors] if anchors.any() else points)


def detect_up_axis(points: np.ndarray) -> str:
    """'y' or 'z': the axis the figure spans more in its median frame (a standing or walking
    figure is taller than it is wide or deep; X is never taken as up, since a T-pose is as
    wide as it is tall; up is taken along +axis).

    points : (F, N, 3) positions; NaN (gaps) ignored.
    """
    extents = median_extents(points)
    return "y" if extents[1] >= extents[2] else "z"


def median_extents(points: np.ndarray) -> np.ndarray:
    """(3,) median over frames of each axis' per-frame extent of points (F, N, 3) (frames
    with no point skipped; zeros when there is none)."""
    finite = np.isfinite(points).all(axis=-1)
    seen = finite.any(axis=1)
    if not seen.any():
        return np.zeros(3)
    high = np.where(finite[..., None], points, -np.inf).max(axis=1)[seen]
    low = np.where(finite[..., None], points, np.inf).min(axis=1)[seen]
    return np.median(high - low, axis=0)
