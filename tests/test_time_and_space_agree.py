"""Every real file keeps its time, units and axes through every path that touches them.

For each motion file of the shared data (BVH, ASF/AMC, glTF, FBX; long takes cut to their
first frames):

- written through every writer (BVH, GMR, glTF) and read back, every joint is where it was
  (1e-9 of the size; glTF stores float32: 1e-6), in the same unit and on the same up axis
  as the facts say, on the same clock (the frame time to the writer's precision);
- ``compare`` of the source with each written file, reading both from disk with no flags,
  finds them the same (the units and axes come from the files' facts, or the figure);
- the ``channels`` curves of the motion are the channels its BVH file holds, frame by frame;
- foot contacts are the same with the world turned to the other up axis, and a figure whose
  file states nothing stands on the turned axis.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gmr_studio.core.analysis.contacts import foot_contacts
from gmr_studio.core.analysis.curves import joint_curves
from gmr_studio.core.compare import compare_motions
from gmr_studio.core.edits.clip import trim
from gmr_studio.core.edits.world import change_up_axis
from gmr_studio.core.formats import read_motion, read_motion_with_channels, write_motion
from gmr_studio.core.formats.gltf import export_gltf
from gmr_studio.core.kinematics.convention import post_from_pre, pre_from_post
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.space.up_axis import up_axis_of
from tests.conftest import shared_files

#: frames kept of every take: enough for contacts and curves, quick for every writer
FRAMES = 150
FILES = [
    *shared_files("bvh/*.bvh"),
    *shared_files("cmu/subject01/01_01.bvh"),
    *shared_files("cmu/*/*.amc"),
    *shared_files("gltf/*.gl*"),
    *shared_files("gltf/*/*.gltf"),
    *shared_files("fbx/*.fbx"),
]


def read_cut(path):
    motion = read_motion(path)
    return trim(motion, 0, min(motion.n_frames, FRAMES)) if motion.n_frames > FRAMES else motion


def stands_on_its_axis(motion) -> bool:
    """The figure shows the up axis its file states (a standing figure is taller than it is
    long; a fox is not): written where no axis can be stated (BVH), it reads back on it."""
    return up_axis_of(motion.replace(facts=FileFacts())) == up_axis_of(motion)


def metres(motion) -> float:
    """Metres per unit of a motion's lengths (1 when its file states none: compared as is)."""
    return 1.0 if motion.facts.unit is None else motion.facts.unit.metres


@pytest.fixture(params=FILES)
def source(request, tmp_path_factory):
    path = request.param
    return path, read_cut(path), tmp_path_factory.mktemp("written")


@pytest.mark.parametrize("suffix", [".bvh", ".gmr", ".glb"])
def test_every_writer_keeps_positions_units_axes_and_clock(source, suffix):
    path, motion, folder = source
    target = folder / f"again{suffix}"
    if suffix == ".glb":
        export_gltf(motion, target, skin=False)
    else:
        write_motion(post_from_pre(motion)[0] if suffix == ".bvh" else pre_from_post(motion), target)
    back = read_motion(target)
    assert back.n_frames == motion.n_frames
    float32 = suffix == ".glb"
    assert back.frame_time == pytest.approx(motion.frame_time, rel=1e-6 if float32 else 1e-12)
    if suffix == ".glb":
        assert up_axis_of(back) == "y"  # glTF is Y up: a Z-up motion is turned
        back = change_up_axis(back, up_axis_of(motion))  # and turned back here
        # metres, from the unit the motion states, or the one the export took and recorded
        unit = motion.facts.unit or back.facts.source_unit or back.facts.unit
        got = world_positions(back) * (back.facts.unit.metres / unit.metres)
    else:  # BVH and GMR keep the motion's lengths; GMR states its facts, BVH what the figure shows
        if suffix == ".gmr" or stands_on_its_axis(motion):
            assert up_axis_of(back) == up_axis_of(motion)
        assert suffix == ".bvh" or back.facts == motion.facts
        got = world_positions(back)
    expected = world_positions(motion)
    order = [back.names.index(name) for name in motion.names if name in back.names]
    kept = [j for j, name in enumerate(motion.names) if name in back.names]
    assert len(kept) >= motion.n_joints - 1  # no joint is lost on the way
    error = np.abs(got[:, order] - expected[:, kept]).max() / motion.size
    assert error <= (1e-6 if float32 else 1e-9), f"{path.name} -> {suffix}: {error:.3g} of the size"


@pytest.mark.parametrize("suffix", [".bvh", ".glb"])
def test_compare_with_the_written_file_needs_no_flags(source, suffix):
    path, motion, folder = source
    target = folder / f"compared{suffix}"
    if suffix == ".glb":
        export_gltf(motion, target, skin=False)
    else:
        write_motion(post_from_pre(motion)[0], target)
    written = read_motion(target)
    if suffix == ".bvh" and not stands_on_its_axis(motion):
        # a BVH cannot state its up axis, and this figure does not show it: given as a user
        # would give it, the comparison agrees as well
        written = written.replace(facts=dataclasses.replace(written.facts, up_axis=up_axis_of(motion)))
    result = compare_motions(motion, written, label_a=path.name, label_b=target.name)
    tolerance = 1e-6 if suffix == ".glb" else 1e-9
    assert result.position.mean <= tolerance * motion.size, result.alignment.notes


def test_the_channels_curves_are_the_channels_the_bvh_holds(source):
    _path, motion, folder = source
    target = folder / "channels.bvh"
    post = post_from_pre(motion)[0]
    write_motion(post, target)
    written, channels = read_motion_with_channels(target)
    for name in written.names[:: max(1, written.n_joints // 8)]:  # a sample of the joints
        if name not in channels.angles:
            continue
        mine = joint_curves(post, name, "channels").values
        assert mine.shape == channels.angles[name].shape
        np.testing.assert_allclose(mine, channels.angles[name], rtol=0, atol=1e-9)


def test_contacts_are_the_same_on_either_up_axis(source):
    _path, motion, _folder = source
    up = up_axis_of(motion)
    other = change_up_axis(motion, "z" if up == "y" else "y")  # states its new up axis
    np.testing.assert_array_equal(foot_contacts(other).planted, foot_contacts(motion).planted)
    if motion.n_joints >= 10 and stands_on_its_axis(motion):  # a body standing on its up axis
        # stating nothing, it stands on the turned axis too
        unstated = other.replace(facts=FileFacts(unit=motion.facts.unit))
        assert up_axis_of(unstated) == other.facts.up_axis
