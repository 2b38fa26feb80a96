"""A rotation block times constant matrices per joint equals numpy's own products frame by
frame, for any number of frames (chunked or not), joints, and matrices given once for all."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.rotations.blocks import CHUNK_FRAMES, sandwiched, turned_vectors


def rotations(rng, *shape: int) -> np.ndarray:
    count = int(np.prod(shape))
    return Rotation.random(count, random_state=rng.integers(1 << 31)).as_matrix().reshape(*shape, 3, 3)


@pytest.mark.parametrize("frames", [0, 1, CHUNK_FRAMES, 2 * CHUNK_FRAMES + 7])
@pytest.mark.parametrize("joints", [1, 5])
def test_a_change_of_frames_per_joint_is_the_products(frames, joints, rng):
    block = rotations(rng, frames, joints)
    left, right = rng.normal(size=(joints, 3, 3)), rng.normal(size=(joints, 3, 3))
    expected = left @ block @ right
    np.testing.assert_allclose(sandwiched(left, block, right), expected, rtol=0, atol=1e-14)
    vectors = rng.normal(size=(frames, joints, 3))
    np.testing.assert_allclose(turned_vectors(left, vectors), (left @ vectors[..., None])[..., 0], rtol=0, atol=1e-14)


def test_one_matrix_for_every_joint_turns_the_world(rng):
    block, turn = rotations(rng, 40, 3), rotations(rng, 1)[0]
    np.testing.assert_allclose(sandwiched(turn[None], block, turn.T[None]), turn @ block @ turn.T, rtol=0, atol=1e-15)


def test_written_over_its_input_when_asked(rng):
    block, left, right = rotations(rng, 2 * CHUNK_FRAMES + 3, 4), rotations(rng, 4), rotations(rng, 4)
    vectors = rng.normal(size=(len(block), 4, 3))
    expected, moved = left @ block @ right, (left @ vectors[..., None])[..., 0]
    out = sandwiched(left, block, right, overwrite=True)
    assert np.shares_memory(out, block)
    np.testing.assert_allclose(block, expected, rtol=0, atol=1e-14)
    assert turned_vectors(left, vectors, overwrite=True) is vectors
    np.testing.assert_allclose(vectors, moved, rtol=0, atol=1e-14)
    kept = block[:, ::2]  # not contiguous: a new array, the block kept
    assert not np.shares_memory(sandwiched(left[::2], kept, right[::2], overwrite=True), block)
