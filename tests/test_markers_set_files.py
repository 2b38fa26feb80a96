"""Marker-set files and the matching of labels (core/markers/sets.py) on small set files
written here: sided and centre roles, alternatives, ``A+B`` means, required groups, the
ranking among sets, the summary line, the refusals of a bad file."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.markers.sets import (
    SETS_DIR,
    identify_marker_set,
    known_sets,
    load_set_definition,
    match_set,
    no_match_text,
    role_positions,
    set_by_name,
)

LAB = """format = "gmr-markerset 1"
name = "lab"
title = "A lab's set"
description = "for the tests"
sides = ["L_", "R_"]
required = ["ASI", "PSI|SACR", "KNE", "C7"]
optional = ["ELB", "CLAV", "TOE", "RBAK"]

[roles.sided]
ASI = "L_ASIS"
PSI = ["L_PSIS", "L_BACK"]
KNE = ["L_KNEE", "L_KLAT+L_KMED"]
ELB = "L_ELB"
TOE = "L_TOE"

[roles.centre]
SACR = ["SACR", "L_PSIS+R_PSIS"]
C7 = "C7"
CLAV = "CLAV"
RBAK = "RBAK"
"""
REQUIRED = 'required = ["ASI", "PSI|SACR", "KNE", "C7"]'


@pytest.fixture
def lab(tmp_path):
    path = tmp_path / "lab.toml"
    path.write_text(LAB)
    return load_set_definition(path)


def test_a_set_file_gives_left_and_right_roles_and_required_groups(lab, tmp_path):
    assert (lab.name, lab.title, lab.description) == ("lab", "A lab's set", "for the tests")
    assert lab.source == str(tmp_path / "lab.toml")
    assert lab.roles["LASI"] == ("L_ASIS",) and lab.roles["RASI"] == ("R_ASIS",)
    assert lab.roles["RPSI"] == ("R_PSIS", "R_BACK")
    assert lab.roles["RKNE"] == ("R_KNEE", "R_KLAT+R_KMED")  # each part of a mean swapped
    assert lab.roles["SACR"] == ("SACR", "L_PSIS+R_PSIS") and lab.roles["C7"] == ("C7",)
    assert lab.required == (("LASI",), ("RASI",), ("LPSI", "SACR"), ("LKNE",), ("RKNE",), ("C7",))
    assert lab.optional == ("LELB", "RELB", "CLAV", "LTOE", "RTOE", "RBAK")
    assert lab.sided_roles() == {"ASI", "PSI", "KNE", "ELB", "TOE"}  # RBAK is a centre role
    assert lab.labels_of("RELB") == ("R_ELB",) and lab.labels_of("NOPE") == ()


def test_a_group_of_sided_roles_only_is_required_on_each_side(tmp_path):
    path = tmp_path / "both.toml"
    path.write_text(LAB.replace('"PSI|SACR"', '"PSI|ASI"'))
    assert load_set_definition(path).required[2:4] == (("LPSI", "LASI"), ("RPSI", "RASI"))


def test_prefixes_of_different_lengths_swap_whole(tmp_path):
    path = tmp_path / "words.toml"
    path.write_text(LAB.replace('sides = ["L_", "R_"]', 'sides = ["Left", "Right"]').replace("L_", "Left"))
    words = load_set_definition(path)
    assert words.roles["RKNE"] == ("RightKNEE", "RightKLAT+RightKMED") and words.roles["LKNE"] == (
        "LeftKNEE",
        "LeftKLAT+LeftKMED",
    )


def test_set_definitions_and_matches_are_frozen(lab):
    with pytest.raises(dataclasses.FrozenInstanceError):
        lab.name = "other"  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        match_set(FULL, lab).score = 0.0  # type: ignore[misc]


def test_a_set_of_one_required_role_is_matched_whole(tmp_path):
    path = tmp_path / "one.toml"
    path.write_text(LAB.replace(REQUIRED, 'required = ["C7"]'))
    assert match_set(["C7"], load_set_definition(path)).score == 1.0


def test_defaults_of_a_set_file(tmp_path):
    path = tmp_path / "plain.toml"
    path.write_text('format = "gmr-markerset 1"\nrequired = ["KNE"]\n[roles.sided]\nKNE = "LKNE"\n')
    plain = load_set_definition(path)
    assert (plain.name, plain.title, plain.description) == ("plain", "plain", "")
    assert plain.roles == {"LKNE": ("LKNE",), "RKNE": ("RKNE",)} and plain.optional == ()


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (LAB.replace('format = "gmr-markerset 1"', 'format = "gmr-markerset 2"'), "format is 'gmr-markerset 2'"),
        (LAB.replace('format = "gmr-markerset 1"\n', ""), "format is None: expected 'gmr-markerset 1'"),
        (LAB.replace('sides = ["L_", "R_"]', 'sides = ["L_"]'), "sides must give the left and the right prefix"),
        (LAB.replace('sides = ["L_", "R_"]', 'sides = ["L_", "R_", "C_"]'), "sides must give the left and"),
        (LAB.replace('ASI = "L_ASIS"', 'ASI = "ASIS"'), "label 'ASIS' does not start with the left prefix 'L_'"),
        (LAB.replace('"L_KNEE", "L_KLAT+L_KMED"', '"L_KNEE", "R_KLAT+L_KMED"'), "sided role label 'R_KLAT'"),
        (LAB.replace('"PSI|SACR"', '"PSI|SACRUM|HIP"'), "required role SACRUM, HIP has no label in [roles]"),
        (LAB.replace("format", "format = = "), "not a readable marker-set TOML file"),
    ],
)
def test_bad_set_files(tmp_path, text, message):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(MotionFileError) as error:
        load_set_definition(path)
    assert message in str(error.value), str(error.value)


def test_an_unreadable_set_file(tmp_path):
    with pytest.raises(MotionFileError, match="not a readable marker-set TOML file"):
        load_set_definition(tmp_path / "absent.toml")
    latin = tmp_path / "latin.toml"
    latin.write_bytes(b'title = "caf\xe9"\n')
    with pytest.raises(MotionFileError, match="not a readable marker-set TOML file"):
        load_set_definition(latin)


# ------------------------------------------------------------------ matching
FULL = ["L_ASIS", "R_ASIS", "L_PSIS", "R_PSIS", "L_KNEE", "R_KLAT", "R_KMED", "C7", "R_ELB", "CLAV"]


def test_labels_matching_a_set_alternatives_and_means(lab):
    match = match_set(FULL, lab)
    assert match.complete and match.score == 1.0 and match.missing == ()
    assert match.found["LPSI"] == "L_PSIS" and match.found["SACR"] == "L_PSIS+R_PSIS"
    assert match.found["RKNE"] == "R_KLAT+R_KMED" and match.found["LKNE"] == "L_KNEE"
    assert match.optional == ("RELB", "CLAV")
    assert match.summary() == "lab (A lab's set), with ELB, CLAV"
    assert match_set([*FULL, "RBAK"], lab).summary() == "lab (A lab's set), with ELB, CLAV, RBAK"


def test_missing_labels_are_the_first_alternatives_of_the_groups_absent(lab):
    match = match_set(["L_ASIS", "R_KLAT", "SACR", "L_TOE", "R_TOE"], lab)
    assert not match.complete
    assert match.missing == ("R_ASIS", "L_KNEE", "R_KNEE", "C7")  # a group's first alternative
    assert match.score == pytest.approx(2 / 6)
    assert match.summary() == "lab (A lab's set), with TOE; missing R_ASIS, L_KNEE, R_KNEE, C7"
    half_mean = match_set(["L_ASIS", "R_ASIS", "L_KNEE", "R_KNEE", "C7", "L_PSIS"], lab)
    assert half_mean.complete and "SACR" not in half_mean.found  # R_PSIS lacks for the mean
    assert match_set([], lab).missing == ("L_ASIS", "R_ASIS", "L_PSIS", "L_KNEE", "R_KNEE", "C7")


def test_a_group_present_once_is_counted_once_and_a_label_missed_twice_listed_once(tmp_path):
    path = tmp_path / "twice.toml"
    path.write_text(LAB.replace(REQUIRED, 'required = ["C7", "C7|CLAV", "ASI"]'))
    twice = load_set_definition(path)
    assert match_set(["L_ASIS", "R_ASIS"], twice).missing == ("C7",)
    only_clav = match_set(["CLAV", "L_ASIS", "R_ASIS"], twice)
    assert only_clav.score == pytest.approx(3 / 4) and only_clav.missing == ("C7",)


def test_a_set_without_required_roles_scores_nothing_found(tmp_path):
    path = tmp_path / "free.toml"
    path.write_text('format = "gmr-markerset 1"\n[roles.centre]\nC7 = "C7"\n')
    match = match_set(["C7"], load_set_definition(path))
    assert match.score == 0.0 and match.complete and match.found == {"C7": "C7"}


def definitions(tmp_path, **texts):
    out = []
    for name, text in texts.items():
        path = tmp_path / f"{name}.toml"
        path.write_text(text.replace('name = "lab"', f'name = "{name}"'))
        out.append(load_set_definition(path))
    return out


def test_the_ranking_complete_then_roles_then_fewer_missing_then_optional_then_order(tmp_path):
    lower = LAB.replace(REQUIRED, 'required = ["ASI", "KNE"]')
    more_optional = lower.replace('"RBAK"]', '"RBAK", "C7"]')  # C7 optional too
    full, small, extra = definitions(tmp_path, full=LAB, small=lower, extra=more_optional)
    labels = [label for label in FULL if label != "C7"]  # full misses C7: small and extra complete
    assert identify_marker_set(labels, [full, small]).definition.name == "small"
    assert identify_marker_set(FULL, [small, full]).definition.name == "full"  # more required roles
    assert identify_marker_set(FULL, [small, extra]).definition.name == "extra"  # C7 optional there
    assert identify_marker_set(FULL, [extra, extra]).definition is extra  # the first of equals
    no_knee = [label for label in FULL if "K" not in label]
    partial_full, partial_small = match_set(no_knee, full), match_set(no_knee, small)
    assert partial_full.score == pytest.approx(4 / 6) and partial_small.score == pytest.approx(2 / 4)
    assert identify_marker_set(no_knee, [small, full]).definition.name == "full"  # small below 0.6


def test_ranking_counts_roles_found_not_the_share(tmp_path):
    """Of two incomplete sets the one with more required roles present wins, though its share is
    lower; with as many, the one missing fewer labels."""
    many = LAB.replace(REQUIRED, 'required = ["ASI", "PSI|SACR", "KNE", "C7", "ELB"]')
    few = LAB.replace(REQUIRED, 'required = ["ASI", "KNE", "ELB"]')
    many_set, few_set = definitions(tmp_path, many=many, few=few)
    labels = ["L_ASIS", "R_ASIS", "L_PSIS", "L_KNEE", "R_KNEE", "C7"]  # no elbows
    assert match_set(labels, many_set).score == pytest.approx(6 / 8)
    assert match_set(labels, few_set).score == pytest.approx(4 / 6)
    assert identify_marker_set(labels, [few_set, many_set]).definition.name == "many"
    means = LAB.replace('KNE = ["L_KNEE", "L_KLAT+L_KMED"]', 'KNE = ["L_KLAT+L_KMED", "L_KNEE"]')
    plain, with_means = definitions(tmp_path, plain=LAB, means=means)
    no_knees = ["L_ASIS", "R_ASIS", "L_PSIS", "C7"]
    assert len(match_set(no_knees, with_means).missing) == 4 and len(match_set(no_knees, plain).missing) == 2
    assert identify_marker_set(no_knees, [with_means, plain]).definition.name == "plain"


def test_a_near_match_needs_six_tenths_of_the_required_roles(tmp_path):
    five = LAB.replace(REQUIRED, 'required = ["C7", "CLAV", "SACR", "C7|CLAV", "SACR|CLAV"]')
    (definition,) = definitions(tmp_path, five=five)
    assert identify_marker_set(["CLAV"], [definition]).score == 0.6  # three groups of five
    assert identify_marker_set(["C7"], [definition]) is None  # two of five


def test_markers_gapped_throughout_do_not_count(lab):
    labels = ["L_ASIS", "R_ASIS", "L_PSIS", "L_KNEE", "R_KNEE", "C7"]
    positions = np.ones((3, len(labels), 3))
    markers = MarkerSet(labels=labels, positions=positions, rate=10, units="mm")
    assert identify_marker_set(markers, [lab]).complete
    positions[:, 5] = np.nan
    positions[1, 4] = np.nan  # seen in other frames: counts
    gapped = MarkerSet(labels=labels, positions=positions, rate=10, units="mm")
    assert identify_marker_set(gapped, [lab]).missing == ("C7",)
    empty = MarkerSet(labels=labels, positions=np.zeros((0, 6, 3)), rate=10, units="mm")
    assert identify_marker_set(empty, [lab]) is None


def test_role_positions_take_the_label_or_the_mean(lab):
    labels = ["L_ASIS", "R_ASIS", "L_PSIS", "R_PSIS", "L_KNEE", "R_KLAT", "R_KMED", "C7"]
    positions = np.arange(2 * 8 * 3, dtype=float).reshape(2, 8, 3)
    markers = MarkerSet(labels=labels, positions=positions, rate=10, units="mm")
    roles = role_positions(markers, match_set(labels, lab))
    np.testing.assert_array_equal(roles["LKNE"], positions[:, 4])
    np.testing.assert_array_equal(roles["RKNE"], (positions[:, 5] + positions[:, 6]) / 2)
    np.testing.assert_array_equal(roles["SACR"], (positions[:, 2] + positions[:, 3]) / 2)
    assert set(roles) == {"LASI", "RASI", "LPSI", "RPSI", "LKNE", "RKNE", "SACR", "C7"}


# ------------------------------------------------------------------ the shipped sets
def test_known_sets_by_name_or_file(tmp_path):
    assert known_sets() is known_sets()  # the files are read once
    names = [s.name for s in known_sets()]
    assert names == sorted(p.stem for p in SETS_DIR.glob("*.toml"))
    assert set_by_name("helen-hayes").title == "Helen Hayes (Kadaba et al. 1990)"
    path = tmp_path / "lab.toml"
    path.write_text(LAB)
    assert set_by_name(str(path)).name == "lab"
    with pytest.raises(MotionFileError, match="no marker set of that name: known sets are cgm2, cmu, helen-hayes"):
        set_by_name("lab")


def test_no_match_text_names_the_three_nearest_sets_their_labels_matched_and_missing():
    """The three nearest sets, each with the share of its required markers present, the
    file's labels it matched and (eight at most, then a count) the labels it misses; then
    how to convert the markers anyway: a skeleton and a marker map of one's own (--map)."""
    text = no_match_text(["LASI", "RASI", "SACR", "LKNE", "RKNE"])
    assert text.startswith(
        "no known marker set fits these labels (nearest: plug-in-gait-lower 38% (matched LASI, RASI, LKNE, RKNE, "
        "SACR; missing LTHI, RTHI, LTIB, RTIB, LANK, RANK, LTOE, RTOE); helen-hayes 33% (matched LASI, RASI, LKNE, "
        "RKNE, SACR; missing LTHI, RTHI, LTIB, RTIB, LANK, RANK, LHEE, RHEE (+2 more)); cgm2 26% (matched LASI, "
        "RASI, LKNE, RKNE, SACR; missing LTHI, RTHI, LKNM, RKNM, LTIB, RTIB, LANK, RANK (+6 more))). To convert "
        "them, give a skeleton and a marker map of your own: gmr markers FILE --skeleton S.asf|S.bvh --map MAP.toml"
    )
    assert text.endswith("see docs/markers.md, 'Marker maps'")
    rounded = no_match_text(["LASI", "RASI", "LPSI", "RPSI", "LTHI", "RTHI", "LKNE", "RKNE"])  # 7 of 13: 53.8%
    assert rounded.startswith("no known marker set fits these labels (nearest: plug-in-gait-lower 54% (matched ")
    assert "; in the file but never seen: LHEE, RHEE)" in no_match_text(["LASI"], ["LHEE", "RHEE"])
