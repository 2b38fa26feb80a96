"""An edit's world transforms follow from the document's: the same as computing them afresh.

Trim keeps some frames (and resampling to a rate that divides the motion's every n-th),
scale multiplies every world position, up axis turns the world and mirror reflects it
(swapping left and right joints); shift root, split and join keep every world position. The
app hands the document's kinematics, so moved, to the result instead of running forward
kinematics again: on random rigs, the demo and a real file, what it holds equals the
result's own forward kinematics to 1e-9 of the size. The compiled pass that moves them gives
the numpy reference's numbers exactly.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from gmr_studio.app.model import commands
from gmr_studio.app.model.state import Snapshot, StudioState
from gmr_studio.core.demo import demo_motion
from gmr_studio.core.edits.clip import resample_edit, trim_edit
from gmr_studio.core.edits.edited import Edited
from gmr_studio.core.edits.mirror import mirror_edit, mirror_pairs
from gmr_studio.core.edits.operations import shift_root_edit, split_edit
from gmr_studio.core.edits.world import change_up_axis_edit, scale_lengths_edit
from gmr_studio.core.formats import load_gmr
from gmr_studio.core.kinematics import engine
from gmr_studio.core.kinematics.fk import forward_kinematics
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.timebase.clock import rate_text
from tests.conftest import random_motion, shared_path

#: a small two-sided rig: hips, two legs of two joints and a chest
SIDED_NAMES = ["Hips", "LeftUpLeg", "LeftLeg", "RightUpLeg", "RightLeg", "Chest"]
SIDED_PARENTS = [-1, 0, 1, 0, 3, 0]


def sided_rig(rng: np.random.Generator, n_frames: int = 7) -> Motion:
    """A random motion on :data:`SIDED_PARENTS` named so that mirror pairs its legs."""
    motion = random_motion(rng, SIDED_PARENTS, n_frames=n_frames, translation_joints=(2,))
    return motion.replace(names=SIDED_NAMES)


def assert_follows(before: Motion, edited) -> None:
    """The world transforms the edit hands over are the result's forward kinematics."""
    positions, rotations = forward_kinematics(before)
    carried_positions, carried_rotations = edited.kinematics(positions, rotations, threads=None)
    fresh_positions, fresh_rotations = forward_kinematics(edited.motion)
    np.testing.assert_allclose(carried_positions, fresh_positions, rtol=0, atol=1e-9 * before.size)
    np.testing.assert_allclose(carried_rotations, fresh_rotations, rtol=0, atol=1e-9)
    assert edited.keeps_rotations(rotations) == (carried_rotations is rotations)  # handed on at no cost


@pytest.mark.parametrize("seed", range(5))
def test_trim_scale_up_axis_and_mirror_hand_over_the_results_kinematics(seed):
    rng = np.random.default_rng(seed)
    motion = sided_rig(rng)
    assert_follows(motion, trim_edit(motion, 2, 5))
    assert_follows(motion, resample_edit(motion, motion.frame_rate / 3))
    assert_follows(motion, scale_lengths_edit(motion, 0.01))
    assert_follows(motion, change_up_axis_edit(motion, "z", "y"))
    assert_follows(motion, change_up_axis_edit(motion, "y", "z"))
    edited, unmatched = mirror_edit(motion)
    assert unmatched == ()
    assert_follows(motion, edited)
    assert_follows(motion, split_edit(motion, 2))
    assert_follows(motion, shift_root_edit(motion, 2))


def test_a_mirrored_joint_is_where_its_partner_was_reflected(rng):
    motion = sided_rig(rng)
    edited, _ = mirror_edit(motion)
    left, right = motion.joint_index("LeftLeg"), motion.joint_index("RightLeg")
    before, after = forward_kinematics(motion)[0], forward_kinematics(edited.motion)[0]
    np.testing.assert_allclose(
        after[:, right], before[:, left] @ edited.turn.T + edited.shift, rtol=0, atol=1e-12 * motion.size
    )


def every_signed_permutation() -> list[np.ndarray]:
    """The 48 axis swaps and reflections of 3D."""
    turns = []
    for axes in itertools.permutations(range(3)):
        for signs in itertools.product((-1.0, 1.0), repeat=3):
            turn = np.zeros((3, 3))
            turn[np.arange(3), axes] = signs
            turns.append(turn)
    return turns


@pytest.mark.skipif(not engine.have_numba(), reason="numba is not installed")
def test_the_compiled_turn_gives_the_numpy_references_numbers(rng):
    vectors = rng.normal(size=(9, 6, 3))
    matrices = rng.normal(size=(9, 6, 3, 3))
    joints = np.array([5, 0, 0, 3])
    moved = {"scale": 0.3, "shift": rng.normal(size=(4, 3))}
    for turn in every_signed_permutation():
        for array, extra in ((vectors, moved), (vectors, {}), (matrices, {})):
            for rows in ((2, 7), None):
                reference = engine.turned_joints(array, joints, rows=rows, turn=turn, backend="numpy", **extra)
                compiled = engine.turned_joints(array, joints, rows=rows, turn=turn, backend="numba", **extra)
                np.testing.assert_array_equal(compiled, reference)


@pytest.mark.skipif(not engine.have_numba(), reason="numba is not installed")
def test_threads_turn_the_same_bits(rng):
    frames = 2 * engine.MIN_FRAMES_PER_THREAD + 3
    matrices = rng.normal(size=(frames, 2, 3, 3))
    turn = every_signed_permutation()[11]
    one = engine.turned_joints(matrices, [1, 0], turn=turn, threads=1)
    np.testing.assert_array_equal(engine.turned_joints(matrices, [1, 0], turn=turn, threads=2), one)


@pytest.mark.skipif(not engine.have_numba(), reason="numba is not installed")
def test_the_compiled_turn_of_a_real_files_swapped_sides_gives_the_numpy_references_numbers():
    motion = load_gmr(shared_path("cmu/subject01/01_01.bvh")).frame_slice(slice(0, 50))
    partners = mirror_pairs(motion).partner
    assert not np.array_equal(partners, np.arange(motion.n_joints))
    reflection = np.diag([-1.0, 1.0, 1.0])
    shift = np.where((motion.parents < 0)[:, None], [0.7, 0.0, 0.0], 0.0)
    for array, extra in ((motion.rotations, {}), (motion.translations, {"shift": shift})):
        for rows in (None, (10, 40)):
            reference = engine.turned_joints(array, partners, rows=rows, turn=reflection, backend="numpy", **extra)
            compiled = engine.turned_joints(array, partners, rows=rows, turn=reflection, backend="numba", **extra)
            np.testing.assert_array_equal(compiled, reference)


def edits_of(motion: Motion) -> dict[str, object]:
    """The app's edits that hand over the document's kinematics, by name."""
    foot = next(j for j, name in enumerate(motion.names) if "Foot" in name or "foot" in name)
    n = motion.n_frames
    return {
        "trim": lambda s: commands.trim_to_range(s, n // 4, 3 * n // 4),
        "resample": lambda s: commands.resample_to(s, 0.5 * rate_text_value(s)),
        "scale": lambda s: commands.scale_by(s, 0.01),
        "up axis": lambda s: commands.up_axis_to(s, "z"),
        "mirror": commands.mirror_left_right,
        "shift root": lambda s: commands.shift_root_to(s, foot),
    }


@pytest.fixture(params=["demo", "01_01"])
def document(request, qapp) -> StudioState:
    """A state holding the demo walk or the first 300 frames of CMU 01_01."""
    if request.param == "demo":
        motion = demo_motion()
    else:
        motion = load_gmr(shared_path("cmu/subject01/01_01.bvh")).frame_slice(slice(0, 300))
    state = StudioState()
    state.open_document(Snapshot.of(motion), None)
    return state


def rate_text_value(state: StudioState) -> float:
    """The document's rate as the app shows it (120 for CMU's printed 0.0083333 s)."""
    return float(rate_text(state.motion.frame_time))


@pytest.mark.parametrize("edit", ["trim", "resample", "scale", "up axis", "mirror", "shift root"])
def test_an_edits_cache_is_its_results_forward_kinematics(document, edit):
    before = document.snapshot
    assert edits_of(before.motion)[edit](document)
    after = document.snapshot
    fresh = Snapshot.of(after.motion)
    size = before.motion.size
    np.testing.assert_allclose(after.positions, fresh.positions, rtol=0, atol=1e-9 * size)
    np.testing.assert_allclose(after.rotations, fresh.rotations, rtol=0, atol=1e-9)
    assert not after.positions.flags.writeable and not after.rotations.flags.writeable
    document.undo_stack.undo()
    assert document.snapshot is before


def test_the_input_arrays_are_handed_on_when_nothing_changes_else_the_results_own(rng):
    motion = sided_rig(rng, n_frames=9)  # 9 frames of 6 joints
    positions, rotations = forward_kinematics(motion)
    n_frames, n_joints = positions.shape[:2]
    for world in ({}, {"rows": (0, n_frames)}, {"rows": (0, n_frames, 1)}, {"turn": np.eye(3)}, {"shift": np.zeros(3)}):
        edited = Edited.same_joints(motion, **world)
        carried = edited.kinematics(positions, rotations)
        assert carried[0] is positions and carried[1] is rotations and edited.keeps_rotations(rotations), world
    fewer = np.arange(n_joints - 1)
    shift = np.array([0.5, 0.0, -2.0])
    for edited, expected, kept in (
        (Edited.same_joints(motion, rows=(1, n_frames)), (positions[1:], rotations[1:]), False),
        (Edited.same_joints(motion, rows=(0, n_frames, 2)), (positions[::2], rotations[::2]), False),
        (Edited.same_joints(motion, shift=shift), (positions + shift, rotations), True),
        (Edited.same_joints(motion, scale=2.0), (2.0 * positions, rotations), True),
        (Edited(motion, fewer, fewer), (positions[:, :-1], rotations[:, :-1]), False),
    ):
        carried = edited.kinematics(positions, rotations)
        for got, want in zip(carried, expected, strict=True):
            assert got.shape == want.shape
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * motion.size)
        assert edited.keeps_rotations(rotations) is kept and (carried[1] is rotations) is kept
        # the result's own memory, not a view: the document before may be let go
        assert not np.shares_memory(carried[0], positions)
        assert kept or not np.shares_memory(carried[1], rotations)
