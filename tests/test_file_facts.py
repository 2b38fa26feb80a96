"""File facts: the units and up axis a file states are typed fields of the motion, read and
written at the I/O boundary, kept true by the edits, and the one answer every feature uses
(a file that states no up axis stands on the axis its figure shows)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gmr_studio.core.analysis.contacts import foot_contacts
from gmr_studio.core.cli import main
from gmr_studio.core.demo import demo_motion
from gmr_studio.core.edits.world import change_up_axis, in_source_unit, scale_lengths
from gmr_studio.core.formats import read_motion
from gmr_studio.core.formats.facts import fact_comments, facts_from_comments
from gmr_studio.core.formats.gmr import gmr_text, read_gmr
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.space.units import CMU_UNIT, UNITS, acclaim_unit, parse_unit, unit_of_length
from gmr_studio.core.space.up_axis import up_axis_of
from tests.conftest import shared_path


def test_fact_lines_read_the_last_statement_of_each_kind_and_keep_the_rest():
    facts, free = facts_from_comments(
        ["made by hand", "units: mm", "Up Axis: Z", "units: Centimeters", "up axis: y (turned back)", "units: km"]
    )
    assert facts == FileFacts(unit=UNITS["cm"], up_axis="y")
    assert free == ("made by hand", "units: km")  # not a unit: kept as a comment
    odd = FileFacts(unit=acclaim_unit(0.45), up_axis="z", source_unit=unit_of_length(0.0125))
    again, rest = facts_from_comments(fact_comments(odd))
    assert again == odd and rest == ()
    older, _ = facts_from_comments(["source units: 0.0564444444444444 m (written by GMR Studio from ...)"])
    assert older.source_unit.metres == pytest.approx(0.0254 / 0.45, rel=1e-14)


def test_a_gmr_file_keeps_its_facts_and_its_comments_apart(rng):
    motion = demo_motion().replace(facts=FileFacts(unit=CMU_UNIT, up_axis="z", source_unit=UNITS["in"]))
    text = gmr_text(motion)
    assert text.startswith("GMR 1\n# units: 0.0564444444444444 m (ASF unit (in / 0.45))\n# up axis: z\n")
    back = read_gmr("walk.gmr", text.encode())
    assert back.facts == motion.facts and back.comments == motion.comments


def test_edits_keep_the_facts_true():
    walk = demo_motion()  # cm, Y up
    assert (walk.facts.unit, walk.facts.up_axis) == (UNITS["cm"], "y")
    assert scale_lengths(walk, 0.01).facts.unit == UNITS["m"]
    assert scale_lengths(walk, 10.0).facts.unit == UNITS["mm"]
    assert scale_lengths(walk, 3.0).facts.unit.metres == pytest.approx(0.01 / 3)
    assert change_up_axis(walk, "z").facts.up_axis == "z"
    glb_like = scale_lengths(walk, 0.01).replace(facts=FileFacts(unit=UNITS["m"], source_unit=UNITS["cm"]))
    back = in_source_unit(glb_like)
    assert back.facts == FileFacts(unit=UNITS["cm"])
    np.testing.assert_allclose(back.offsets, walk.offsets, rtol=1e-15)


def test_readers_state_what_their_formats_state():
    assert read_motion(shared_path("cmu/subject01/01_01.bvh")).facts == FileFacts()  # BVH states nothing
    amc = read_motion(shared_path("cmu/subject01/01_01.amc"))
    assert amc.facts.unit == CMU_UNIT and amc.facts.up_axis is None
    fox = read_motion(shared_path("gltf/bevy_Fox.glb"))
    assert fox.facts == FileFacts(unit=UNITS["m"], up_axis="y")
    assert parse_unit("Millimetres") == UNITS["mm"] and parse_unit("yards") is None


def test_contacts_of_a_z_up_motion_that_states_nothing_are_measured_along_z():
    """Regression: a Z-up motion without a statement was drawn Z up but its contacts were
    measured along Y (9.8% planted became 1.0% on the demo)."""
    walk = demo_motion()
    z_up = change_up_axis(walk, "z").replace(facts=FileFacts())
    assert up_axis_of(z_up) == "z"
    assert np.array_equal(foot_contacts(z_up).planted, foot_contacts(walk).planted)
    assert foot_contacts(walk).planted.mean() > 0.05


def test_a_bvh_written_z_up_reads_back_with_its_axes(tmp_path, capsys):
    """Regression: ``gmr edit walk.bvh --up z -o walk_z.bvh`` wrote a BVH that states no up
    axis, and its contacts were then measured along Y (planted 41% -> 2% on a real walk)."""
    source = shared_path("bvh/bvh-python_test_mocapbank.bvh")
    turned, original_csv, turned_csv = tmp_path / "walk_z.bvh", tmp_path / "a.csv", tmp_path / "b.csv"
    assert main(["edit", str(source), "--up", "z", "-o", str(turned)]) == 0
    assert up_axis_of(read_motion(turned)) == "z"
    assert main(["curves", str(source), "--quantity", "contacts", "-o", str(original_csv)]) == 0
    assert main(["curves", str(turned), "--quantity", "contacts", "-o", str(turned_csv)]) == 0
    capsys.readouterr()
    before, after = (np.loadtxt(p, delimiter=",", skiprows=1) for p in (original_csv, turned_csv))
    assert before[:, 1:].mean() > 0.05
    np.testing.assert_array_equal(after, before)


@pytest.mark.parametrize("up", ["y", "z"])
def test_a_forest_exported_under_a_world_root_reads_back_with_its_axes_and_size(tmp_path, capsys, up):
    """Regression: a split-all walk written as one BVH hangs its trees under a still
    ``World`` root at the origin; counted as part of the figure, the walk's distance from
    it made a Y-up walk look Z up (a comparison with the source then turned it over)."""
    walk = change_up_axis(demo_motion(), up)
    source, forest, again = tmp_path / "walk.gmr", tmp_path / "forest.gmr", tmp_path / "forest.bvh"
    source.write_text(gmr_text(walk.replace(facts=FileFacts())))  # stating nothing: detected
    assert main(["edit", str(source), "--split-all", "-o", str(forest)]) == 0
    assert main(["convert", str(forest), str(again)]) == 0
    capsys.readouterr()
    motion = read_motion(again)
    assert [motion.names[j] for j in np.flatnonzero(motion.anchors)] == ["World"]
    assert up_axis_of(motion) == up_axis_of(walk) == up
    assert motion.size == pytest.approx(walk.size, rel=1e-9)


def test_a_conversion_chain_through_gltf_keeps_the_units_it_came_from(tmp_path, capsys):
    """Regression: AMC -> BVH -> glb -> BVH wrote the last BVH in metres, stating nothing, and
    compare with the AMC gave an MPJPE of 30 units on a 29-unit skeleton."""
    amc = shared_path("cmu/subject01/01_01.amc")
    a_bvh, glb, b_bvh, report = tmp_path / "a.bvh", tmp_path / "a.glb", tmp_path / "b.bvh", tmp_path / "r.json"
    for source, target in ((amc, a_bvh), (a_bvh, glb), (glb, b_bvh)):
        assert main(["convert", str(source), str(target)]) == 0, (source, target)
    assert read_motion(b_bvh).size == pytest.approx(read_motion(a_bvh).size, rel=1e-6)
    assert main(["compare", str(amc), str(b_bvh), "--json", str(report)]) == 0
    capsys.readouterr()
    result = json.loads(report.read_text())
    assert result["mpjpe"] < 1e-5 * read_motion(amc).size


def test_compare_warns_when_sizes_differ_and_no_units_are_stated(tmp_path, capsys):
    source = shared_path("bvh/cmu_cgspeed_npybvh_example_75f.bvh")
    metres = tmp_path / "metres.bvh"
    assert main(["edit", str(source), "--scale", "0.0564444", "-o", str(metres)]) == 0
    capsys.readouterr()
    assert main(["compare", str(source), str(metres)]) == 0
    out = capsys.readouterr().out
    assert "WARNING" in out and "different units" in out and "--scale" in out
