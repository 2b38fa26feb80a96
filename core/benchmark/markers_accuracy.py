"""Marker-conversion accuracy, printed (asserts nothing) (docs/markers.md, "Accuracy and limits").

1. Real markers: CMU 01_01.c3d through the shipped ``cmu`` map (calibrated on frames
   0:1100) against the FK of 01_01.amc, on frames 1100:2751 (not used for calibration):
   MPJPE in millimetres per joint and overall, for both ways of aiming the bones; then the
   same onto the BVH skeleton of the take (against the BVH itself, its frame 0 a T-pose), and
   both after ``--refine`` (the goals: within 15 mm on the ASF, 20 mm on the BVH);
   the closed form with its root fitted (the default, :mod:`core.markers.root_fit`) and with
   the paper's root at the pelvis root virtual marker X1 (``root_at="pelvis"``).
2. Twist from the same trial: 02_01's joint positions as markers (the exact case), twists
   from 02_01 itself with every reference frame within 1 s of the query excluded: the
   distribution of the twist error (the angle between recovered and true local rotation;
   positions are exact, so it is all twist), per joint and overall. The same for 01_01, and
   without any reference (least change from frame to frame) for comparison.

Run: ``.venv/bin/python -m core.benchmark.markers_accuracy``.
"""

from __future__ import annotations

import time

import numpy as np

from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers import MarkerSet, markers_to_motion, read_markers
from gmr_studio.core.rotations.euler import rotation_angle
from gmr_studio.core.shared_data import shared_file

MM_PER_ASF_UNIT = 25.4 / 0.45  # CMU ASF ":units length 0.45": one unit is 1/0.45 inch
CALIBRATION_FRAMES = slice(0, 1100)
EVALUATION_FRAMES = slice(1100, None)


def mpjpe_report() -> None:
    markers = read_markers(shared_file("cmu/subject01/01_01.c3d"))
    skeleton = load_gmr(shared_file("cmu/subject01/01.asf"))
    truth = load_gmr(shared_file("cmu/subject01/01_01.amc"))
    expected = world_positions(truth)[EVALUATION_FRAMES]
    table = {}
    for aim in ("markers", "chain"):
        start = time.perf_counter()
        result = markers_to_motion(markers, skeleton, "cmu", frames=EVALUATION_FRAMES, aim=aim)
        elapsed = time.perf_counter() - start
        error = np.linalg.norm(world_positions(result.motion) - expected, axis=2) * MM_PER_ASF_UNIT
        table[aim] = error.mean(axis=0)
        print(f"aim={aim}: {result.motion.n_frames} frames converted in {elapsed:.2f} s")
    print("\nMPJPE (mm), CMU 01_01.c3d with the cmu map vs FK of 01_01.amc, frames 1100:2751")
    print(f"{'joint':<10} {'aim=markers':>12} {'aim=chain':>10}")
    for j, name in enumerate(skeleton.names):
        print(f"{name:<10} {table['markers'][j]:>12.1f} {table['chain'][j]:>10.1f}")
    print(f"{'overall':<10} {table['markers'].mean():>12.1f} {table['chain'].mean():>10.1f}")


def refine_report() -> None:
    """MPJPE over all mapped joints, closed form and refined, on the ASF and on the BVH."""
    from gmr_studio.core.markers.refine import refine_joints

    markers = read_markers(shared_file("cmu/subject01/01_01.c3d"))
    print("\nMPJPE (mm) over all joints, CMU 01_01.c3d with the cmu map, frames 1100:2751")
    print(f"{'skeleton':<24} {'root at X1':>10} {'closed form':>11} {'--refine':>9} {'refine s (wall/CPU)':>20}")
    for skeleton_file, truth_file, first in (
        ("cmu/subject01/01.asf", "cmu/subject01/01_01.amc", 0),
        ("cmu/subject01/01_01.bvh", "cmu/subject01/01_01.bvh", 1),  # the BVH's frame 0 is a T-pose
    ):
        skeleton = load_gmr(shared_file(skeleton_file))
        expected = world_positions(load_gmr(shared_file(truth_file)))[first:][EVALUATION_FRAMES]
        paper = markers_to_motion(markers, skeleton, "cmu", frames=EVALUATION_FRAMES, root_at="pelvis")
        result = markers_to_motion(markers, skeleton, "cmu", frames=EVALUATION_FRAMES)
        wall, cpu = time.perf_counter(), time.process_time()
        refined = refine_joints(result.motion, result.refine_targets(), weights=result.weights)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        at_x1 = np.linalg.norm(world_positions(paper.motion) - expected, axis=2).mean() * MM_PER_ASF_UNIT
        before = np.linalg.norm(world_positions(result.motion) - expected, axis=2).mean() * MM_PER_ASF_UNIT
        after = np.linalg.norm(world_positions(refined.motion) - expected, axis=2).mean() * MM_PER_ASF_UNIT
        name = skeleton_file.rsplit("/", 1)[1] + f" ({skeleton.n_joints} joints)"
        print(f"{name:<24} {at_x1:>10.1f} {before:>11.1f} {after:>9.1f} {wall:>10.1f} / {cpu:.1f}")


def twist_report(amc: str, asf: str) -> None:
    truth = load_gmr(shared_file(amc))
    skeleton = load_gmr(shared_file(asf))
    markers = MarkerSet(labels=truth.names, positions=world_positions(truth), rate=truth.frame_rate, units="mm")
    runs = {
        "reference, 1 s excluded": {"reference": truth, "exclude_within": 1.0},
        "no reference (least change)": {},
    }
    print(f"\nTwist error (degrees), {amc}: its joint positions as markers, {truth.n_frames} frames")
    for label, options in runs.items():
        start = time.perf_counter()
        result = markers_to_motion(markers, skeleton, "joints", **options)
        elapsed = time.perf_counter() - start
        position_error = np.abs(world_positions(result.motion) - world_positions(truth)).max() / truth.size
        angles = np.degrees(rotation_angle(np.swapaxes(result.motion.rotations, -1, -2) @ truth.rotations))[:, 1:]
        q = np.percentile(angles, [50, 90, 95, 99])
        print(
            f"  {label}: median {q[0]:.2f}, 90% {q[1]:.2f}, 95% {q[2]:.2f}, 99% {q[3]:.2f}, max {angles.max():.2f}"
            f"  (positions exact to {position_error:.1e} of the size; {elapsed:.2f} s)"
        )
        if "reference" in options:
            print(f"    {'joint':<10} {'median':>7} {'90%':>7} {'99%':>7} {'max':>7}")
            for j, name in enumerate(truth.names[1:]):
                p = np.percentile(angles[:, j], [50, 90, 99])
                print(f"    {name:<10} {p[0]:>7.2f} {p[1]:>7.2f} {p[2]:>7.2f} {angles[:, j].max():>7.2f}")


if __name__ == "__main__":
    mpjpe_report()
    refine_report()
    twist_report("cmu/subject02/02_01.amc", "cmu/subject02/02.asf")
    twist_report("cmu/subject01/01_01.amc", "cmu/subject01/01.asf")
