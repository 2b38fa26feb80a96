"""The round-trip auditor: a motion through every path the project offers, and back.

Each path turns the motion into another motion (in memory, through a written file, after an
edit) whose joints are matched with the original's by name; the path's error is the largest
distance between a joint's world position before and after, over all joints and frames,
relative to the skeleton's size (:attr:`Motion.size`). Each path has the tolerance the
project documents for it:

- operations (shift root, split, join, dummy removal, the GMR form): positions kept to
  1e-9 of the size (docs/conventions.md);
- the GMR file: 15 significant digits, 1e-12 (docs/gmr-format.md);
- BVH export, also of a forest after split all: 1e-6 (docs/formats.md);
- glTF export (``.glb`` in memory, read back by :mod:`core.formats.gltf_in`, metres and Y up
  turned back to the source's units and up axis), also of a forest after split all: 2e-7,
  float32 precision (about 6e-8 per value, composed down the chain; docs/gltf.md);
- for an AMC input, the ASF's rest pose read alone against the motion's rest pose: 1e-9.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path

import numpy as np

from gmr_studio.core.edits.dummies import remove_dummies
from gmr_studio.core.edits.operations import join_all, shift_root, split_all
from gmr_studio.core.edits.world import change_up_axis, scale_lengths
from gmr_studio.core.formats.acclaim import asf_beside, read_asf_file
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.formats.bvh_export import bvh_export
from gmr_studio.core.formats.gmr import gmr_text, read_gmr
from gmr_studio.core.kinematics.convention import post_from_pre, pre_from_post
from gmr_studio.core.kinematics.fk import forward_kinematics
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.space.up_axis import up_axis_of

OPERATION_TOLERANCE = 1e-9
GMR_FILE_TOLERANCE = 1e-12
BVH_FILE_TOLERANCE = 1e-6
#: glTF stores float32: rounding of each value composed down a chain of joints (docs/gltf.md)
GLTF_FILE_TOLERANCE = 2e-7


@dataclasses.dataclass(frozen=True)
class AuditPath:
    """One round trip: its worst position error (source units and relative to the size),
    the documented tolerance, the joint and frame of the worst error, the joints it moved
    beyond the tolerance, and the joints it lost (unmatched after the trip)."""

    name: str
    max_error: float
    relative_error: float
    tolerance: float
    worst_joint: str
    worst_frame: int
    failing_joints: tuple[str, ...] = ()
    lost_joints: tuple[str, ...] = ()
    error: str = ""

    @property
    def ok(self) -> bool:
        return not self.error and not self.lost_joints and self.relative_error <= self.tolerance

    def to_json(self) -> dict:
        return {
            "name": self.name,
            "max_error": self.max_error,
            "relative_error": self.relative_error,
            "tolerance": self.tolerance,
            "ok": self.ok,
            "worst_joint": self.worst_joint,
            "worst_frame": self.worst_frame,
            "failing_joints": list(self.failing_joints),
            "lost_joints": list(self.lost_joints),
            "error": self.error or None,
        }


#: a trip gives the motion after it, and the joints it removes on purpose (dummies)
Trip = Callable[[Motion], "Motion | tuple[Motion, list[str]]"]


def round_trips(motion: Motion, source: str | Path | None = None, every: int = 5) -> list[tuple[str, float, Trip]]:
    """The paths for a motion: (name, tolerance, function giving the motion after the trip).

    ``every``: shift the root to every ``every``-th joint; ``source``: the file the motion
    came from (an .amc adds the ASF rest-pose path).
    """
    gmr = pre_from_post(motion)
    trips: list[tuple[str, float, Trip]] = [
        ("to GMR in memory", OPERATION_TOLERANCE, lambda m: gmr),
        ("GMR file written and read", GMR_FILE_TOLERANCE, lambda m: read_gmr("audit.gmr", gmr_text(gmr).encode())),
        ("BVH written and read", BVH_FILE_TOLERANCE, _through_bvh),
        ("forest export after split all", BVH_FILE_TOLERANCE, lambda m: _through_bvh(split_all(gmr))),
        ("glTF written and read", GLTF_FILE_TOLERANCE, through_gltf),
        ("forest glTF after split all", GLTF_FILE_TOLERANCE, lambda m: through_gltf(split_all(gmr))),
        ("dummy removal", OPERATION_TOLERANCE, lambda m: remove_dummies(gmr)),
        ("dummy removal and back", OPERATION_TOLERANCE, _dummies_and_back),
        ("split all / join all", OPERATION_TOLERANCE, lambda m: join_all(split_all(gmr))),
    ]
    for joint in range(0, motion.n_joints, max(1, every)):
        name = motion.names[joint]
        trips.append((f"shift root to {name}", OPERATION_TOLERANCE, lambda m, j=joint: shift_root(gmr, j)))
    if source is not None and str(source).lower().endswith(".amc"):
        asf = asf_beside(Path(source))
        trips.append(("ASF rest pose against the AMC's", OPERATION_TOLERANCE, lambda m, a=asf: read_asf_file(a)))
    return trips


def _dummies_and_back(motion: Motion) -> tuple[Motion, list[str]]:
    """Dummies folded, then the BVH (post-rotation) form, with dummies where it needs them."""
    folded, removed = remove_dummies(pre_from_post(motion))
    return post_from_pre(folded)[0], removed


def _through_bvh(motion: Motion) -> Motion:
    """Export as BVH text, read it back, name the joints as the source's (end sites and
    single-word renames undone; added dummies and the World root stay unmatched)."""
    export = bvh_export(motion)
    read = read_bvh("audit.bvh", export.text().encode())
    back = {bvh: source for source, bvh in zip(motion.names, export.names) if bvh is not None}
    taken = set(back.values())
    names = [back.get(n) or (n if n not in taken else f"{n} (bvh)") for n in read.names]
    return read.replace(names=names)


def through_gltf(motion: Motion) -> Motion:
    """Export as ``.glb`` bytes (with the skin, as ``gmr convert`` writes it), read them
    back, and undo the export's unit scale and up-axis turn (a motion without frames goes
    as its rest pose, one frame)."""
    from gmr_studio.core.formats.gltf import build_gltf
    from gmr_studio.core.formats.gltf_in import read_gltf

    source = motion.rest_pose() if motion.n_frames == 0 else motion
    gltf, blob, summary = build_gltf(source)
    gltf.set_binary_blob(blob)
    data = b"".join(gltf.save_to_bytes())
    read = read_gltf("audit.glb", data=data)
    read = change_up_axis(scale_lengths(read, 1 / summary.metres_per_unit), up_axis_of(motion), "y")
    return read


def audit_motion(motion: Motion, source: str | Path | None = None, every: int = 5) -> list[AuditPath]:
    """Run every path of :func:`round_trips`; a path that raises is reported, not raised.

    A motion without frames (a skeleton only, ``Frames: 0``) is measured by the rest pose
    of what each path gives back."""
    reference = forward_kinematics(motion, with_rotations=False, threads=None)[0]
    rest = forward_kinematics(motion.rest_pose(), with_rotations=False)[0]
    results = []
    for name, tolerance, trip in round_trips(motion, source, every):
        try:
            after = trip(motion)
            after, removed = after if isinstance(after, tuple) else (after, [])
            if motion.n_frames == 0 and after.n_frames == 0:  # a skeleton only: what it kept is its rest pose
                after = after.rest_pose()
            truth = rest if after.n_frames == 1 and motion.n_frames != 1 else reference
            results.append(_measure(name, tolerance, motion, truth, after, set(removed)))
        except Exception as exc:  # a failing path is a finding of the audit
            results.append(AuditPath(name, np.inf, np.inf, tolerance, "", -1, error=f"{type(exc).__name__}: {exc}"))
    return results


def _measure(
    name: str, tolerance: float, motion: Motion, truth: np.ndarray, after: Motion, removed: set[str]
) -> AuditPath:
    """The worst distance of each joint from where it was; a joint the trip removed on
    purpose (a zero-length dummy) is measured against its nearest ancestor that stayed."""
    names, size = motion.names, motion.size
    index = {n: j for j, n in enumerate(after.names)}
    pairs = []
    for i in range(len(names)):
        k = i
        while names[k] not in index and names[k] in removed and motion.parents[k] >= 0:
            k = int(motion.parents[k])
        if names[k] in index:
            pairs.append((i, index[names[k]]))
    lost = tuple(n for n in names if n not in index and n not in removed)
    positions = forward_kinematics(after, with_rotations=False, threads=None)[0]
    source = np.array([i for i, _ in pairs], dtype=np.int64)
    target = np.array([j for _, j in pairs], dtype=np.int64)
    difference = truth[:, source] - positions[:, target]
    distance = np.sqrt(np.einsum("fjk,fjk->fj", difference, difference))
    worst_per_joint = distance.max(axis=0)
    frame, column = np.unravel_index(int(np.argmax(distance)), distance.shape)
    worst = float(distance[frame, column])
    failing = tuple(names[source[j]] for j in np.flatnonzero(worst_per_joint > tolerance * size))
    return AuditPath(
        name=name,
        max_error=worst,
        relative_error=worst / size,
        tolerance=tolerance,
        worst_joint=names[source[column]],
        worst_frame=int(frame),
        failing_joints=failing,
        lost_joints=lost,
    )
