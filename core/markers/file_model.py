"""Our joint centres and pelvis frames against the lab model's own, stored in the C3D.

Vicon Plug-in Gait and pyCGM2 write their model's joint centres and segment frames into the
C3D they export, as points: joint centres by name (``LHJC``, ``LKJC``, ``LAJC``... as in
opensim-core's walking5 trial) and, for every segment, its origin and the ends of its three
axes (``PELO``, ``PELA``, ``PELL``, ``PELP``: origin, anterior, lateral, proximal; ``LFEO``...).
Plug-in Gait's segment origins are joint centres: the pelvis origin is the mid-point of the
hip centres, the femur's origin the knee centre and its proximal point the hip centre, the
tibia's origin the ankle centre (checked on c3d.org's sample 03: ``LFEP``-``RFEP`` are 170 mm
apart with their mid-point 0.05 mm from ``PELO``). :data:`FILE_POINTS` lists, per joint of the
built skeleton (:mod:`core.markers.build`), the file points tried in order.

:func:`compare_with_file_model` gives the position error per joint (mm) and the pelvis
angle error, after the constant rotation between the two axis conventions (the chordal mean
of the per-frame relative rotations), in degrees.
"""

from __future__ import annotations

import numpy as np

from gmr_studio.core.errors import OperationError
from gmr_studio.core.kinematics.fk import world_rotations
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rotations.euler import nearest_rotation, rotation_angle

FILE_POINTS = {
    "pelvis": ("PELO",),
    "LHJC": ("LHJC", "LFEP"),
    "RHJC": ("RHJC", "RFEP"),
    "LKJC": ("LKJC", "LFEO"),
    "RKJC": ("RKJC", "RFEO"),
    "LAJC": ("LAJC", "LTIO"),
    "RAJC": ("RAJC", "RTIO"),
    "LSJC": ("LSJC", "LCLO"),
    "RSJC": ("RSJC", "RCLO"),
    "LEJC": ("LEJC", "LHUO"),
    "REJC": ("REJC", "RHUO"),
    "LWJC": ("LWJC", "LRAO"),
    "RWJC": ("RWJC", "RRAO"),
}
PELVIS_POINTS = ("PELO", "PELA", "PELL", "PELP")


def file_model_points(markers: MarkerSet) -> list[str]:
    """The model outputs among the file's points (joint centres and segment-frame points)."""
    known = {p for points in FILE_POINTS.values() for p in points} | set(PELVIS_POINTS)
    return [label for label in markers.labels if label in known]


def compare_with_file_model(markers: MarkerSet, motion: Motion, positions: np.ndarray) -> dict:
    """Errors of our joints against the file's model points.

    markers : the marker set (mm) holding the model points; motion : our GMR motion on the
    same frames (mm, the file's axes); positions : (F, J, 3) its joint world positions.
    Returns ``{"joints": [{"name", "file_point", "frames", "mean_mm", "median_mm", "max_mm"}],
    "pelvis": {"file_segment", "frames", "median_deg", "max_deg"} or None}``.
    Raises OperationError when the file holds no model point we can compare.
    """
    markers = markers.in_units("mm")
    joints = []
    for name, candidates in FILE_POINTS.items():
        label = next((c for c in candidates if c in markers.labels), None)
        if label is None or name not in motion.names:
            continue
        theirs = markers.positions[:, markers.index(label)]
        error = np.linalg.norm(positions[:, motion.joint_index(name)] - theirs, axis=1)
        error = error[np.isfinite(error)]
        if error.size == 0:
            continue
        joints.append(
            {
                "name": name,
                "file_point": label,
                "frames": int(error.size),
                "mean_mm": float(error.mean()),
                "median_mm": float(np.median(error)),
                "max_mm": float(error.max()),
            }
        )
    pelvis = None
    if all(p in markers.labels for p in PELVIS_POINTS):
        o, a, lateral, p = (markers.positions[:, markers.index(q)] for q in PELVIS_POINTS)
        theirs = nearest_rotation(np.nan_to_num(np.stack([a - o, lateral - o, p - o], axis=-1)))
        seen = np.isfinite(np.stack([o, a, lateral, p])).all(axis=(0, 2))
        ours = world_rotations(motion)[:, int(motion.roots[0])]
        relative = np.swapaxes(theirs[seen], -1, -2) @ ours[seen]
        if relative.size:
            offset = nearest_rotation(relative.sum(axis=0))
            angles = np.degrees(rotation_angle(relative @ offset.T))
            pelvis = {
                "file_segment": "PEL (PELO, PELA, PELL, PELP)",
                "frames": int(seen.sum()),
                "median_deg": float(np.median(angles)),
                "max_deg": float(angles.max()),
            }
    if not joints and pelvis is None:
        raise OperationError(
            f"{markers.source or 'the file'} stores no model joint centres or segment frames "
            f"(looked for {', '.join(sorted({p for c in FILE_POINTS.values() for p in c}))}, PELO...)"
        )
    return {"joints": joints, "pelvis": pelvis}


def file_model_text(report: dict) -> str:
    lines = [f"{'joint':<8} {'file point':<10} {'frames':>6} {'mean mm':>8} {'median':>8} {'max':>8}"]
    for row in report["joints"]:
        lines.append(
            f"{row['name']:<8} {row['file_point']:<10} {row['frames']:>6} {row['mean_mm']:>8.1f} "
            f"{row['median_mm']:>8.1f} {row['max_mm']:>8.1f}"
        )
    pelvis = report.get("pelvis")
    if pelvis:
        lines.append(
            f"pelvis frame vs {pelvis['file_segment']}: median {pelvis['median_deg']:.2f} deg, "
            f"max {pelvis['max_deg']:.2f} deg over {pelvis['frames']} frames (after the constant axis offset)"
        )
    return "\n".join(lines)
