"""The state object and the edit commands, without any window.

Every edit is undoable and undo/redo restore positions and structure exactly (the very
same snapshot objects); refused edits change nothing and say why.
"""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.model import commands
from gmr_studio.app.model.state import UNDO_MEMORY_BUDGET, Snapshot, StudioState, history_bytes, undo_limit_for
from gmr_studio.core.demo import demo_markers, demo_motion
from gmr_studio.core.kinematics.fk import forward_kinematics, world_positions
from gmr_studio.core.markers.pelvis import PelvisFrames
from gmr_studio.core.rotations.euler import matrix_from_euler
from tests.conftest import random_motion

PARENTS = [-1, 0, 1, 2, 1, 4, 0, 6]


class Recorder:
    """Collects the signals a state emits, by name."""

    def __init__(self, state: StudioState) -> None:
        self.events: list[tuple] = []
        for name in (
            "document_changed",
            "motion_changed",
            "frame_changed",
            "selection_changed",
            "overlay_changed",
            "markers_changed",
            "pelvis_changed",
            "message",
            "modified_changed",
        ):
            getattr(state, name).connect(lambda *args, name=name: self.events.append((name, *args)))

    def names(self) -> list[str]:
        return [e[0] for e in self.events]


@pytest.fixture
def state(rng) -> StudioState:
    state = StudioState()
    state.open_document(Snapshot.of(random_motion(rng, PARENTS, n_frames=7)), "random.gmr")
    return state


def structure(motion):
    return (motion.parents.copy(), motion.soft_parents.copy(), motion.rotation_orders)


def test_snapshot_caches_forward_kinematics_for_all_frames(rng):
    motion = random_motion(rng, PARENTS, n_frames=5)
    snapshot = Snapshot.of(motion)
    np.testing.assert_array_equal(snapshot.positions, world_positions(motion))
    assert snapshot.positions.shape == (5, 8, 3) and snapshot.rotations.shape == (5, 8, 3, 3)
    assert not snapshot.positions.flags.writeable


EDITS = [
    ("shift_root", lambda s: commands.shift_root_to(s, 3)),
    ("split", lambda s: commands.split_here(s, 4)),
    ("split_all", commands.split_everything),
]


@pytest.mark.parametrize(("name", "edit"), EDITS, ids=[e[0] for e in EDITS])
def test_every_edit_undoes_and_redoes_exactly(state, name, edit):
    before = state.snapshot
    size = before.motion.size
    assert edit(state)
    after = state.snapshot
    assert after is not before and state.modified
    np.testing.assert_allclose(after.positions, before.positions, rtol=0, atol=1e-9 * size)
    state.undo_stack.undo()
    assert state.snapshot is before and not state.modified
    state.undo_stack.redo()
    assert state.snapshot is after
    state.undo_stack.undo()
    assert state.snapshot is before


def with_a_dummy(motion):
    """The motion with joint 1 (children 2 and 4) a zero-offset, channel-free joint."""
    offsets, translations = motion.offsets.copy(), motion.translations.copy()
    offsets[1], translations[:, 1] = 0.0, 0.0
    return motion.replace(offsets=offsets, translations=translations)


EVERY_EDIT = [
    ("shift_root_to", lambda s: commands.shift_root_to(s, 5)),
    ("split", lambda s: commands.split_here(s, 4)),
    ("join", lambda s: commands.split_here(s, 4) and commands.join_to_parent(s, 4)),
    ("split_all", commands.split_everything),
    ("join_all", lambda s: commands.split_everything(s) and commands.join_everything(s)),
    (
        "join_all_rerooted",
        lambda s: commands.split_here(s, 2) and commands.shift_root_to(s, 3) and commands.join_everything(s),
    ),
    ("remove_dummies", commands.remove_dummy_joints),
]


@pytest.mark.parametrize(("name", "edit"), EVERY_EDIT, ids=[e[0] for e in EVERY_EDIT])
def test_the_cache_after_every_edit_is_the_forward_kinematics_of_its_motion(rng, name, edit):
    state = StudioState()
    state.open_document(Snapshot.of(with_a_dummy(random_motion(rng, PARENTS, n_frames=7))), None)
    size = state.motion.size
    assert edit(state)
    positions, rotations = forward_kinematics(state.motion)
    np.testing.assert_allclose(state.positions, positions, rtol=0, atol=1e-12 * size)
    np.testing.assert_allclose(state.rotations, rotations, rtol=0, atol=1e-12)
    assert not state.positions.flags.writeable and not state.rotations.flags.writeable


def test_edits_that_keep_the_world_transforms_share_them_with_the_snapshot_before(state):
    opened = state.snapshot
    frames = opened.rotations  # a view shows joint frames: the document's world rotations are at hand
    held = history_bytes(state)
    assert commands.split_here(state, 4)
    assert state.positions is opened.positions and state.rotations is frames
    motion_bytes = state.motion.rotations.nbytes + state.motion.translations.nbytes
    assert history_bytes(state) == held + motion_bytes  # the new motion, nothing else
    assert commands.shift_root_to(state, 3)  # frames move along the path: new rotations, same positions
    assert state.positions is opened.positions and state.rotations is not frames
    shifted = state.snapshot
    shifted_frames = shifted.rotations
    assert commands.split_everything(state)  # the world transforms become the motion's data
    held = history_bytes(state)
    assert np.shares_memory(state.motion.rotations, shifted_frames)
    assert np.shares_memory(state.motion.translations, shifted.positions)
    state.undo_stack.undo()
    state.undo_stack.redo()
    assert history_bytes(state) == held


def test_only_the_document_shown_holds_its_world_rotations(state):
    opened = state.snapshot
    assert not opened.holds_rotations  # drawing the figure needs the positions only
    frames = opened.rotations  # a view shows joint frames: every frame's, computed once
    np.testing.assert_array_equal(frames, forward_kinematics(opened.motion)[1])
    assert opened.rotations is frames and not frames.flags.writeable
    with_rotations = history_bytes(state)
    assert commands.trim_to_range(state, 2, 6)  # new world rotations (a slice), computed when asked
    assert not opened.holds_rotations and not state.snapshot.holds_rotations  # in the history: let go
    assert history_bytes(state) == with_rotations - frames.nbytes + state.snapshot.nbytes
    state.undo_stack.undo()
    assert state.snapshot is opened
    np.testing.assert_array_equal(state.rotations, frames)  # asked again: the same numbers


def test_join_and_join_all_undo_exactly(state):
    commands.split_here(state, 2)
    commands.split_here(state, 6)
    split_twice = state.snapshot
    assert commands.join_to_parent(state, 6)
    assert state.snapshot.motion.soft_parents[6] == -1
    assert commands.join_everything(state)
    joined = state.snapshot
    assert len(joined.motion.roots) == 1
    np.testing.assert_allclose(joined.positions, split_twice.positions, atol=1e-9 * joined.motion.size)
    state.undo_stack.undo()
    state.undo_stack.undo()
    assert state.snapshot is split_twice
    assert [state.undo_stack.text(i) for i in range(state.undo_stack.count())] == [
        "Split at 'j2'",
        "Split at 'j6'",
        "Join 'j6' to its parent",
        "Join all",
    ]


def test_a_refused_edit_changes_nothing_and_says_why(state):
    recorder = Recorder(state)
    before = state.snapshot
    assert not commands.join_to_parent(state, 0)  # the last root
    assert state.snapshot is before and state.undo_stack.count() == 0 and not state.modified
    assert recorder.names() == ["message"]
    assert "last root" in recorder.events[0][1]
    assert not commands.split_here(state, 0)  # already a root
    assert "already a root" in recorder.events[-1][1]
    assert not commands.shift_root_to(state, 0)  # nothing to change
    assert state.undo_stack.count() == 0


def test_can_join_only_split_roots_with_a_soft_link(state):
    motion = state.motion
    assert not commands.can_join(motion, 0) and not commands.can_join(motion, 4) and not commands.can_join(motion, None)
    commands.split_here(state, 4)
    assert commands.can_join(state.motion, 4)


def test_selection_survives_edits_because_indices_do(state):
    state.select(5)
    commands.shift_root_to(state, 5)
    assert state.selected == 5
    state.undo_stack.undo()
    assert state.selected == 5
    state.select(99)
    assert state.selected is None


def test_frame_is_clamped_and_signals_only_on_change(state):
    recorder = Recorder(state)
    state.set_frame(3)
    state.set_frame(3)
    state.set_frame(100)
    state.step(-10)
    assert [e for e in recorder.events if e[0] == "frame_changed"] == [
        ("frame_changed", 3),
        ("frame_changed", 6),
        ("frame_changed", 0),
    ]


def test_overlays_switch_and_unknown_ones_are_refused(state):
    recorder = Recorder(state)
    state.set_overlay("axes", True)
    state.set_overlay("axes", True)
    assert recorder.events == [("overlay_changed", "axes", True)]
    with pytest.raises(KeyError):
        state.set_overlay("nonsense", True)


def test_opening_a_document_resets_history_selection_and_markers(state, rng):
    commands.split_here(state, 4)
    state.select(4)
    state.set_frame(3)
    state.open_document(Snapshot.of(random_motion(rng, PARENTS, n_frames=3)), None)
    assert state.undo_stack.count() == 0 and state.selected is None and state.frame == 0
    assert state.marker_overlay is None and not state.modified


def test_save_marks_clean_and_an_edit_after_it_modifies(state, tmp_path):
    commands.split_here(state, 4)
    assert state.modified
    state.mark_saved(tmp_path / "x.gmr")
    assert not state.modified and state.path.name == "x.gmr"
    state.undo_stack.undo()
    assert state.modified  # undoing past the save point is a change too


def test_markers_are_resampled_aligned_and_kept_through_edits():
    motion = demo_motion()
    state = StudioState()
    state.open_document(Snapshot.of(motion), None)
    markers = demo_markers(motion)
    state.set_markers(markers.resampled(60.0))  # a marker file at half the motion's rate
    overlay = state.marker_overlay
    assert overlay.positions.shape == (motion.n_frames, markers.n_markers, 3)
    joints = overlay.positions[:, : motion.n_joints]
    error = np.linalg.norm(joints - state.positions, axis=-1)
    assert np.nanmedian(error) < 0.3  # interpolated at 60 Hz, on the joints to a few mm
    gap = markers.labels.index("LWRA")
    assert np.isnan(overlay.positions[110, gap]).all()
    commands.split_here(state, 5)
    assert state.marker_overlay is overlay  # positions are invariant: markers stay put


def test_pelvis_frames_follow_the_marker_alignment():
    motion = demo_motion()
    state = StudioState()
    state.open_document(Snapshot.of(motion), None)
    markers = demo_markers(motion)
    state.set_markers(markers)
    n = markers.n_frames
    valid = np.ones(n, bool)
    valid[10] = False
    turn = matrix_from_euler(np.array([0.3, -0.2, 0.5]), "ZYX")  # a pelvis rotation in the marker file's axes
    pelvis = PelvisFrames(
        rotations=np.broadcast_to(turn, (n, 3, 3)).copy(),
        origins=np.where(valid[:, None], markers.positions[:, 0] / 1000, np.nan),  # in metres
        residuals=np.where(valid, 0.01, np.nan),
        valid=valid,
        units="m",
    )
    state.set_pelvis(pelvis)
    shown = state.pelvis
    np.testing.assert_allclose(shown.origins[0], state.positions[0, 0], atol=0.3)  # m -> mm -> cm
    assert np.isnan(shown.origins[10]).all() and np.isnan(shown.residuals[10])
    a = state.marker_overlay.alignment.transform.rotation
    np.testing.assert_allclose(shown.rotations[0], a @ turn @ a.T, atol=1e-12)  # the same turn, motion axes


@pytest.mark.parametrize("case", ["demo", "cmu"])
def test_recovered_pelvis_turns_with_the_root(case):
    """The pelvis frames recovered from markers (demo: markers named like joints; CMU: the
    shipped CMU map on the C3D) turn with the skeleton's root, to a degree or two."""
    from gmr_studio.app.model import pelvis_recovery
    from gmr_studio.core.formats import load_gmr
    from gmr_studio.core.markers import read_markers
    from gmr_studio.core.rotations.euler import rotation_angle
    from tests.conftest import shared_path

    if case == "demo":
        motion = demo_motion()
        markers = demo_markers(motion)
    else:
        motion = load_gmr(shared_path("cmu/subject01/01_01.amc"))
        markers = read_markers(shared_path("cmu/subject01/01_01.c3d"))
    state = StudioState()
    state.open_document(Snapshot.of(motion), None)
    state.set_markers(markers)
    assert pelvis_recovery.recover_pelvis_frames(state)
    pelvis = state.pelvis
    assert pelvis.source.valid.mean() > 0.99
    angle = np.degrees(rotation_angle(np.swapaxes(pelvis.rotations, 1, 2) @ state.rotations[:, 0]))
    assert np.nanmedian(angle) < 1.5 and np.nanpercentile(angle, 95) < 4
    distance = np.linalg.norm(pelvis.origins - state.positions[:, 0], axis=1)
    assert np.nanmedian(distance) < 0.02 * motion.size


def test_the_undo_history_of_a_long_take_fits_in_its_budget(rng):
    small = Snapshot.of(random_motion(rng, PARENTS, n_frames=3))
    assert undo_limit_for(small) == 100
    for frames in (30_000, 100_000, 400_000):  # 01_01 tiled, 38 joints (views: nothing allocated)
        motion = demo_motion()
        take = motion.replace(
            rotations=np.broadcast_to(np.eye(3), (frames, motion.n_joints, 3, 3)),
            translations=np.broadcast_to(motion.offsets, (frames, motion.n_joints, 3)),
        )
        shown = Snapshot(take, take.translations, take.rotations)  # with its world rotations
        limit = undo_limit_for(shown)
        assert limit >= 1
        # the document shown and `limit` edits that each hold a new motion and positions as big
        kept = shown.nbytes - take.rotations.nbytes
        assert shown.nbytes + limit * kept <= UNDO_MEMORY_BUDGET or limit == 1
        if frames == 100_000:
            assert limit >= 3
