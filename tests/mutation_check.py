"""Re-run the mutation checks of docs/reliability.md ("Tests that can fail").

Each mutation replaces one piece of the code, runs the tests meant to catch it, and puts the
file back as it was (from the text read before, whatever happens). A mutation the tests do
not catch is printed as SURVIVED and makes the exit code 1.

    GMR_REQUIRE_GUI=1 xvfb-run -a .venv/bin/python -m tests.mutation_check [INDEX ...]

Not part of the test suite (it edits the working tree while it runs: do not run it with the
suite, nor on a tree other processes are reading).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: (what, file, text replaced, replacement, tests that must fail); or (what, file,
#: [(text replaced, replacement), ...], tests)
MUTATIONS = [
    (
        "zero-frame split offset 0 (the bug)",
        "core/edits/operations.py",
        "        offset=rest_world_positions(motion)[j],\n",
        "        offset=np.zeros(3),\n",
        ["tests/test_operations_rest.py"],
    ),
    (
        "join ignores the offset the split kept",
        "core/edits/operations.py",
        "            mean = kept.copy()\n    elif",
        "            pass\n    elif",
        ["tests/test_operations_rest.py"],
    ),
    (
        "fit_rigid RMS over all K points",
        "core/space/similarity.py",
        "rms = np.sqrt(error.sum(axis=-1) / safe[..., 0])",
        "rms = np.sqrt(error.sum(axis=-1) / points.shape[-2])",
        ["tests/test_procrustes.py"],
    ),
    (
        "atomic: no chmod",
        "core/atomic.py",
        [
            ("os.chmod(temporary, target.stat().st_mode & 0o7777)", "pass"),
            ("os.chmod(temporary, 0o666 & ~umask)", "pass"),
        ],
        ["tests/test_atomic.py"],
    ),
    (
        "gmr fuzz exits 0 on failures",
        "core/cli/fuzz.py",
        'FORMAT:INDEX --save case.bin")\n        return 1',
        'FORMAT:INDEX --save case.bin")\n        return 0',
        ["tests/test_fuzz.py::test_the_fuzz_command_exits_1_and_prints_the_replay_line_when_a_case_fails"],
    ),
    (
        "export: World root not renamed",
        "core/formats/bvh_export.py",
        "        world = _unique(world_root, set(names))",
        "        world = world_root",
        ["tests/test_export.py::test_a_joint_named_world_keeps_its_name_and_the_synthetic_root_takes_another"],
    ),
    (
        "app: no except Exception around export",
        "app/window/exports.py",
        '            self.files.report(describe_unexpected(f"Exporting {path}", exc))\n            return False\n',
        "            raise\n",
        ["tests/test_export_app.py"],
    ),
    (
        "shift_root: old root always gets translation channels",
        "core/edits/operations.py",
        "        has_translation[old_root] = has_translation[new_root]\n",
        "        has_translation[old_root] = True\n",
        ["tests/test_operations_rest.py"],
    ),
    (
        "shift_root: new root keeps its own flag",
        "core/edits/operations.py",
        "        has_translation[new_root] = True\n",
        "        has_translation[new_root] = has_translation[old_root]\n",
        ["tests/test_operations_rest.py"],
    ),
    (
        "shift_root: old root's translation from the static offset",
        "core/edits/operations.py",
        "        translations[:, old_root] = -t1\n",
        "        translations[:, old_root] = -offsets[new_root]\n",
        ["tests/test_operations_rest.py"],
    ),
    (
        "shift_root: old root's flag not moved",
        "core/edits/operations.py",
        "        has_translation[old_root] = has_translation[new_root]\n",
        "",
        ["tests/test_operations_rest.py"],
    ),
    (
        "peers: a failing peer dropped",
        "core/benchmark/peers.py",
        '            results.append(PeerResult(distribution, version, "(failed)", 0, nan, nan, nan, 0, failure))\n',
        "",
        ["tests/test_bench.py::test_a_peer_that_fails_is_reported_and_each_row_is_checked_on_its_own_output"],
    ),
    (
        "peers: pymotion Euler row reports the cached positions",
        "core/benchmark/peers.py",
        "stored.best, stored_positions, names)",
        "stored.best, cached_positions, names)",
        ["tests/test_bench.py::test_pymotion_times_and_checks_each_of_its_rows"],
    ),
    (
        "bench --data ignored",
        "core/cli/bench.py",
        "folders=(shared_data_dir(), *args.data),",
        "folders=(shared_data_dir(),),",
        ["tests/test_bench.py::test_bench_command_on_a_tiny_input"],
    ),
    (
        "demo: walk 0.01% faster",
        "core/demo.py",
        "WALK_SPEED = 125.0  # cm/s",
        "WALK_SPEED = 125.0125  # cm/s",
        ["tests/test_demo.py::test_the_demo_in_memory_is_the_committed_one"],
    ),
    (
        "FK: compiled kernel ignores the convention",
        "core/kinematics/engine.py",
        "                plan.pre,\n                plan.staged,",
        "                True,\n                plan.staged,",
        ["tests/test_fk_engine.py::test_the_public_entry_point_matches_the_per_joint_reference"],
    ),
    (
        "writers format all frames at once (memory)",
        "core/formats/textmotion.py",
        "WRITE_CHUNK_FRAMES = 4096",
        "WRITE_CHUNK_FRAMES = 10**9",
        ["tests/test_stress.py::test_peak_memory_extrapolates_within_the_claim"],
    ),
    # issue 24: the 21 planted bugs that survived the suite of their day, each now caught
    (
        "compare: per-joint worst frame is the row, not A's frame",
        "core/compare/result.py",
        "np.where(seen, frames[rows] if len(frames) else -1, -1)",
        "np.where(seen, rows if len(frames) else -1, -1)",
        ["tests/test_compare_blind_spots.py"],
    ),
    (
        "compare: rigid fit without the reflection fix",
        "core/space/similarity.py",
        "        sign[2] = -1.0\n",
        "        pass\n",
        ["tests/test_compare_blind_spots.py"],
    ),
    (
        "curves: Euler of fewer than 3 channels takes the last angles",
        "core/analysis/curves.py",
        "angles[:, : len(order)]",
        "angles[:, -len(order) :]",
        ["tests/test_curves_mirror_blind_spots.py"],
    ),
    (
        "autosave: only the 10th edit saves, not every 10th",
        "app/reliability/autosave.py",
        "self.edits % self.every == 0",
        "self.edits == self.every",
        ["tests/test_app_autosave_rules.py"],
    ),
    (
        "recovery: listed oldest first",
        "app/reliability/recovery.py",
        "key=lambda r: r.saved_at, reverse=True",
        "key=lambda r: r.saved_at, reverse=False",
        ["tests/test_app_autosave_rules.py", "tests/test_app_recovery.py"],
    ),
    (
        "joint transforms: root BVH rotation, product order swapped",
        "app/model/joint_transforms.py",
        "rotation = motion.rotations[frame, joint] @ rotation",
        "rotation = rotation @ motion.rotations[frame, joint]",
        ["tests/test_joint_transforms.py"],
    ),
    (
        "layers: B's samples at A's rate",
        "core/compare/clock.py",
        "    return (frames / rate_a + offset_seconds) * common_rate(rate_a, rate_b)",
        "    return (frames / rate_a + offset_seconds) * rate_a",
        ["tests/test_app_layers_clock.py"],
    ),
    (
        "audit: ok ignores lost joints",
        "core/compare/audit.py",
        "return not self.error and not self.lost_joints and self.relative_error",
        "return not self.error and self.relative_error",
        ["tests/test_compare_blind_spots.py"],
    ),
    (
        "dataset: resampled files keep the source rate",
        "core/cli/dataset.py",
        "        frame_rate = rate\n",
        "        pass\n",
        ["tests/test_dataset.py"],
    ),
    (
        "compare: JSON compared counts NaN samples",
        "core/compare/result.py",
        "count = int(values.size)",
        "count = int(errors.size)",
        ["tests/test_compare_blind_spots.py"],
    ),
    (
        "contacts: up axis fixed to Y",
        "core/analysis/contacts.py",
        'up = 2 if up_axis_of(motion) == "z" else 1',
        "up = 1",
        ["tests/test_contacts.py"],
    ),
    (
        "inspector: the parent's GMR world rotation shown",
        "app/docks/inspector.py",
        "gmr_world = state.rotations[f, j]",
        "gmr_world = state.rotations[f, max(parent, 0)]",
        ["tests/test_app_inspector.py"],
    ),
    (
        "autosave: old copy kept when the recovery path changes",
        "app/reliability/autosave.py",
        '            self._submit("remove", self.current, None, 0)\n        self.current = path\n',
        "            pass\n        self.current = path\n",
        ["tests/test_app_autosave_rules.py"],
    ),
    (
        "mirror: rotation orders not swapped with the sides",
        "core/edits/mirror.py",
        "rotation_orders=tuple(motion.rotation_orders[s] for s in sigma),",
        "rotation_orders=motion.rotation_orders,",
        ["tests/test_curves_mirror_blind_spots.py"],
    ),
    (
        "layers: another document keeps the layer's old offset",
        "app/model/layers.py",
        '                layer.offset, layer.auto_offset = "auto", True\n',
        "                pass\n",
        ["tests/test_app_layers_clock.py"],
    ),
    (
        "classroom: roots dropped from the stored count",
        "core/analysis/classroom.py",
        "rotation_orders]) | (motion.parents < 0)",
        "rotation_orders])",
        ["tests/test_classroom.py"],
    ),
    (
        "amass: SMPL-X's mocap_frame_rate refused",
        "core/formats/amass.py",
        'rate_key = "mocap_framerate" if "mocap_framerate" in arrays else "mocap_frame_rate"',
        'rate_key = "mocap_framerate"',
        ["tests/test_amass.py"],
    ),
    (
        "compare: quantiles overwrite their input",
        "core/compare/result.py",
        "work = values.reshape(-1) if overwrite else values.ravel().copy()",
        "work = values.reshape(-1)",
        ["tests/test_compare_blind_spots.py"],
    ),
    (
        "joint transforms: BVH world rotation always the joint's own",
        "app/model/joint_transforms.py",
        "return world_rotations[frame, child if rotation is not None else joint]",
        "return world_rotations[frame, joint]",
        ["tests/test_joint_transforms.py"],
    ),
    (
        "layers: the found offset not stored on recompute",
        "app/model/layers.py",
        "                    layer.comparison, layer.ghost = compare_layer(document, layer)\n"
        "                    layer.offset = layer.comparison.alignment.offset_frames\n",
        "                    layer.comparison, layer.ghost = compare_layer(document, layer)\n",
        ["tests/test_app_layers_clock.py"],
    ),
    (
        "body model: extra betas not cut to the model's count",
        "core/formats/body_model.py",
        ".reshape(-1)[: model.shapedirs.shape[2]]",
        ".reshape(-1)",
        ["tests/test_amass.py"],
    ),
    (
        "glTF: rotation keys not made continuous (the w >= 0 form, frame by frame)",
        "core/formats/gltf.py",
        "return translations, continuous_quaternions(quaternions_from_matrices(motion.rotations))",
        "return translations, quaternions_from_matrices(motion.rotations)",
        ["tests/test_gltf_continuity.py"],
    ),
]


def main(only: list[str]) -> int:
    survived = 0
    for index, (what, file, *change, tests) in enumerate(MUTATIONS):
        if only and str(index) not in only:
            continue
        pairs = change[0] if len(change) == 1 else [tuple(change)]
        path = ROOT / file
        original = mutated = path.read_text()
        if not all(old in original for old, _ in pairs):
            print(f"{index}: {what}: the code changed, update the mutation")
            survived += 1
            continue
        for old, new in pairs:
            mutated = mutated.replace(old, new, 1)
        path.write_text(mutated)
        try:
            done = subprocess.run(
                [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *tests],
                cwd=ROOT,
                capture_output=True,
                text=True,
                env=os.environ,
            )
        finally:
            path.write_text(original)
        failed = [line.split(" ")[1] for line in done.stdout.splitlines() if line.startswith("FAILED ")]
        caught = done.returncode != 0 and bool(failed)
        survived += not caught
        print(f"{index}: {what}: {'caught by ' + ', '.join(failed) if caught else 'SURVIVED'}", flush=True)
    return 1 if survived else 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
