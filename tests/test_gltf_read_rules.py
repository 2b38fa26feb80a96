"""The glTF reader's own rules (core.formats.gltf_in.reader): channels left out and why, each
refusal of an animation's channels and samplers, node names made joint names, the notes on
units, bind pose, armature and scale, this project's pre-rotation exports, the sample limit."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats.gltf_in import reader
from gmr_studio.core.formats.gltf_in.reader import read_gltf
from tests.gltf_builder import GltfBuilder, glb_bytes, quaternion

TURNS = [quaternion([0, 0, 1], a) for a in (0, 90)]


def two_nodes(**root) -> GltfBuilder:
    builder = GltfBuilder()
    builder.node(name="root", children=[1], **root)
    builder.node(name="tip", translation=[1, 0, 0])
    return builder


def read(builder: GltfBuilder, tmp_path, **options):
    return read_gltf(builder.save(tmp_path / "r.glb"), **options)


def message(builder: GltfBuilder, tmp_path, **options) -> str:
    with pytest.raises(MotionFileError) as caught:
        read(builder, tmp_path, **options)
    return caught.value.message


# ------------------------------------------------------------------------ channels
def test_channels_outside_the_skeleton_or_of_other_paths_are_left_out_with_a_note(tmp_path):
    builder = two_nodes()
    builder.node(name="mesh")
    builder.doc["skins"] = [{"joints": [0, 1]}]
    builder.animation(
        [
            (0, "rotation", [0.0, 1.0], TURNS, "LINEAR"),
            (2, "translation", [0.0, 1.0], [[0, 0, 0], [1, 0, 0]], "LINEAR"),
            (2, "rotation", [0.0, 1.0], TURNS, "LINEAR"),
        ]
    )
    channels = builder.doc["animations"][0]["channels"]
    channels.append({"sampler": 0, "target": {"node": 0, "path": "weights"}})
    channels.append({"sampler": 0, "target": {"path": "rotation"}})  # no node: an extension's target
    channels.append({"sampler": 0, "target": {"node": 1}})
    motion = read(builder, tmp_path)
    assert "2 channels of nodes outside the skeleton (meshes, cameras) left out" in motion.comments
    assert "channels of None, weights (not a joint's transform) left out" in motion.comments
    assert motion.n_frames == 2 and not motion.has_translation.any()


def test_an_animation_of_the_skeleton_only_has_no_notes_on_channels(tmp_path):
    builder = two_nodes()
    builder.animation([(0, "rotation", [0.0, 1.0], TURNS, "LINEAR")])
    assert not any("left out" in c for c in read(builder, tmp_path).comments)


def _animation_edit(change):
    builder = two_nodes()
    builder.animation([(0, "rotation", [0.0, 1.0], TURNS, "LINEAR")])
    change(builder.doc["animations"][0], builder)
    return builder


@pytest.mark.parametrize(
    ("change", "expected"),
    [
        (lambda a, b: a.update(channels={}), "animation 0: 'channels' and 'samplers' must be arrays"),
        (lambda a, b: a.update(samplers=None), "animation 0: 'channels' and 'samplers' must be arrays"),
        (lambda a, b: a["channels"].append(3), "animation 0 channel 1: needs a 'target'"),
        (lambda a, b: a["channels"][0].pop("target"), "animation 0 channel 0: needs a 'target'"),
        (
            lambda a, b: a["channels"][0].update(sampler=True),
            "animation 0 channel 0: sampler True out of range (the animation has 1)",
        ),
        (
            lambda a, b: a["channels"][0].update(sampler=-1),
            "animation 0 channel 0: sampler -1 out of range (the animation has 1)",
        ),
        (
            lambda a, b: a["channels"][0].update(sampler=1),
            "animation 0 channel 0: sampler 1 out of range (the animation has 1)",
        ),
        (
            lambda a, b: a["channels"][0].update(sampler="0"),
            "animation 0 channel 0: sampler '0' out of range (the animation has 1)",
        ),
        (lambda a, b: a["samplers"].__setitem__(0, 7), "animation 0 channel 0 sampler 0: must be an object"),
        (
            lambda a, b: a["samplers"][0].update(interpolation="CUBIC"),
            "animation 0 channel 0 sampler 0: interpolation 'CUBIC' is not one of LINEAR, STEP, CUBICSPLINE",
        ),
        (
            lambda a, b: a["samplers"][0].update(interpolation="CUBICSPLINE"),
            "animation 0 channel 0 sampler 0: 2 CUBICSPLINE keys need 6 outputs of 4 components, not 2 of 4",
        ),
        (
            lambda a, b: a["samplers"][0].update(output=b.accessor(np.array([TURNS[0], [0, 0, 0, 9e-4]]))),
            "animation 0 channel 0 sampler 0: rotation key 1 is not a quaternion (length 0.0009)",
        ),
    ],
)
def test_bad_channels_and_samplers_are_refused(tmp_path, change, expected):
    assert message(_animation_edit(change), tmp_path) == expected


def test_keys_may_repeat_a_time_and_a_quaternion_of_the_least_length_is_one(tmp_path):
    builder = two_nodes()
    short = [0.0, 0.0, 0.0, 1e-3 * 1.0001]  # just above the least length, as float32 stores it
    builder.animation([(0, "rotation", [0.0, 1.0, 1.0, 2.0], [TURNS[0], TURNS[1], TURNS[1], short], "LINEAR")])
    motion = read(builder, tmp_path)
    assert motion.n_frames == 3  # keys every second, the repeated one a frame of its own time
    np.testing.assert_allclose(motion.rotations[2, 0], np.eye(3), atol=1e-7)  # normalised: no turn


def test_a_quaternion_exactly_the_least_length_is_one(tmp_path, monkeypatch):
    monkeypatch.setattr(reader, "MIN_QUATERNION_LENGTH", 0.5)  # binary: the length is exact
    builder = two_nodes()
    builder.animation([(0, "rotation", [0.0, 1.0], [TURNS[0], [0.0, 0.0, 0.0, 0.5]], "LINEAR")])
    assert read(builder, tmp_path).n_frames == 2
    monkeypatch.setattr(reader, "MIN_QUATERNION_LENGTH", 0.5000001)
    assert message(builder, tmp_path).endswith("rotation key 1 is not a quaternion (length 0.5)")


def test_two_keys_in_decreasing_time_are_refused(tmp_path):
    builder = two_nodes()
    builder.animation([(0, "rotation", [1.0, 0.0], TURNS, "LINEAR")])
    assert message(builder, tmp_path) == "animation 0 channel 0 sampler 0: key times must not decrease (key 1)"
    later = two_nodes()  # the key that goes back is named, not the repeat before it
    later.animation([(0, "rotation", [0.0, 1.0, 1.0, 0.5], TURNS * 2, "LINEAR")])
    assert message(later, tmp_path) == "animation 0 channel 0 sampler 0: key times must not decrease (key 3)"


def test_cubicspline_rotation_keys_are_checked_on_their_values_not_tangents(tmp_path):
    builder = two_nodes()
    zero = [0.0, 0.0, 0.0, 0.0]
    values = [zero, TURNS[0], zero, zero, TURNS[1], zero]  # in-tangent, value, out-tangent per key
    builder.animation([(0, "rotation", [0.0, 1.0], values, "CUBICSPLINE")])
    np.testing.assert_allclose(read(builder, tmp_path).rotations[1, 0], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-7)
    bad = two_nodes()
    bad.animation(
        [(0, "rotation", [0.0, 1.0], [TURNS[0], zero, TURNS[0], TURNS[1], TURNS[1], TURNS[1]], "CUBICSPLINE")]
    )
    assert "rotation key 0 is not a quaternion (length 0)" in message(bad, tmp_path)


# ------------------------------------------------------------------------ names
def test_node_names_made_joint_names_and_counted(tmp_path):
    builder = GltfBuilder()
    names = ["left  arm\t", "a{b}", "\x01x", None, "hips", "hips", 7]
    for k, name in enumerate(names):
        fields = {"name": name} if name is not None else {}
        builder.node(children=[k + 1] if k + 1 < len(names) else [], **fields)
    motion = read(builder, tmp_path)
    assert motion.names == ("left arm", "a_b_", "_x", "node3", "hips", "hips_5", "node6")
    assert "6 node names made valid joint names (unnamed: node<index>)" in motion.comments
    plain = GltfBuilder()
    plain.node(name="only")
    assert not any("node names" in c for c in read(plain, tmp_path).comments)


# ------------------------------------------------------------------------ notes
def _with_asset(builder: GltfBuilder, tmp_path, **asset):
    builder.save(tmp_path / "a.glb")
    doc = json.loads(json.dumps(builder.doc))
    doc["asset"].update(asset)
    doc["buffers"] = [{"byteLength": len(builder.blob)}]
    (tmp_path / "a.glb").write_bytes(glb_bytes(doc, bytes(builder.blob)))
    return read_gltf(tmp_path / "a.glb")


@pytest.mark.parametrize(
    ("factor", "metres"),
    [(0.01, 0.01), (1, None), (0, None), (-0.01, None), (True, None), ("0.01", None), (float("inf"), None)],
)
def test_source_units_only_from_a_positive_finite_number(tmp_path, factor, metres):
    """The unit a glTF written by this project came from (its extras' metres per unit):
    a positive finite number other than a metre; anything else is no source unit."""
    source = _with_asset(two_nodes(), tmp_path, extras={"metres_per_unit": factor}).facts.source_unit
    assert (None if source is None else source.metres) == metres


def test_a_pre_rotation_export_by_this_project_is_read_as_one(tmp_path):
    builder = two_nodes()
    builder.doc["nodes"][1]["rotation"] = list(quaternion([0, 0, 1], 90))  # written [R, R t]
    ours = _with_asset(builder, tmp_path, generator="GMR Studio 0.1", extras={"convention": "pre"})
    assert ours.convention == "pre"
    assert "written by GMR Studio from a pre-rotation (GMR) motion: read as one" in ours.comments
    np.testing.assert_allclose(ours.offsets[1], [0, -1, 0], atol=1e-12)  # R^T t: the offset before the turn
    other = _with_asset(builder, tmp_path, generator="other tool", extras={"convention": "pre"})
    assert other.convention == "post" and not any("pre-rotation" in c for c in other.comments)
    assert _with_asset(builder, tmp_path, generator="GMR Studio", extras=["pre"]).convention == "post"


def test_the_bind_note_counts_the_joints_turned(tmp_path):
    builder = two_nodes()
    turn = np.eye(4)
    turn[:3, :3] = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]])  # 90 degrees about z
    inverse = np.linalg.inv(turn)
    builder.doc["skins"] = [
        {"joints": [0, 1], "inverseBindMatrices": builder.accessor(np.array([np.eye(4).ravel(), inverse.T.ravel()]))}
    ]
    motion = read(builder, tmp_path)
    expected = (
        "rest pose: the skin's bind pose; the rest orientation of its joints (up to 90 deg, 1 joints) "
        "taken out of their frames"
    )
    assert expected in motion.comments
    three = GltfBuilder()
    for k in range(3):
        three.node(name=f"j{k}", children=[k + 1] if k < 2 else [])
    half_degree = np.eye(4)
    half_degree[:3, :3] = Rotation.from_rotvec([0, 0, np.radians(0.5)]).as_matrix()
    for inverses, count, angle in (
        ([np.eye(4), half_degree, turn], 2, 90),
        ([np.eye(4), half_degree, np.eye(4)], 1, 0.5),
    ):
        binds = np.array([np.linalg.inv(m).T.ravel() for m in inverses])
        three.doc["skins"] = [{"joints": [0, 1, 2], "inverseBindMatrices": three.accessor(binds)}]
        note = next(c for c in read(three, tmp_path).comments if c.startswith("rest pose"))
        assert f"(up to {angle} deg, {count} joints)" in note
    still = two_nodes()
    still.doc["skins"] = [{"joints": [0, 1], "inverseBindMatrices": still.accessor(np.array([np.eye(4).ravel()] * 2))}]
    assert not any(c.startswith("rest pose") for c in read(still, tmp_path).comments)


def test_armature_notes_name_unnamed_nodes_by_index(tmp_path):
    builder = GltfBuilder()
    builder.node(children=[1], translation=[0, 1, 0], name="")
    builder.node(children=[2])
    builder.node(translation=[0, 1, 0])
    builder.doc["skins"] = [{"joints": [1, 2]}]
    motion = read(builder, tmp_path)
    assert "armature: the transform of node 0 above the skeleton applied to its roots (node 1)" in motion.comments


def test_scale_notes_mirrored_folded_animated_and_float32_ones(tmp_path):
    builder = GltfBuilder()
    builder.node(name="mirror", scale=[-1, 1, 1], children=[1])
    builder.node(name="folded", scale=[2, 2, 2], children=[2])
    builder.node(name="grows", children=[3])
    builder.node(name="rounded", scale=[1 + 5e-6] * 3, children=[4])
    builder.node(name="flat", scale=[1, 1 + 2e-5, 1], children=[5])
    builder.node(name="gone", scale=[0, 0, 0])
    builder.animation([(2, "scale", [0.0, 1.0], [[1, 1, 1], [3, 3, 3]], "LINEAR")])
    comments = read(builder, tmp_path).comments
    assert "uniform scale folded into the offsets: 'folded' (2)" in comments
    assert "animated uniform scale folded into per-frame translations: 'grows' (1 to 3)" in comments
    warning = next(c for c in comments if c.startswith("WARNING"))
    assert "on 'mirror' (axes up to 1:1, mirrored), 'flat' (axes up to 1.00002:1), 'gone' (axes up to 0:1):" in warning
    assert "rounded" not in " ".join(comments)


def test_a_joint_whose_channel_holds_one_value_takes_it_as_its_offset(tmp_path):
    builder = two_nodes()
    builder.animation(
        [(1, "translation", [0.0, 1.0], [[0, 2, 0], [0, 2, 0]], "LINEAR"), (0, "rotation", [0.0, 1.0], TURNS, "LINEAR")]
    )
    motion = read(builder, tmp_path)
    assert not motion.has_translation[1]
    np.testing.assert_array_equal(motion.offsets[1], [0, 2, 0])


def test_the_sample_limit_counts_frames_times_joints(tmp_path, monkeypatch):
    builder = two_nodes()
    builder.animation([(0, "rotation", [0.0, 1.0, 2.0], [TURNS[0], TURNS[1], TURNS[0]], "LINEAR")])
    monkeypatch.setattr(reader, "MAX_SAMPLES", 6)
    assert read(builder, tmp_path).n_frames == 3
    monkeypatch.setattr(reader, "MAX_SAMPLES", 5)
    assert message(builder, tmp_path) == "3 frames of 2 joints is more than this reader holds: use --frame-rate"


def test_bytes_in_hand_are_read_instead_of_the_file(tmp_path):
    data = two_nodes().save(tmp_path / "r.glb").read_bytes()
    assert read_gltf(tmp_path / "gone.glb", data=data).names == ("root", "tip")


def test_options_are_keywords(tmp_path):
    path = two_nodes().save(tmp_path / "r.glb")
    with pytest.raises(TypeError):
        read_gltf(path, 0)  # type: ignore[misc]


def test_scale_notes_read_the_first_frame_and_the_first_axis(tmp_path):
    """Scales equal across axes to 1e-5 (uniform for the notes) but not to the bit: the
    notes read axis x at the first frame, and the spread of x over the frames against 1e-5
    of it; a shrunk uneven scale is named too."""
    builder = GltfBuilder()
    builder.node(name="folded", scale=[2, 2.00001, 2.00001])
    for name in ("drift", "grows", "xonly", "nearly"):
        builder.node(name=name)
    builder.node(name="small", scale=[0.5, 0.25, 0.5])
    scales = {
        1: [[2, 2, 2], [2.00001] * 3],  # a spread of 1e-5 is 5e-6 of 2: still
        2: [[1, 1.000008, 1.000008], [3, 3.00002, 3.00002]],
        3: [[1, 1.000005, 1.000005], [1.000012, 1.000007, 1.000007]],  # x spreads 1.2e-5, y and z 2e-6
        4: [[1.000005, 1.000012, 1.000012], [1.000012] * 3],  # x within 1e-5 of 1 at the first frame
    }
    builder.animation([(node, "scale", [0.0, 1.0], value, "LINEAR") for node, value in scales.items()])
    comments = read(builder, tmp_path).comments
    assert "uniform scale folded into the offsets: 'folded' (2), 'drift' (2)" in comments
    assert (
        "animated uniform scale folded into per-frame translations: 'grows' (1 to 3), 'xonly' (1 to 1.00001)"
        in comments
    )
    warning = next(c for c in comments if c.startswith("WARNING"))
    assert "on 'small' (axes up to 2:1): joint" in warning


def test_scale_notes_at_their_tolerance(tmp_path, monkeypatch):
    """With a tolerance of 0.5 (binary, exact): axes 2:3 are uniform enough (ratio 1.5),
    a scale of 1.5 is one, a spread of 1 over a scale of 2 is still; just beyond, notes."""
    monkeypatch.setattr(reader, "SCALE_NOTE_TOLERANCE", 0.5)
    builder = GltfBuilder()
    builder.node(name="ratio", scale=[2, 3, 2], children=[1])
    builder.node(name="near", scale=[1.5, 1.5, 1.5], children=[2])
    builder.node(name="spread")
    builder.animation([(2, "scale", [0.0, 1.0], [[2, 2, 2], [3, 3, 3]], "LINEAR")])
    comments = read(builder, tmp_path).comments
    assert "uniform scale folded into the offsets: 'ratio' (2), 'spread' (2)" in comments
    assert not any("WARNING" in c or "animated" in c for c in comments)
