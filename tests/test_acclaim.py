"""ASF/AMC -> GMR: against an independent per-frame Acclaim FK, against CMU's BVH of the
same trial, and the reader's handling of the format's variants."""

from __future__ import annotations

import re

import numpy as np
import pytest

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.formats import load_gmr, read_motion
from gmr_studio.core.formats.acclaim import asf_beside, read_amc, read_asf, skeleton_motion
from gmr_studio.core.formats.amc import parse_amc_frames, read_amc_with_channels
from gmr_studio.core.formats.amc_bulk import bulk_frames
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.kinematics.engine import have_numba
from gmr_studio.core.kinematics.fk import world_positions
from tests.conftest import shared_files, shared_path

# ------------------------------------------------------------------ independent Acclaim FK


def elementary(axis: str, angle: float) -> np.ndarray:
    """4x4 rotation about one axis (right-handed, column vectors)."""
    c, s = np.cos(angle), np.sin(angle)
    i, j = {"x": (1, 2), "y": (2, 0), "z": (0, 1)}[axis.lower()]
    out = np.eye(4)
    out[i, i], out[i, j], out[j, i], out[j, j] = c, -s, s, c
    return out


def translation(vector) -> np.ndarray:
    out = np.eye(4)
    out[:3, 3] = vector
    return out


def fixed_axes(angles_by_axis: dict[str, float], sequence: list[str]) -> np.ndarray:
    """Rotations applied one after the other about fixed axes, in ``sequence``."""
    out = np.eye(4)
    for axis in sequence:
        out = elementary(axis, angles_by_axis.get(axis.lower(), 0.0)) @ out
    return out


def simple_amc_frames(text: str) -> list[dict[str, list[float]]]:
    """AMC frames as dicts, parsed line by line (the slow, obvious way)."""
    frames: list[dict[str, list[float]]] = []
    for line in text.replace("\r\n", "\n").split("\n"):
        words = line.split("#")[0].split()
        if not words or words[0].startswith(":"):
            continue
        if words[0].isdigit() and len(words) == 1:
            frames.append({})
        else:
            frames[-1][words[0]] = [float(w) for w in words[1:]]
    return frames


def acclaim_fk(skeleton, frames, degrees: bool = True) -> np.ndarray:
    """(F, 1 + B, 3): the root's position and each bone's end, frame by frame, the way an
    Acclaim viewer draws it: each bone's local frame is its parent's frame, moved to the
    parent's end, turned by ``C_parent^-1 C_bone`` and then by the AMC rotation."""
    unit = np.pi / 180 if degrees else 1.0
    bones = {b.name: b for b in skeleton.bones}
    children: dict[str, list[str]] = {"root": []}
    for b in skeleton.bones:
        children.setdefault(b.name, [])
        children["root" if b.parent < 0 else skeleton.bones[b.parent].name].append(b.name)

    def axis_matrix(angles, order) -> np.ndarray:
        return fixed_axes(dict(zip("xyz", angles)), list(order.lower()))

    out = np.zeros((len(frames), 1 + len(bones), 3))
    names = ["root", *skeleton.names]
    for f, frame in enumerate(frames):
        root_values = dict(zip(skeleton.root_order, frame["root"]))
        shift = [root_values.get(f"t{a}", 0.0) for a in "xyz"]
        rotation = fixed_axes(
            {d[1]: v * unit for d, v in root_values.items() if d[0] == "r"},
            [d[1] for d in skeleton.root_order if d[0] == "r"],
        )
        root_axis = axis_matrix(skeleton.root_orientation, skeleton.root_axis)
        frame_of = {"root": translation(skeleton.root_position + np.array(shift)) @ root_axis @ rotation}
        axis_of = {"root": root_axis}
        tip_of = {"root": np.zeros(3)}  # the bone vector in the bone's own local frame
        out[f, 0] = frame_of["root"][:3, 3]
        stack = ["root"]
        while stack:
            parent = stack.pop()
            for name in children[parent]:
                bone = bones[name]
                values = dict(zip(bone.dof, frame.get(name, [])))
                c = axis_matrix(bone.axis, bone.axis_order)
                amc = fixed_axes(
                    {d[1]: v * unit for d, v in values.items() if d[0] == "r"},
                    [d[1] for d in bone.dof if d[0] == "r"],
                )
                frame_of[name] = (
                    frame_of[parent] @ translation(tip_of[parent]) @ np.linalg.inv(axis_of[parent]) @ c @ amc
                )
                axis_of[name] = c
                local_direction = np.linalg.inv(c)[:3, :3] @ bone.direction
                length = bone.length + values.get("l", 0.0)
                tip_of[name] = length * local_direction + np.array([values.get(f"t{a}", 0.0) for a in "xyz"])
                out[f, names.index(name)] = (frame_of[name] @ np.append(tip_of[name], 1.0))[:3]
                stack.append(name)
    return out


# -------------------------------------------------------------------------- synthetic files
SKELETON = """\
# a small skeleton using most of the format
:version 1.10
:name test, skeleton
:units
  mass 1.0
  length 0.45
  angle deg
:documentation
  free text: (parentheses), commas, # even hashes
  and a second line
:root
   order RZ TX RY TY RX TZ
   axis ZXY
   position 1 2 3
   orientation 10 -20 30
:bonedata
  begin
     id 1
     name hip
     direction 0 -2 0
     length 3
     axis 0 0 20 XYZ
     dof rx ry rz
     limits (-160.0 20.0)
            (-70.0 70.0)
            (-inf inf)
  end
  begin
     id 2
     name knee
     direction 0.3 -0.9 0.1
     length 2.5
     axis 15 -5 40 ZYX
     dof rz rx
     limits (-10 170) (0 1)
  end
  begin
     name stretch
     direction 1 0 0
     length 1
     axis 5 10 15 YZX
     dof ry l tx tz
  end
  begin
     name spine
     direction 0.1 1 0.05
     length 2
     axis 0 0 0 XYZ
  end
  begin
     name head
     direction 0 1 0
     length 1.5
     axis -30 0 90 XZY
     dof ry
  end
:hierarchy
  begin
    root hip spine
    hip knee
    knee stretch
    spine head
  end
"""


def synthetic_amc(rng: np.random.Generator, n_frames: int = 6, shuffle: bool = True) -> str:
    dofs = {"root": 6, "hip": 3, "knee": 2, "stretch": 4, "head": 1}
    lines = ["# made by the test", ":FULLY-SPECIFIED", ":DEGREES"]
    for f in range(n_frames):
        lines.append(str(f + 1))
        order = list(dofs)
        if shuffle:
            rng.shuffle(order)
        for name in order:
            values = rng.uniform(-170, 170, dofs[name])
            if name == "stretch":
                values[1:] = rng.normal(size=3)
            lines.append(name + " " + " ".join(f"{v:.9g}" for v in values))
    return "\n".join(lines) + "\n"


@pytest.fixture
def synthetic(tmp_path, rng):
    asf = tmp_path / "test.asf"
    amc = tmp_path / "test.amc"
    asf.write_text(SKELETON)
    amc.write_text(synthetic_amc(rng))
    return asf, amc


def test_asf_fields(synthetic):
    skeleton = read_asf(synthetic[0])
    assert skeleton.name == "test, skeleton" and skeleton.version == "1.10"
    assert skeleton.units.length == 0.45 and skeleton.units.angle == "deg"
    assert skeleton.documentation.startswith("free text: (parentheses)") and "second line" in skeleton.documentation
    assert skeleton.root_order == ("rz", "tx", "ry", "ty", "rx", "tz") and skeleton.root_axis == "ZXY"
    np.testing.assert_array_equal(skeleton.root_position, [1, 2, 3])
    np.testing.assert_allclose(skeleton.root_orientation, np.radians([10, -20, 30]))
    assert skeleton.names == ("hip", "knee", "stretch", "spine", "head")
    assert list(skeleton.parents) == [-1, 0, 1, -1, 3]
    hip, knee, stretch, spine, _ = skeleton.bones
    np.testing.assert_array_equal(hip.direction, [0, -1, 0])  # normalised
    assert hip.length == 3 and hip.id == 1 and hip.dof == ("rx", "ry", "rz")
    np.testing.assert_allclose(hip.limits, np.radians([[-160, 20], [-70, 70], [-np.inf, np.inf]]))
    assert knee.axis_order == "ZYX" and knee.dof == ("rz", "rx")
    np.testing.assert_allclose(knee.axis, np.radians([15, -5, 40]))
    assert stretch.dof == ("ry", "l", "tx", "tz") and np.isnan(stretch.limits).all()
    assert spine.dof == () and spine.limits.shape == (0, 2)


def test_synthetic_amc_matches_independent_fk(synthetic):
    asf, amc = synthetic
    skeleton = read_asf(asf)
    motion = read_amc(amc, skeleton)
    assert motion.convention == "pre" and motion.names == ("root", "hip", "knee", "stretch", "spine", "head")
    motion.check_invariants()
    expected = acclaim_fk(skeleton, simple_amc_frames(amc.read_text()))
    assert np.abs(world_positions(motion) - expected).max() <= 1e-12 * motion.size


def test_radians_crlf_and_separators(synthetic, tmp_path):
    asf, amc = synthetic
    skeleton = read_asf(asf)
    degrees = read_amc(amc, skeleton)
    # the same motion in radians, CRLF line endings, commas and tabs as separators
    frames = simple_amc_frames(amc.read_text())
    lines = [":FULLY-SPECIFIED", ":RADIANS"]
    for f, frame in enumerate(frames, start=1):
        lines.append(f"{f}\t")
        for name, values in frame.items():
            dof = skeleton.root_order if name == "root" else skeleton.bones[skeleton.bone_index(name)].dof
            converted = [np.radians(v) if d[0] == "r" else v for d, v in zip(dof, values)]
            lines.append(f"{name}\t" + "  ".join(repr(float(v)) for v in converted))
    radians = tmp_path / "radians.amc"
    radians.write_bytes(("\r\n".join(lines) + "\r\n").encode())
    crlf_asf = tmp_path / "crlf.asf"
    crlf_asf.write_bytes(SKELETON.replace("\n", "\r\n").replace("0 -2 0", "0, -2, 0").encode())
    again = read_amc(radians, crlf_asf)
    np.testing.assert_allclose(world_positions(again), world_positions(degrees), atol=1e-12 * degrees.size)


def test_bones_in_any_order_give_the_same_motion(tmp_path, rng):
    asf = tmp_path / "s.asf"
    asf.write_text(SKELETON)
    text = synthetic_amc(np.random.default_rng(7), shuffle=False)
    frames = text.split("\n")
    # reverse the bone lines inside every frame
    out, block = [], []
    for line in frames:
        if line.strip().isdigit() or not line.strip():
            out += [*block[::-1], line]
            block = []
        elif line.startswith((":", "#")):
            out.append(line)
        else:
            block.append(line)
    out += block[::-1]
    (tmp_path / "a.amc").write_text(text)
    (tmp_path / "b.amc").write_text("\n".join(out))
    a, b = read_amc(tmp_path / "a.amc", asf), read_amc(tmp_path / "b.amc", asf)
    np.testing.assert_array_equal(a.rotations, b.rotations)
    np.testing.assert_array_equal(a.translations, b.translations)


def test_rest_pose(synthetic):
    skeleton = read_asf(synthetic[0])
    rest = skeleton_motion(skeleton, n_frames=2)
    assert rest.n_frames == 2 and rest.names[0] == "root"
    positions = world_positions(rest)[0]
    hip, knee, stretch, spine, head = skeleton.bones
    np.testing.assert_allclose(positions[0], [1, 2, 3])
    np.testing.assert_allclose(positions[3], [1, 2, 3] + 3 * hip.direction + 2.5 * knee.direction + stretch.direction)
    np.testing.assert_allclose(positions[5], [1, 2, 3] + 2 * spine.direction + 1.5 * head.direction)


# ------------------------------------------------------------------------------ real data
@pytest.mark.parametrize("amc", shared_files("**/*.amc"))
def test_real_amc_matches_independent_fk(amc):
    skeleton = read_asf(asf_beside(amc))
    motion = read_amc(amc, skeleton)
    frames = simple_amc_frames(amc.read_text())
    assert motion.n_frames == len(frames)
    every = slice(0, None, 37)  # the per-frame FK is slow: a spread of frames
    expected = acclaim_fk(skeleton, frames[every])
    assert np.abs(world_positions(motion)[every] - expected).max() <= 1e-9 * motion.size


@pytest.mark.parametrize("amc", shared_files("**/*.amc"))
def test_fast_parser_reads_every_value(amc):
    skeleton = read_asf(asf_beside(amc))
    values, first_frame, flags = parse_amc_frames(amc.read_bytes(), str(amc), skeleton)
    frames = simple_amc_frames(amc.read_text())
    assert first_frame == 1 and flags == {"fully_specified": True, "angle": "deg"}
    names = ["root", *skeleton.names]
    expected = np.array([[v for n in names for v in frame.get(n, [])] for frame in frames])
    np.testing.assert_array_equal(values, expected)


@pytest.mark.skipif(not have_numba(), reason="numba is not installed: the reader uses numpy")
@pytest.mark.parametrize("amc", shared_files("**/*.amc"))
def test_real_amc_reads_the_same_with_the_compiled_kernel_as_with_numpy(amc):
    """The compiled rotations equal the numpy path's to rounding; the rest to the bit."""
    skeleton = read_asf(asf_beside(amc))
    compiled, compiled_channels = read_amc_with_channels(amc, skeleton, backend="numba")
    reference, channels = read_amc_with_channels(amc, skeleton, backend="numpy")
    np.testing.assert_allclose(compiled.rotations, reference.rotations, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(compiled.translations, reference.translations)
    assert compiled_channels.orders == channels.orders and compiled_channels.angles.keys() == channels.angles.keys()
    for name, angles in channels.angles.items():
        np.testing.assert_array_equal(compiled_channels.angles[name], angles)


#: BVH joint of CMU 01_01.bvh -> the AMC joint (bone end) at the same place
CMU_SAME_PLACE = {
    "Hips": "root",
    "LHipJoint": "root",
    "RHipJoint": "root",
    "LowerBack": "root",
    "LeftUpLeg": "lhipjoint",
    "LeftLeg": "lfemur",
    "LeftFoot": "ltibia",
    "LeftToeBase": "lfoot",
    "LeftToeBase_End": "ltoes",
    "RightUpLeg": "rhipjoint",
    "RightLeg": "rfemur",
    "RightFoot": "rtibia",
    "RightToeBase": "rfoot",
    "RightToeBase_End": "rtoes",
    "Spine": "lowerback",
    "Spine1": "upperback",
}


def test_cmu_amc_agrees_with_the_cmu_bvh():
    bvh = read_bvh(shared_path("cmu/subject01/01_01.bvh"))
    amc = read_motion(shared_path("cmu/subject01/01_01.amc"))  # 01.asf found beside it
    assert bvh.n_frames == amc.n_frames + 1  # the BVH adds a T-pose as frame 0
    bvh_positions, amc_positions = world_positions(bvh)[1:], world_positions(amc)
    for bvh_name, amc_name in CMU_SAME_PLACE.items():
        difference = bvh_positions[:, bvh.names.index(bvh_name)] - amc_positions[:, amc.names.index(amc_name)]
        assert np.abs(difference).max() <= 1e-4, (bvh_name, amc_name)
    # the upper body: the BVH's Neck sits where the AMC's thorax starts, not where it ends
    neck = bvh_positions[:, bvh.names.index("Neck")]
    thorax_start = amc_positions[:, amc.names.index("upperback")]
    thorax_end = amc_positions[:, amc.names.index("thorax")]
    assert np.abs(neck - thorax_start).max() <= 1e-4
    thorax = read_asf(shared_path("cmu/subject01/01.asf")).bones[amc.names.index("thorax") - 1]
    np.testing.assert_allclose(np.linalg.norm(neck - thorax_end, axis=1), thorax.length, atol=1e-4)


def test_read_motion_finds_the_skeleton_and_load_gmr_keeps_it(tmp_path, synthetic):
    asf, amc = synthetic
    assert asf_beside(amc) == asf
    direct = read_amc(amc, asf, frame_rate=60)
    via = read_motion(amc, frame_rate=60)
    np.testing.assert_array_equal(via.rotations, direct.rotations)
    assert via.frame_time == 1 / 60 and load_gmr(amc).convention == "pre"
    assert read_motion(asf).n_frames == 1  # an ASF alone: its rest pose
    other = tmp_path / "other.asf"
    other.write_text(SKELETON)
    assert asf_beside(amc) == asf  # two skeletons: the one named like the AMC
    read_motion(amc, asf=other)


# ------------------------------------------------- frames in bulk and line by line agree
def frame_block(amc) -> bytes:
    """The frame lines of an AMC file (LF line ends), from its first frame number on."""
    data = amc.read_bytes().replace(b"\r\n", b"\n")
    return data[re.search(rb"^\d+\n", data, re.MULTILINE).start() :]


def dof_layout(skeleton) -> tuple[list[str], np.ndarray, np.ndarray]:
    """Joint names (root first), dofs per joint, first column of each joint's values."""
    counts = np.array([len(skeleton.root_order)] + [len(b.dof) for b in skeleton.bones])
    return ["root", *skeleton.names], counts, np.concatenate(([0], np.cumsum(counts)[:-1]))


def swap_first_bones_of_even_frames(block: bytes) -> bytes:
    """The same motion with the first two bone lines swapped in every other frame."""
    frames = re.split(rb"(?m)^(?=\d+\n)", block)
    out = []
    for k, frame in enumerate(f for f in frames if f):
        lines = frame.split(b"\n")
        if k % 2 == 0:
            lines[1], lines[2] = lines[2], lines[1]
        out.append(b"\n".join(lines))
    return b"".join(out)


@pytest.mark.parametrize("amc", shared_files("**/*.amc"))
def test_real_amc_frames_read_in_bulk_are_those_read_line_by_line(amc):
    skeleton = read_asf(asf_beside(amc))
    data = amc.read_bytes()
    names, counts, column_of = dof_layout(skeleton)
    bulk = bulk_frames(frame_block(amc), names, counts, column_of)
    assert bulk is not None, "a CMU take lists the same bones in every frame: it is read in bulk"
    values, first_frame, flags = parse_amc_frames(data, str(amc), skeleton)
    general, general_first, general_flags = parse_amc_frames(data, str(amc), skeleton, bulk=False)
    assert values.tobytes() == general.tobytes() == bulk[0].tobytes()
    assert values.shape == general.shape and first_frame == general_first == bulk[1]
    assert flags == general_flags


@pytest.mark.parametrize("amc", shared_files("**/*.amc"))
def test_real_amc_with_bones_reordered_reads_the_same_motion_to_the_bit(amc, tmp_path):
    """Frames whose bones come in differing orders are read line by line; the motion and
    channels are those of the file as published, read in bulk."""
    header = amc.read_bytes().replace(b"\r\n", b"\n")
    header = header[: re.search(rb"^\d+\n", header, re.MULTILINE).start()]
    reordered = tmp_path / amc.name
    reordered.write_bytes(header + swap_first_bones_of_even_frames(frame_block(amc)))
    skeleton = read_asf(asf_beside(amc))
    names, counts, column_of = dof_layout(skeleton)
    assert bulk_frames(frame_block(reordered), names, counts, column_of) is None
    (motion, channels), (same, same_channels) = (read_amc_with_channels(p, skeleton) for p in (amc, reordered))
    assert motion.rotations.tobytes() == same.rotations.tobytes()
    assert motion.translations.tobytes() == same.translations.tobytes()
    assert channels.angles.keys() == same_channels.angles.keys()
    for name, angles in channels.angles.items():
        assert angles.tobytes() == same_channels.angles[name].tobytes()


@pytest.mark.parametrize(
    ("change", "error"),
    [
        pytest.param(lambda b: b.replace(b" ", b"\t", 1), None, id="a tab"),
        pytest.param(lambda b: b.replace(b" ", b"  ", 1), None, id="two spaces"),
        pytest.param(lambda b: b.replace(b"\n", b" \n", 3), None, id="a trailing space"),
        pytest.param(lambda b: b.replace(b"\n", b"\n ", 3), None, id="a leading space"),
        pytest.param(lambda b: b.replace(b"\n", b"\n\n", 2), None, id="a blank line"),
        pytest.param(lambda b: b.replace(b"\n", b"\n# note\n", 2), None, id="a comment"),
        pytest.param(lambda b: b.rsplit(b"\n", 3)[0] + b"\n", "has no line for bone", id="a frame cut short"),
        pytest.param(lambda b: re.sub(rb"(?m)^2$", b"2x", b, count=1), "unknown bone '2x'", id="a bad frame number"),
        pytest.param(lambda b: re.sub(rb"(?m)^3$", b"4", b, count=1), "frame number 4: expected 3", id="a skip"),
        pytest.param(
            lambda b: b.replace(b"\nlowerback ", b"\nlowerback 0 ", 1), "bone 'lowerback' has 3 dof", id="a value more"
        ),
        pytest.param(
            lambda b: re.sub(rb"(?m)^(lowerback \S+ \S+) (\S+)\n(\w+) ", rb"\1\n\3 \2 ", b, count=1),
            "bone 'lowerback' has 3 dof (rx ry rz): expected 3 values, found 2",
            id="a value moved to the next bone's line",
        ),
        pytest.param(
            lambda b: re.sub(rb"(?m)^(lowerback \S+) \S+ ", rb"\1  ", b, count=1),
            "bone 'lowerback' has 3 dof (rx ry rz): expected 3 values, found 2",
            id="a value left out between two spaces",
        ),
    ],
)
def test_frames_of_another_layout_are_read_line_by_line_to_the_same_values_or_error(change, error, tmp_path):
    amc = shared_path("cmu/subject02/02_01.amc")
    skeleton = read_asf(asf_beside(amc))
    names, counts, column_of = dof_layout(skeleton)
    block = change(frame_block(amc))
    assert block != frame_block(amc)
    assert bulk_frames(block, names, counts, column_of) is None
    if error is not None:  # the general reader's error, naming the line
        with pytest.raises(MotionFileError, match=re.escape(error)):
            parse_amc_frames(block, str(amc), skeleton)
        return
    values, _, _ = parse_amc_frames(block, str(amc), skeleton)
    np.testing.assert_array_equal(values, parse_amc_frames(amc.read_bytes(), str(amc), skeleton)[0])


@pytest.mark.parametrize("short_lines", [False, True], ids=["long lines", "a bone line under 8 bytes"])
def test_synthetic_take_in_one_bone_order_reads_the_same_in_bulk_and_line_by_line(tmp_path, rng, short_lines):
    asf, amc = tmp_path / "test.asf", tmp_path / "test.amc"
    asf.write_text(SKELETON)
    text = synthetic_amc(rng, n_frames=5, shuffle=False)
    if short_lines:  # the last bone of every frame, "head", with one short value
        text = re.sub(r"(?m)^head .*$", "head 7", text)
    amc.write_text(text)
    skeleton = read_asf(asf)
    names, counts, column_of = dof_layout(skeleton)
    bulk = bulk_frames(frame_block(amc), names, counts, column_of)
    assert (bulk is None) == short_lines
    values, first, flags = parse_amc_frames(amc.read_bytes(), str(amc), skeleton)
    general, general_first, general_flags = parse_amc_frames(amc.read_bytes(), str(amc), skeleton, bulk=False)
    assert values.tobytes() == general.tobytes() and (first, flags) == (general_first, general_flags)
    if bulk is not None:
        assert bulk[0].tobytes() == values.tobytes()
