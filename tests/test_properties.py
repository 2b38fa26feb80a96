"""Property tests: random forests, random rotations, random sequences of operations."""

from __future__ import annotations

import os

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gmr_studio.core.edits.operations import join, join_all, shift_root, split, split_all
from gmr_studio.core.formats.gmr import gmr_text, read_gmr
from gmr_studio.core.kinematics.fk import forward_kinematics, world_positions
from tests.conftest import random_motion

#: more examples on demand: GMR_HYPOTHESIS_EXAMPLES=1000 pytest tests/test_properties.py
EXAMPLES = int(os.environ.get("GMR_HYPOTHESIS_EXAMPLES", "60"))
SETTINGS = settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@st.composite
def motions(draw, max_joints=60):
    n = draw(st.integers(1, max_joints))
    # each joint picks a parent among the earlier ones; a random share start new trees
    branching = draw(st.floats(0.0, 1.0))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    parents = [-1]
    for j in range(1, n):
        if rng.random() < 0.05:
            parents.append(-1)
        elif rng.random() < branching:
            parents.append(int(rng.integers(0, j)))
        else:
            parents.append(j - 1)
    moving = tuple(int(j) for j in rng.choice(n, size=min(n, 3), replace=False))
    return random_motion(rng, parents, n_frames=draw(st.integers(1, 4)), translation_joints=moving)


@st.composite
def edits(draw, motion):
    """A random sequence of valid operations, applied; returns the final motion."""
    steps = draw(st.integers(1, 12))
    for _ in range(steps):
        kind = draw(st.sampled_from(["shift", "split", "join", "split", "join_all", "split_all"]))
        if kind == "shift":
            motion = shift_root(motion, draw(st.integers(0, motion.n_joints - 1)))
        elif kind == "split":
            candidates = np.flatnonzero(motion.parents >= 0)
            if candidates.size:
                motion = split(motion, int(draw(st.sampled_from(list(candidates)))))
        elif kind == "join":
            candidates = np.flatnonzero((motion.parents < 0) & (motion.soft_parents >= 0))
            if candidates.size and len(motion.roots) > 1:
                motion = join(motion, int(draw(st.sampled_from(list(candidates)))))
        elif kind == "join_all" and draw(st.booleans()):
            motion = join_all(motion)
        elif kind == "split_all" and draw(st.integers(0, 5)) == 0:
            motion = split_all(motion)
    return motion


def tree_edges(motion):
    return {frozenset((j, int(p))) for j, p in enumerate(motion.parents) if p >= 0} | {
        frozenset((j, int(s))) for j, s in enumerate(motion.soft_parents) if s >= 0
    }


@SETTINGS
@given(data=st.data())
def test_random_edit_sequences_keep_every_position(data):
    motion = data.draw(motions())
    edited = data.draw(edits(motion))
    error = np.abs(world_positions(edited) - world_positions(motion)).max()
    assert error <= 1e-9 * motion.size
    edited.check_invariants()
    assert tree_edges(edited) == tree_edges(motion)  # trees + soft links are the original forest
    restored = join_all(edited)
    hard = {frozenset((j, int(p))) for j, p in enumerate(restored.parents) if p >= 0}
    original = {frozenset((j, int(p))) for j, p in enumerate(motion.parents) if p >= 0}
    assert hard == original and (restored.soft_parents < 0).all()
    assert np.abs(world_positions(restored) - world_positions(motion)).max() <= 1e-9 * motion.size


@SETTINGS
@given(data=st.data())
def test_split_then_join_is_the_identity(data):
    motion = data.draw(motions())
    candidates = np.flatnonzero(motion.parents >= 0)
    if not candidates.size:
        return
    j = int(data.draw(st.sampled_from(list(candidates))))
    joined = join(split(motion, j), j)
    assert list(joined.parents) == list(motion.parents)
    assert joined.has_translation[j] == motion.has_translation[j] or motion.has_translation[j]
    np.testing.assert_allclose(joined.rotations, motion.rotations, atol=1e-9)
    np.testing.assert_allclose(joined.translations, motion.translations, atol=1e-9 * motion.size)
    _, world = forward_kinematics(motion)
    np.testing.assert_allclose(forward_kinematics(joined)[1], world, atol=1e-9)


@SETTINGS
@given(data=st.data())
def test_gmr_file_round_trip_after_random_edits(data):
    motion = data.draw(edits(data.draw(motions(max_joints=25))))
    again = read_gmr("random.gmr", gmr_text(motion).encode())
    index = [again.names.index(n) for n in motion.names]
    assert [again.names[p] if p >= 0 else None for p in again.parents[index]] == [
        motion.names[p] if p >= 0 else None for p in motion.parents
    ]
    assert [again.names[s] if s >= 0 else None for s in again.soft_parents[index]] == [
        motion.names[s] if s >= 0 else None for s in motion.soft_parents
    ]
    error = np.abs(world_positions(again)[:, index] - world_positions(motion)).max()
    assert error <= 1e-9 * motion.size
