"""Skeletons built from lab marker sets, printed (asserts nothing).

1. Every shared file of a known set: the set, the bone lengths' spread over the take (RMS
   about the fitted length, mm), and the marker residuals of the refinement: per marker the
   median over the frames (mm), its worst marker and the overall RMS; the closed form's for
   comparison (the goal: Plug-in Gait files within 10 mm per marker after ``--refine``).
2. Against the lab model stored in the file (``--against-file-model``): c3d.org sample 03
   (Plug-in Gait outputs PELO..., LFEO...) and opensim-core's walking5 (LHJC, LKJC, LAJC).
3. Speed: 10,000 frames of the 40-marker Plug-in Gait full-body sample (its 721 frames
   repeated, 2 mm of noise added) through skeleton building, the closed form and the
   refinement (the goal: under 10 s); wall and CPU seconds and the load average when it ends
   (the machine is shared).

Run: ``.venv/bin/python -m gmr_studio.core.benchmark.markers_built``.
"""

from __future__ import annotations

import os
import time

import numpy as np

from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers import read_markers
from gmr_studio.core.markers.built_motion import markers_to_built_motion
from gmr_studio.core.markers.file_model import compare_with_file_model, file_model_text
from gmr_studio.core.shared_data import shared_file

FILES = (
    "c3d/c3dorg_s00_NexGen_test1_PiG_fullbody.c3d",
    "c3d/c3dorg_s03_gait-pig.c3d",
    "c3d/opensim-core_walking5.c3d",
    "trc/opensim-core_dataWithBlanksForMissingMarkers.trc",
    "c3d/ezc3d_Qualisys.c3d",
    "c3d/c3dio_c3dorg-sample11_evart.c3d",
    "trc/opensim_gait2392_subject01_walk1.trc",
    "cmu/subject01/01_01.c3d",
)


def residual_report() -> None:
    print("Built skeletons: bone-length spread and marker residuals (mm, median over the frames)")
    print(f"{'file':<50} {'set':<18} {'spread max':>10} {'closed worst':>12} {'refined worst':>13} {'refined RMS':>11}")
    for relative in FILES:
        built = markers_to_built_motion(read_markers(shared_file(relative)), refine=True)
        valid = built.result.frame_valid
        before = np.nanmedian(built.refinement.residuals_before[valid], axis=0)
        after = np.nanmedian(built.refinement.residuals[valid], axis=0)
        rms = np.sqrt(np.nanmean(built.refinement.residuals[valid] ** 2))
        worst = int(np.argmax(after))
        print(
            f"{relative:<50} {built.built.set_match.definition.name:<18} {np.nanmax(built.built.spread):>10.1f} "
            f"{before.max():>12.1f} {after.max():>7.1f} {built.labels[worst]:<5} {rms:>11.2f}"
        )
        spreads = ", ".join(
            f"{n} {s:.1f}" for n, s in zip(built.built.skeleton.names, built.built.spread) if np.isfinite(s) and s > 0
        )
        print(f"    spread per bone: {spreads}")


def file_model_report() -> None:
    for relative in ("c3d/c3dorg_s03_gait-pig.c3d", "c3d/opensim-core_walking5.c3d"):
        markers = read_markers(shared_file(relative))
        for hip in ("harrington", "davis"):
            built = markers_to_built_motion(markers, hip=hip)
            motion = built.result.motion
            report = compare_with_file_model(markers, motion, world_positions(motion))
            print(f"\n{relative}, hips by {hip}, closed form, against the file's model points:")
            print(file_model_text(report))


def speed_report(n_frames: int = 10_000) -> None:
    markers = read_markers(shared_file("c3d/c3dorg_s00_NexGen_test1_PiG_fullbody.c3d")).in_units("mm")
    repeats = -(-n_frames // markers.n_frames)
    positions = np.concatenate([markers.positions] * repeats)[:n_frames]
    positions = positions + np.random.default_rng(0).normal(scale=2.0, size=positions.shape)
    big = markers.replace(positions=positions)
    wall, cpu = time.perf_counter(), time.process_time()
    built = markers_to_built_motion(big, refine=True)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    rms = np.sqrt(np.nanmean(built.refinement.residuals**2))
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    print(
        f"\nSpeed: {n_frames} frames x {big.n_markers} markers, build + closed form + refinement "
        f"({built.refinement.iterations} iterations): {wall:.2f} s wall, {cpu:.2f} s CPU (residual RMS {rms:.2f} mm; "
        f"load average {load})"
    )


if __name__ == "__main__":
    residual_report()
    file_model_report()
    speed_report()
