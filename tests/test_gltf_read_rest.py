"""The rest pose of a glTF skeleton and this project's pre-rotation exports
(core.formats.gltf_in.rest): inverse bind matrices of a scaled skin listed in its own
order, the bind orientations taken out with every joint position kept, the identity left
alone, pre-rotation translations static to float32 rounding or moving."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats.gltf_in import rest
from gmr_studio.core.formats.gltf_in.container import open_gltf
from gmr_studio.core.formats.gltf_in.rest import bind_rotations, pre_from_export, turn_to_bind
from tests.gltf_builder import GltfBuilder, post_rotation_forward


def _document(tmp_path, inverse_binds: np.ndarray | None, listed: list[int]):
    builder = GltfBuilder()
    for n in range(5):
        builder.node(name=f"n{n}")
    skin = {"joints": listed}
    if inverse_binds is not None:
        skin["inverseBindMatrices"] = builder.accessor(np.array([m.T.ravel() for m in inverse_binds]))
    builder.doc["skins"] = [skin]
    path = builder.save(tmp_path / "bind.glb")
    return open_gltf(path, path.read_bytes())


def test_bind_rotations_are_the_rotations_of_the_inverse_bind_matrices_inverted(tmp_path):
    """Joints 1..4 of the motion; the skin lists nodes 4, 1, 2 (3 is between two joints,
    without a matrix: the identity). Each bind transform is T R S with a scale of 2."""
    turns = Rotation.from_rotvec([[0.3, 0, 0], [0, 0.5, 0.2], [0.1, -0.7, 0.4]]).as_matrix()
    inverses = []
    for k, turn in enumerate(turns):
        world = np.eye(4)
        world[:3, :3] = turn * 2.0
        world[:3, 3] = [k, 1.0, -2.0]
        inverses.append(np.linalg.inv(world))
    doc = _document(tmp_path, np.array(inverses), [4, 1, 2])
    bind, count = bind_rotations(doc, 0, [1, 2, 3, 4])
    assert count == 3
    np.testing.assert_allclose(bind, [turns[1], turns[2], np.eye(3), turns[0]], rtol=0, atol=1e-7)  # float32
    only, count = bind_rotations(doc, 0, [2, 3])  # a listed node that is no joint here is left out
    assert count == 1
    np.testing.assert_allclose(only, [turns[2], np.eye(3)], rtol=0, atol=1e-7)


def test_no_skin_or_no_matrices_bind_at_the_identity_and_a_short_list_is_refused(tmp_path):
    for skin, doc in ((None, _document(tmp_path, None, [1])), (0, _document(tmp_path, None, [1, 2]))):
        bind, count = bind_rotations(doc, skin, [1, 2])
        assert count == 0 and bind.shape == (2, 3, 3)
        np.testing.assert_array_equal(bind, np.broadcast_to(np.eye(3), (2, 3, 3)))
    doc = _document(tmp_path, np.broadcast_to(np.eye(4), (2, 4, 4)), [1, 2, 3])
    with pytest.raises(MotionFileError, match="skin 0: 3 joints need as many MAT4 inverse bind matrices"):
        bind_rotations(doc, 0, [1, 2, 3])


def test_taking_the_bind_out_keeps_every_position_and_turns_each_frame_by_its_bind():
    rng = np.random.default_rng(3)
    frames, parents = 4, np.array([-1, 0, 1, 0])
    bind = Rotation.random(4, random_state=5).as_matrix()
    rotations = Rotation.random(frames * 4, random_state=6).as_matrix().reshape(frames, 4, 3, 3)
    offsets = rng.normal(size=(4, 3))
    moving = np.array([True, False, True, False])
    translations = np.where(moving[:, None], rng.normal(size=(frames, 4, 3)), offsets)
    turned, moved, placed = turn_to_bind(bind, parents, rotations, translations, offsets, moving)
    worlds, positions = post_rotation_forward(parents, rotations, translations)
    new_worlds, new_positions = post_rotation_forward(parents, turned, moved)
    np.testing.assert_allclose(new_positions, positions, rtol=0, atol=1e-12)
    np.testing.assert_allclose(new_worlds, worlds @ np.swapaxes(bind, -1, -2), rtol=0, atol=1e-12)
    np.testing.assert_array_equal(moved[:, ~moving], np.broadcast_to(placed[~moving], (frames, 2, 3)))
    np.testing.assert_allclose(placed[1], bind[0] @ offsets[1], rtol=0, atol=1e-15)  # in its parent's rest frame


def test_a_bind_at_the_identity_to_its_tolerance_changes_nothing():
    parents = np.array([-1, 0])
    rotations = Rotation.from_rotvec([[[0.1, 0, 0], [0, 0.2, 0]]]).as_matrix()
    translations, offsets, moving = np.ones((1, 2, 3)), np.ones((2, 3)), np.array([True, False])
    bind = np.broadcast_to(np.eye(3), (2, 3, 3)).copy()
    bind[1, 0, 1] = 1e-12
    out = turn_to_bind(bind, parents, rotations, translations, offsets, moving)
    assert out[0] is rotations and out[1] is translations and out[2] is offsets
    bind[1, 0, 1] = 2e-12
    assert turn_to_bind(bind, parents, rotations, translations, offsets, moving)[0] is not rotations
    empty = (np.zeros((0, 3, 3)), np.zeros(0, np.int64), np.zeros((1, 0, 3, 3)), np.zeros((1, 0, 3)), np.zeros((0, 3)))
    out = turn_to_bind(*empty, np.zeros(0, bool))
    assert out[0] is empty[2] and out[1] is empty[3] and out[2] is empty[4]


def _export(rotations, pre_translations):
    """What this project writes for a pre-rotation joint: ``R t`` (roots: ``t``)."""
    written = (rotations @ pre_translations[..., None])[..., 0]
    written[:, 0] = pre_translations[:, 0]
    return written


def test_pre_rotation_exports_read_back_static_to_float32_and_moving_beyond():
    frames, parents = 5, np.array([-1, 0, 1, 1])
    rotations = Rotation.random(frames * 4, random_state=2).as_matrix().reshape(frames, 4, 3, 3)
    pre = np.empty((frames, 4, 3))
    pre[:, 0] = np.linspace(0, 1, frames)[:, None] * [1.0, 0.0, 2.0]  # the root moves
    pre[:, 1] = [0.0, 0.5, 0.0]
    pre[:, 2] = [0.3, 0.1, 0.0] * (1 + 1e-7 * np.arange(frames))[:, None]  # float32 rounding
    pre[:, 3] = [0.2, 0, 0] + 1e-5 * np.arange(frames)[:, None]  # moves, if little
    written = _export(rotations, pre)
    offsets = written[0].copy()  # as the reader had them, post-rotation
    local, placed, moving = pre_from_export(rotations, written, offsets, parents, np.array([True, False, True, True]))
    assert moving.tolist() == [True, False, False, True]
    np.testing.assert_allclose(local, pre, rtol=0, atol=1e-6)
    np.testing.assert_allclose(local[:, [0, 3]], pre[:, [0, 3]], rtol=0, atol=1e-14)
    np.testing.assert_allclose(placed[2], pre[:, 2].mean(axis=0), rtol=0, atol=1e-15)  # the mean of the rounding
    np.testing.assert_array_equal(local[:, [1, 2]], np.broadcast_to(placed[[1, 2]], (frames, 2, 3)))
    np.testing.assert_allclose(placed[3], pre[0, 3], rtol=0, atol=1e-15)  # a moving joint: its first frame
    np.testing.assert_array_equal(placed[0], offsets[0])  # a root's offset stays


def test_a_root_keeps_its_moving_flag_and_a_tiny_child_translation_is_no_rounding():
    rotations = np.broadcast_to(np.eye(3), (2, 2, 3, 3))
    written = np.array([[[0.0, 0, 0], [1e-9, 0, 0]], [[0.0, 0, 0], [1.1e-9, 0, 0]]])
    moving = pre_from_export(rotations, written, written[0].copy(), np.array([-1, 0]), np.zeros(2, bool))[2]
    assert moving.tolist() == [False, True]  # 10% of its size: not float32 rounding however small
    zero = np.zeros((2, 2, 3))
    moving = pre_from_export(rotations, zero, zero[0].copy(), np.array([-1, 0]), np.ones(2, bool))[2]
    assert moving.tolist() == [True, False]  # a child held at its parent: static


def test_a_spread_of_exactly_the_static_tolerance_is_static(monkeypatch):
    monkeypatch.setattr(rest, "STATIC_FLOAT32", 0.25)  # spread 1 of 4: exactly
    rotations = np.broadcast_to(np.eye(3), (2, 2, 3, 3))
    written = np.array([[[0.0, 0, 0], [2.0, 0, 0]], [[0.0, 0, 0], [4.0, 0, 0]]])
    _, placed, moving = pre_from_export(rotations, written, written[0].copy(), np.array([-1, 0]), np.zeros(2, bool))
    assert moving.tolist() == [False, False] and placed[1].tolist() == [3.0, 0, 0]
