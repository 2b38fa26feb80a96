"""Names survive every BVH export path (issue 14.8): a joint left childless by a split is
written as a named JOINT (three zero rotation channels and a zero-offset End Site), and our
reader, pybvh and bvhio read every joint back with its name at its position."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.cli import main
from gmr_studio.core.edits.operations import split, split_all
from gmr_studio.core.formats import load_gmr, read_motion, write_motion
from gmr_studio.core.formats.bvh import read_bvh
from gmr_studio.core.formats.bvh_export import bvh_export, bvh_export_trees
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.model.motion import Motion
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.conftest import shared_path

studio = app_fixtures.studio  # the main-window fixture (fails on leaked windows)


@pytest.fixture(scope="module")
def split_feet() -> Motion:
    """CMU 01_01.bvh (first 200 frames) split at both feet: LeftLeg and RightLeg are leaves."""
    motion = load_gmr(shared_path("cmu/subject01/01_01.bvh")).frame_slice(slice(0, 200))
    return split(split(motion, "LeftFoot"), "RightFoot")


def assert_names_and_positions_kept(source: Motion, again: Motion) -> None:
    """Every joint of ``source`` is in ``again`` under its own name, at its own positions."""
    missing = [n for n in source.names if n not in again.names]
    assert not missing, f"names lost: {missing}"
    theirs = world_positions(again)[:, [again.names.index(n) for n in source.names]]
    np.testing.assert_allclose(theirs, world_positions(source), rtol=0, atol=1e-9 * source.size)


def test_a_joint_left_childless_by_a_split_keeps_its_name(split_feet, tmp_path):
    assert not split_feet.children[split_feet.joint_index("LeftLeg")]
    export = bvh_export(split_feet)
    assert export.names == split_feet.names
    text = export.text()
    assert "JOINT LeftLeg\n" in text.replace("\t", "") and "LeftUpLeg_End" not in text
    block = text.split("JOINT LeftLeg\n", 1)[1].splitlines()
    assert block[2].strip().startswith("CHANNELS 3 ") and block[3].strip() == "End Site"
    assert block[5].split() == ["OFFSET", "0", "0", "0"]
    export.write(tmp_path / "feet.bvh")
    assert_names_and_positions_kept(split_feet, read_bvh(tmp_path / "feet.bvh"))


def test_an_end_site_split_off_as_its_own_tree_keeps_its_name_and_the_file_stays_valid(split_feet):
    """Splitting off ``LeftToeBase_End`` leaves ``LeftToeBase`` a leaf with channels: the export
    gives it a zero-offset End Site (every JOINT has a child, as strict readers require), and
    writes the ``LeftToeBase_End`` tree first, so that a reader numbers that End Site
    ``LeftToeBase_End2`` instead of meeting the name twice (it did: no End Site was written)."""
    from tests.test_export import validate_bvh

    motion = split(split_feet, "LeftToeBase_End")
    export = bvh_export(motion)
    assert export.names == motion.names
    text = export.text()
    validate_bvh(text)
    again = read_bvh("end.bvh", text.encode())
    assert "LeftToeBase_End2" in again.names and again.parents[again.names.index("LeftToeBase_End2")] == (
        again.names.index("LeftToeBase")
    )
    assert_names_and_positions_kept(motion, again)


def test_names_kept_one_file_per_tree(split_feet, tmp_path):
    for root, export in bvh_export_trees(split_feet):
        path = tmp_path / f"{root}.bvh"
        export.write(path)
        kept = [j for j, name in enumerate(export.names) if name is not None]
        assert [export.names[j] for j in kept] == [split_feet.names[j] for j in kept]
        assert_names_and_positions_kept(split_feet.joint_slice(split_feet.subtree(root)), read_bvh(path))


def test_names_kept_after_split_all(split_feet):
    every = split_all(split_feet)
    again = read_bvh("all.bvh", bvh_export(every).text().encode())
    assert_names_and_positions_kept(every, again)


@pytest.mark.parametrize("command", ["edit", "convert", "convert-trees"])
def test_names_kept_by_the_command_line(split_feet, tmp_path, capsys, command):
    source = tmp_path / "feet.gmr"
    write_motion(split_feet, source)
    out = tmp_path / "out.bvh"
    argv = {
        "edit": ["edit", str(source), "-o", str(out)],
        "convert": ["convert", str(source), str(out)],
        "convert-trees": ["convert", str(source), str(out), "--split-trees"],
    }[command]
    assert main(argv) == 0, capsys.readouterr().err
    files = sorted(tmp_path.glob("out*.bvh"))
    assert files
    names = set().union(*(read_motion(f).names for f in files))
    assert set(split_feet.names) <= names


def test_other_readers_read_the_names_back(split_feet, tmp_path):
    """pybvh and bvhio (as strict as Blender's importer: both reject or rename
    differently-shaped joints) read the exported file with every name."""
    pybvh = pytest.importorskip("pybvh")
    bvhio = pytest.importorskip("bvhio")
    path = tmp_path / "hips.bvh"  # one tree (pybvh reads no position channels below the root)
    root, export = bvh_export_trees(split_feet)[0]
    assert root == "Hips"
    export.write(path)
    pybvh_names = {node.name for node in pybvh.read_bvh_file(path).nodes}
    bvhio_names = {joint.Name for joint, _, _ in bvhio.readAsHierarchy(str(path)).layout()}
    ours = read_bvh(path)
    # End Sites: pybvh calls them EndSite<parent>, bvhio leaves them out; the rest by name
    joints = {n for j, n in enumerate(ours.names) if ours.rotation_orders[j] or ours.has_translation[j]}
    assert {"LeftLeg", "RightLeg", "Head"} <= joints
    assert joints <= pybvh_names and joints <= bvhio_names


@pytest.mark.gui
def test_names_kept_by_the_apps_export(qtbot, studio, tmp_path):
    """File > Export BVH (one file and one file per tree) after Split here at both feet."""
    from gmr_studio.app.model import commands

    open_file(studio, shared_path("cmu/subject01/01_01.bvh"))
    state = studio.state
    for foot in ("LeftFoot", "RightFoot"):
        assert commands.split_here(state, state.motion.joint_index(foot))
    assert studio.exports.export_bvh(tmp_path / "one.bvh")
    assert set(state.motion.names) <= set(read_bvh(tmp_path / "one.bvh").names)
    assert studio.exports.export_bvh(tmp_path / "trees.bvh", per_tree=True)
    names = set().union(*(read_bvh(f).names for f in tmp_path.glob("trees_*.bvh")))
    assert set(state.motion.names) <= names
