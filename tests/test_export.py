"""BVH export of anything GMR holds: a strict structural check of every file written,
export -> re-read round trips on the real files and on generated forests, continuous
Euler angles, original channel orders, one file per tree."""

from __future__ import annotations

import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gmr_studio.core.edits.operations import join, shift_root, split, split_all
from gmr_studio.core.errors import OperationError
from gmr_studio.core.formats import load_gmr, read_motion
from gmr_studio.core.formats.bvh import bvh_text, read_bvh
from gmr_studio.core.formats.bvh_export import bvh_export, bvh_export_trees, tree_file_name
from gmr_studio.core.kinematics.convention import pre_from_post
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.rotations.continuity import continuous_euler
from gmr_studio.core.rotations.euler import EULER_ORDERS, euler_from_matrix, matrix_from_euler
from tests.conftest import random_motion, shared_files, shared_path
from tests.test_bvh_reader import SMALL

#: round-trip position error of an export, over the skeleton's size: 15 significant digits
#: written, errors accumulate along the chains; measured at most 9.8e-14 on the shared files
#: and the generated forests (was 1e-6 and 1e-9, far above what a regression would reach)
EXPORT_TOLERANCE = 5e-13

_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"


def validate_bvh(text: str) -> dict:
    """Check the layout a strict BVH importer (Blender's) relies on; return a summary.

    - the first line is HIERARCHY; no comment lines anywhere; one ROOT;
    - ``ROOT|JOINT name``, then lines ``{``, ``OFFSET x y z``, ``CHANNELS n ...`` in that
      order; an ``End Site`` is ``{``, ``OFFSET``, ``}``; braces balance;
    - a joint has 0 or 3 position channels and 0 or 3 rotation channels, positions first;
    - every joint without child joints ends in an End Site;
    - MOTION, ``Frames: N``, ``Frame Time: t``, then N lines of exactly as many numbers
      as channels.
    """
    lines = [line.strip() for line in text.split("\n")]
    assert lines[0] == "HIERARCHY", lines[0]
    assert not any(line.startswith("#") for line in lines), "comment line"
    assert "\t" not in "".join(line.split(None, 1)[-1] for line in lines if line.startswith(("ROOT", "JOINT")))
    i, depth, roots, channels, names = 1, 0, 0, 0, []
    stack: list[dict] = []
    while lines[i] != "MOTION":
        words = lines[i].split()
        if words[0] in ("ROOT", "JOINT"):
            assert len(words) == 2, f"joint name with spaces: {lines[i]}"
            assert (words[0] == "ROOT") == (depth == 0), lines[i]
            roots += words[0] == "ROOT"
            names.append(words[1])
            assert lines[i + 1] == "{"
            assert re.fullmatch(rf"OFFSET {_NUMBER} {_NUMBER} {_NUMBER}", lines[i + 2]), lines[i + 2]
            kinds = lines[i + 3].split()
            assert kinds[0] == "CHANNELS" and int(kinds[1]) == len(kinds) - 2, lines[i + 3]
            positions = [k for k in kinds[2:] if k.endswith("position")]
            rotations = [k for k in kinds[2:] if k.endswith("rotation")]
            assert len(positions) in (0, 3) and len(rotations) in (0, 3), lines[i + 3]
            assert kinds[2:] == positions + rotations, "positions come first"
            assert sorted(p[0] for p in positions) in ([], ["X", "Y", "Z"])
            assert sorted(r[0] for r in rotations) in ([], ["X", "Y", "Z"])
            channels += len(kinds) - 2
            if stack:
                stack[-1]["children"] += 1
            stack.append({"name": words[1], "children": 0})
            depth += 1
            i += 4
        elif words == ["End", "Site"]:
            assert lines[i + 1] == "{" and lines[i + 3] == "}", lines[i : i + 4]
            assert re.fullmatch(rf"OFFSET {_NUMBER} {_NUMBER} {_NUMBER}", lines[i + 2])
            stack[-1]["children"] += 1
            i += 4
        elif words == ["}"]:
            joint = stack.pop()
            assert joint["children"] > 0, f"joint {joint['name']} has no child and no End Site"
            depth -= 1
            i += 1
        else:
            raise AssertionError(f"unexpected line {i + 1}: {lines[i]}")
    assert depth == 0 and not stack and roots == 1
    assert len(set(names)) == len(names)
    frames = int(re.fullmatch(r"Frames: (\d+)", lines[i + 1]).group(1))
    assert re.fullmatch(rf"Frame Time: {_NUMBER}", lines[i + 2]) and float(lines[i + 2].split()[2]) > 0
    data = [line for line in lines[i + 3 :] if line]
    assert len(data) == frames
    assert all(len(line.split()) == channels for line in data)
    return {"names": names, "channels": channels, "frames": frames}


def assert_round_trip(source: Motion, export, text: str | None = None, tolerance: float = EXPORT_TOLERANCE) -> Motion:
    """Re-read the export's text and compare every source joint's world positions."""
    text = text if text is not None else export.text()
    validate_bvh(text)
    again = read_bvh("export.bvh", text.encode())
    expected = world_positions(source)
    for j, name in enumerate(export.names):
        if name is None:
            continue
        error = np.abs(world_positions(again)[:, again.names.index(name)] - expected[:, j]).max()
        assert error <= tolerance * source.size, (source.names[j], name, error)
    return again


def degrees_jump(motion: Motion) -> float:
    """Largest change of any Euler channel between consecutive frames, in degrees, as written."""
    text = bvh_text(motion)
    block = text.split("Frame Time:")[1].split("\n", 1)[1]
    values = np.loadtxt(block.splitlines(), ndmin=2)
    rotation_columns = []
    column = 0
    for j in motion.topological_order:
        if motion.has_translation[j]:
            column += 3
        for _ in motion.rotation_orders[j]:
            rotation_columns.append(column)
            column += 1
    if values.shape[0] < 2 or not rotation_columns:
        return 0.0
    return float(np.abs(np.diff(values[:, rotation_columns], axis=0)).max())


# ------------------------------------------------------------------------------ real files
@pytest.mark.parametrize("path", shared_files("**/*.bvh") + shared_files("**/*.amc"))
def test_export_of_every_shared_file(path):
    source = load_gmr(path)
    export = bvh_export(source)
    again = assert_round_trip(source, export)
    assert export.world_root is None and again.n_frames == source.n_frames
    # the file's own joints keep their names (AMC leaves become End Sites of their parent)
    if path.suffix == ".bvh":
        assert again.names == read_bvh(path).names


def test_cmu_bvh_exports_as_it_was_read():
    original = read_bvh(shared_path("cmu/subject01/01_01.bvh"))
    export = bvh_export(pre_from_post(original))
    assert export.dummies == () and export.motion.rotation_orders == original.rotation_orders
    again = assert_round_trip(original, export)
    np.testing.assert_allclose(again.offsets, original.offsets, atol=1e-12)


def test_amc_leaves_keep_their_names_and_siblings_get_dummies():
    source = read_motion(shared_path("cmu/subject01/01_01.amc"))
    export = bvh_export(source)
    assert export.names == source.names  # leaves too: JOINT ltoes with a zero-offset End Site
    again = read_bvh("again.bvh", export.text().encode())
    assert set(source.names) <= set(again.names)
    # root's children (lhipjoint, rhipjoint, lowerback) turn differently: one dummy each
    assert {"lhipjoint_dummy", "rhipjoint_dummy", "lowerback_dummy"} <= set(export.dummies)
    summary = validate_bvh(export.text())
    assert summary["names"][0] == "root"


def test_forest_goes_under_one_world_root_with_six_channel_trees():
    source = split(split(load_gmr(shared_path("cmu/subject01/01_01.bvh")), "LeftFoot"), "RightArm")
    export = bvh_export(source)
    assert export.world_root == "World"
    text = export.text()
    assert text.splitlines()[1] == "ROOT World"
    for root in ("Hips", "LeftFoot", "RightArm"):
        block = text.split(f"JOINT {root}\n", 1)[1].splitlines()
        assert block[2].strip().startswith("CHANNELS 6 Xposition Yposition Zposition")
    assert_round_trip(source, export)


@pytest.mark.parametrize("path", shared_files("**/*.bvh") + shared_files("**/*.amc"))
def test_export_after_random_edits_of_every_shared_file(path):
    rng = np.random.default_rng(sum(path.name.encode()))
    motion = load_gmr(path)
    n = motion.n_joints
    for _ in range(8):
        operation, joint = rng.choice(["shift", "split", "split", "join"]), int(rng.integers(n))
        try:
            if operation == "shift":
                motion = shift_root(motion, joint)
            elif operation == "split":
                motion = split(motion, joint)
            else:
                motion = join(motion, int(rng.choice(motion.roots)))
        except OperationError:
            pass
    if len(motion.roots) == 1:
        motion = split(motion, int(rng.choice(np.flatnonzero(motion.parents >= 0))))
    assert_round_trip(motion, bvh_export(motion))
    for _, export in bvh_export_trees(motion):
        assert_round_trip(motion, export)


def test_names_with_spaces_become_single_words(rng):
    motion = random_motion(rng, [-1, 0, 1], n_frames=2).replace(names=("Hips", "Left Hand", "Left_Hand"))
    export = bvh_export(motion)
    assert export.names == ("Hips", "Left_Hand2", "Left_Hand")  # the leaf keeps its name
    assert_round_trip(motion, export)


def test_one_file_per_tree(tmp_path):
    source = split(split(load_gmr(shared_path("cmu/subject01/01_01.bvh")), "LeftFoot"), "RightArm")
    trees = bvh_export_trees(source)
    assert [root for root, _ in trees] == ["Hips", "LeftFoot", "RightArm"]
    covered = set()
    for root, export in trees:
        path = tree_file_name(tmp_path / "walk.bvh", root)
        export.write(path)
        assert path.name == f"walk_{root}.bvh" and export.world_root is None
        again = assert_round_trip(source, export, path.read_text())
        assert again.names[0] == root
        covered |= {j for j, name in enumerate(export.names) if name is not None}
    assert covered == set(range(source.n_joints))


def test_per_frame_offsets_become_position_channels(rng):
    # a join whose bone length changes over time keeps per-frame offsets
    motion = random_motion(rng, [-1, 0, 1, 2], n_frames=5)
    split_once = split(motion, 2)
    translations = split_once.translations.copy()
    translations[:, 2] += rng.normal(size=(5, 3))  # move the split root: the bone stretches
    joined = join(split_once.replace(translations=translations), 2)
    assert joined.has_translation[2] and joined.parents[2] == 1
    export = bvh_export(joined)
    text = export.text()
    block = text.split("JOINT j2\n", 1)[1].splitlines()
    assert "Xposition Yposition Zposition" in block[2]
    assert_round_trip(joined, export)


def test_channel_orders_survive_bvh_gmr_bvh():
    text = """HIERARCHY
ROOT Hips
{
\tOFFSET 0 0 0
\tCHANNELS 6 Xposition Yposition Zposition Yrotation Xrotation Zrotation
\tJOINT Chest
\t{
\t\tOFFSET 0 2 0
\t\tCHANNELS 3 Xrotation Zrotation Yrotation
\t\tJOINT Head
\t\t{
\t\t\tOFFSET 0 1 0.5
\t\t\tCHANNELS 3 Zrotation Xrotation Yrotation
\t\t\tEnd Site
\t\t\t{
\t\t\t\tOFFSET 0 1 0
\t\t\t}
\t\t}
\t}
}
MOTION
Frames: 2
Frame Time: 0.04
1 2 3 10 20 30 40 50 60 70 80 90
1 2 3 -170 95 175 40 -50 60 -70 80 -90
"""
    original = read_bvh("orders.bvh", text.encode())
    export = bvh_export(pre_from_post(original))
    assert export.motion.rotation_orders[:3] == ("YXZ", "XZY", "ZXY")
    assert_round_trip(original, export)


# ------------------------------------------------------------------------ Euler continuity
@pytest.mark.parametrize("order", EULER_ORDERS)
def test_continuous_euler_recovers_a_continuous_path(order):
    # several turns about the first and last axes, the middle angle swinging past +-90
    t = np.linspace(0, 1, 400)
    path = np.stack([6 * np.pi * t, 2.2 * np.sin(9 * t), -5 * np.pi * t], axis=-1)
    angles = continuous_euler(matrix_from_euler(path, order), order)
    np.testing.assert_allclose(angles, path, atol=1e-9)
    principal = euler_from_matrix(matrix_from_euler(path, order), order)
    assert np.abs(np.diff(principal, axis=0)).max() > np.radians(300)  # what the writer used to print


@pytest.mark.parametrize("order", ["ZYX", "XZY", "YX", "Z"])
def test_continuous_euler_block_by_block_matches_one_call(order, rng):
    # turns and gimbal passes that cross the block boundaries; the writer goes block by block
    t = np.linspace(0, 1, 997)
    swing = 2.2 if len(order) == 3 else 1.2  # a shorter order cannot pass its middle axis beyond 90 degrees
    path = np.stack([6 * np.pi * t, swing * np.sin(9 * t), -5 * np.pi * t], axis=-1)[:, None, : len(order)]
    path = path + rng.normal(scale=0.01, size=(len(t), 4, len(order)))
    matrices = matrix_from_euler(path, order)
    whole = continuous_euler(matrices, order)
    blocks, previous = [], None
    for start in range(0, len(t), 100):
        blocks.append(continuous_euler(matrices[start : start + 100], order, previous))
        previous = blocks[-1][-1]
    np.testing.assert_allclose(np.concatenate(blocks), whole, rtol=0, atol=1e-12)
    np.testing.assert_allclose(whole, path, atol=1e-9)


def test_written_angles_are_continuous(rng):
    n = 400
    t = np.linspace(0, 1, n)
    spin = matrix_from_euler(np.stack([6 * np.pi * t, 2.2 * np.sin(9 * t), -5 * np.pi * t], axis=-1), "ZYX")
    motion = random_motion(rng, [-1, 0, 1], n_frames=n)
    motion = motion.replace(
        rotations=np.stack([np.broadcast_to(np.eye(3), (n, 3, 3)), spin, spin], axis=1),
        rotation_orders=("ZYX", "ZYX", "ZYX"),
    )
    export = bvh_export(motion)
    assert degrees_jump(export.motion) < 5.0  # the motion's own steps are below 3 degrees
    assert_round_trip(motion, export)
    assert degrees_jump(read_bvh("again.bvh", export.text().encode())) < 5.0


@pytest.mark.parametrize("path", shared_files("cmu/**/*.amc"))
def test_real_motion_has_no_360_jumps(path):
    export = bvh_export(read_motion(path))
    assert degrees_jump(export.motion) < 90.0


# --------------------------------------------------------------- generated forests (hypothesis)
@st.composite
def edited_forests(draw):
    n = draw(st.integers(2, 7))
    parents = [-1] + [draw(st.integers(-1, j - 1)) if j > 1 else 0 for j in range(1, n)]
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    motion = random_motion(rng, parents, n_frames=draw(st.integers(1, 4)))
    steps = draw(st.lists(st.tuples(st.sampled_from(["shift", "split", "join", "split_all"]), st.integers(0, n - 1))))
    for operation, joint in steps[:6]:
        try:
            if operation == "shift":
                motion = shift_root(motion, joint)
            elif operation == "split":
                motion = split(motion, joint)
            elif operation == "join":
                motion = join(motion, joint)
            elif joint == 0:
                motion = split_all(motion)
        except OperationError:
            pass
    return motion


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(edited_forests(), st.booleans())
def test_generated_forests_export_and_read_back(motion, per_tree):
    if per_tree:
        for _, export in bvh_export_trees(motion):
            assert_round_trip(motion, export)
    else:
        export = bvh_export(motion)
        assert (export.world_root is not None) == (len(motion.roots) > 1)
        assert_round_trip(motion, export)


def test_the_validator_refuses_what_strict_importers_misread():
    good = bvh_export(read_bvh("small.bvh", SMALL.encode())).text()
    validate_bvh(good)
    bad = {
        "comment": good.replace("HIERARCHY\n", "HIERARCHY\n# made by gmr\n"),
        "two rotation channels": good.replace(
            "CHANNELS 3 Zrotation Xrotation Yrotation", "CHANNELS 2 Zrotation Xrotation"
        ),
        "no End Site": re.sub(r"\s*End Site\s*\{[^}]*\}", "", good),
        "count": good.replace("Frames: 2", "Frames: 3"),
        "unbalanced": good.replace("}\nMOTION", "MOTION"),
    }
    for what, text in bad.items():
        with pytest.raises(AssertionError):
            validate_bvh(text)
        assert text != good, what


def test_a_joint_named_world_keeps_its_name_and_the_synthetic_root_takes_another(rng):
    motion = random_motion(rng, [-1, 0, 1, -1, 3], n_frames=4)
    motion = motion.replace(names=("Hips", "World", "Hand", "Other", "World2"))
    export = bvh_export(motion)
    assert export.world_root == "World3"  # World and World2 are taken by joints
    summary = validate_bvh(export.text())
    assert summary["names"][0] == "World3" and len(set(summary["names"])) == len(summary["names"])
    assert [export.names[j] for j in (0, 1, 3)] == ["Hips", "World", "Other"]  # joints with children
    again = assert_round_trip(motion, export)
    world = again.joint_index("World")
    assert again.names[again.parents[world]] == "Hips" and again.parents[again.joint_index("World3")] == -1
