"""Marker map files and objects (core/markers/markermap.py): the alignment, the text written
and read back, every refusal of a bad file, the pelvis guesses and the built-in joints map."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gmr_studio.core.errors import MotionFileError
from gmr_studio.core.markers.markermap import (
    MAPS_DIR,
    MarkerMap,
    VirtualMarker,
    guess_pelvis,
    joints_map,
    load_marker_map,
    marker_map_text,
    save_marker_map,
)
from gmr_studio.core.space.similarity import Similarity
from tests.test_markers_map import SMALL_MAP

PERMUTATION = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])

SMALL = SMALL_MAP.lstrip("\n")  # the small map of tests/test_markers_map.py


def written(tmp_path, text: str, name: str = "map.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


# ------------------------------------------------------------------ objects
def test_virtual_markers_calibrated_and_the_maps_labels():
    assert VirtualMarker("a", "marker", ("A",)).calibrated and VirtualMarker("a", "mean", ("A", "B")).calibrated
    assert not VirtualMarker("c", "cluster", ("A", "B", "C")).calibrated
    assert not VirtualMarker("c", "cluster", ("A", "B", "C"), offset=np.zeros(3)).calibrated
    assert not VirtualMarker("c", "cluster", ("A", "B", "C"), template=np.zeros((3, 3))).calibrated
    assert VirtualMarker("c", "cluster", ("A", "B", "C"), np.zeros(3), np.zeros((3, 3))).calibrated
    marker_map = MarkerMap("m", (
        VirtualMarker("x", "mean", ("B", "A")), VirtualMarker("y", "cluster", ("@x", "A", "C", "B")),
    ))  # fmt: skip
    assert marker_map.labels() == ["B", "A", "C"] and marker_map.names == ("x", "y")
    assert marker_map.replace(name="n").name == "n" and marker_map.name == "m"


def test_guess_pelvis_is_case_insensitive_in_order_and_returns_the_names_as_given():
    assert guess_pelvis(["ROOT", "LHipJoint", "rhipjoint", "Hips", "LeftUpLeg", "RightUpLeg"]) == (
        "ROOT", "LHipJoint", "rhipjoint",
    )  # fmt: skip
    assert guess_pelvis(["Hips", "LeftUpLeg", "RightUpLeg"]) == ("Hips", "LeftUpLeg", "RightUpLeg")
    assert guess_pelvis(["hips", "lefthip", "RightHip"]) == ("hips", "lefthip", "RightHip")
    assert guess_pelvis(["pelvis", "l_hip", "r_hip"]) == ("pelvis", "l_hip", "r_hip")
    assert guess_pelvis(["Hips", "LeftUpLeg"]) is None


def test_the_joints_map():
    built = joints_map(["root", "lhipjoint", "rhipjoint", "knee"])
    assert built.joints and built.name == "joints" and built.names == ("root", "lhipjoint", "rhipjoint", "knee")
    assert all(v.kind == "marker" and v.markers == (v.name,) for v in built.virtual)
    assert built.pelvis == ("root", "lhipjoint", "rhipjoint")
    assert joints_map(["a", "b", "c"], pelvis=("c", "b", "a")).pelvis == ("c", "b", "a")
    assert joints_map(["a"]).pelvis is None
    named = load_marker_map("joints")
    assert named.joints and named.virtual == () and named.pelvis is None
    assert load_marker_map(built) is built


def test_maps_and_their_parts_are_frozen_and_compared_by_identity():
    alignment, virtual = Similarity(), VirtualMarker("x", "marker", ("A",))
    marker_map = MarkerMap("m", (virtual,))
    for thing, field in ((alignment, "scale"), (virtual, "name"), (marker_map, "name")):
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(thing, field, 2)
        assert thing != dataclasses.replace(thing) and len({thing, thing}) == 1
    assert not marker_map.joints  # a map is the built-in joints map only when made by joints_map


# ------------------------------------------------------------------ text
def full_map() -> MarkerMap:
    return MarkerMap(
        name='lab "A"\\1',
        description="two\nlines,\ttabbed\r, a bell \x07, a unit separator \x1f and a delete \x7f",
        units="cm",
        alignment=Similarity(PERMUTATION, 0.25, np.array([1.0, 2.0, 3.0])),
        pelvis=("hips", "left", "back"),
        pelvis_home=np.arange(9.0).reshape(3, 3),
        bone_starts={"knee": "left", "back": "hips"},
        calibration={"frames": "0:10", "rms mean": 0.5, "count": 3},
        virtual=(
            VirtualMarker("hips", "cluster", ("A", "B", "C"), np.array([0.5, -1.0, 2.0]), np.eye(3), 0.125),
            VirtualMarker("left", "mean", ("A", "B")),
            VirtualMarker("back", "marker", ("C",)),
            VirtualMarker("knee", "cluster", ("@left", "D", "E")),
            VirtualMarker("head top", "marker", ("F",)),
        ),
    )


def test_a_full_map_written_reads_back_the_same(tmp_path):
    original = full_map()
    path = tmp_path / "lab.toml"
    save_marker_map(original, path)
    again = load_marker_map(path)
    assert (again.name, again.description, again.units, again.pelvis) == (
        original.name, original.description, "cm", original.pelvis,
    )  # fmt: skip
    np.testing.assert_array_equal(again.pelvis_home, original.pelvis_home)
    np.testing.assert_array_equal(again.alignment.rotation, PERMUTATION)
    assert again.alignment.scale == 0.25
    np.testing.assert_array_equal(again.alignment.translation, [1.0, 2.0, 3.0])
    assert again.bone_starts == original.bone_starts and again.calibration == original.calibration
    assert again.names == original.names and [v.kind for v in again.virtual] == [v.kind for v in original.virtual]
    assert [v.markers for v in again.virtual] == [v.markers for v in original.virtual]
    hips = again.virtual[0]
    np.testing.assert_array_equal(hips.offset, [0.5, -1.0, 2.0])
    np.testing.assert_array_equal(hips.template, np.eye(3))
    assert hips.rms == 0.125 and again.virtual[3].offset is None and again.virtual[3].rms is None
    assert again.source == str(path)
    assert marker_map_text(again) == marker_map_text(original)


def test_the_text_of_a_map_line_by_line():
    text = marker_map_text(full_map())
    lines = text.splitlines()
    assert lines[:3] == [
        'format = "gmr-markermap 1"',
        'name = "lab \\"A\\"\\\\1"',
        'description = "two\\nlines,\\ttabbed\\r, a bell \\u0007, a unit separator \\u001f and a delete \\u007f"',
    ]
    assert 'units = "cm"' in lines
    assert "rotation = [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]" in lines
    assert "scale = 0.25" in lines and "offset = [1.0, 2.0, 3.0]" in lines
    assert 'markers = ["hips", "left", "back"]' in lines
    assert "home = [[0.0, 1.0, 2.0], [3.0, 4.0, 5.0], [6.0, 7.0, 8.0]]" in lines
    assert lines[lines.index("[bones]") + 1 : lines.index("[bones]") + 3] == ['knee = "left"', 'back = "hips"']
    at = lines.index("[calibration]")
    assert lines[at + 1 : at + 4] == ['frames = "0:10"', '"rms mean" = 0.5', "count = 3.0"]
    at = lines.index("[virtual.hips]")
    assert lines[at + 1 : at + 5] == [
        'cluster = ["A", "B", "C"]', "offset = [0.5, -1.0, 2.0]",
        "template = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]", "rms = 0.125",
    ]  # fmt: skip
    assert lines[lines.index("[virtual.left]") + 1] == 'mean = ["A", "B"]'
    assert lines[lines.index("[virtual.back]") + 1] == 'marker = "C"'
    assert lines[lines.index("[virtual.knee]") + 1 :][:2] == ['cluster = ["@left", "D", "E"]', ""]
    assert '[virtual."head top"]' in lines
    assert text.endswith('marker = "F"\n')


def test_a_plain_map_writes_no_optional_section():
    plain = MarkerMap("plain", (VirtualMarker("x", "marker", ("A",)),))
    assert marker_map_text(plain) == (
        'format = "gmr-markermap 1"\nname = "plain"\ndescription = ""\n\n'
        "# skeleton = scale * rotation @ marker + offset\n[alignment]\n"
        "rotation = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\nscale = 1.0\noffset = [0.0, 0.0, 0.0]\n\n"
        '[virtual.x]\nmarker = "A"\n'
    )
    homeless = MarkerMap("p", (VirtualMarker("x", "marker", ("A",)),), pelvis=("x", "x", "x"))
    text = marker_map_text(homeless)
    assert '[pelvis]\nmarkers = ["x", "x", "x"]\n\n[virtual.x]' in text and "home" not in text


def test_a_cluster_with_half_a_calibration_writes_none_of_it():
    half = MarkerMap("h", (VirtualMarker("c", "cluster", ("A", "B", "C"), offset=np.zeros(3)),))
    assert marker_map_text(half).endswith('[virtual.c]\ncluster = ["A", "B", "C"]\n')


def test_non_finite_numbers_are_written_as_strings():
    marker_map = MarkerMap("n", (VirtualMarker("x", "marker", ("A",)),), calibration={"rms": float("nan")})
    assert '\nrms = "nan"\n' in marker_map_text(marker_map)


# ------------------------------------------------------------------ reading
def test_a_map_by_name_path_or_object(tmp_path):
    assert load_marker_map("cmu").source == str(MAPS_DIR / "cmu.toml")
    path = written(tmp_path, SMALL, "small.toml")
    loaded = load_marker_map(str(path))
    assert loaded.name == "small" and loaded.units == "mm" and loaded.alignment.scale == 0.5
    assert loaded.description == "" and loaded.calibration == {} and loaded.bone_starts == {}
    assert loaded.pelvis_home is None
    unnamed = load_marker_map(written(tmp_path, SMALL.replace('name = "small"\n', ""), "nameless.toml"))
    assert unnamed.name == "nameless"
    bare = written(tmp_path, SMALL, "bare")  # a path without suffix that exists is read as a path
    assert load_marker_map(bare).name == "small"


def test_defaults_of_a_minimal_map(tmp_path):
    path = written(tmp_path, '[virtual.x]\nmarker = "A"\n', "minimal.toml")
    loaded = load_marker_map(path)
    assert loaded.name == "minimal" and loaded.units is None and loaded.pelvis is None
    assert loaded.alignment.is_identity and loaded.virtual[0].rms is None


def test_unreadable_files(tmp_path):
    with pytest.raises(MotionFileError, match="no marker map of that name: known maps are joints, asis-psis, cmu"):
        load_marker_map("nonesuch")
    with pytest.raises(MotionFileError, match=r"cannot read the marker map: No such file or directory$"):
        load_marker_map(tmp_path / "absent.toml")
    with pytest.raises(MotionFileError, match="cannot read the marker map"):
        load_marker_map(tmp_path)  # a folder
    binary = tmp_path / "latin.toml"
    binary.write_bytes(b'name = "caf\xe9"\n')
    with pytest.raises(MotionFileError, match="bytes that are not UTF-8 text"):
        load_marker_map(binary)


def test_a_toml_error_gives_its_line_and_column(tmp_path):
    with pytest.raises(MotionFileError) as error:
        load_marker_map(written(tmp_path, SMALL.replace("scale = 0.5", "scale = = 0.5")))
    assert (error.value.line, error.value.column) == (7, 9)
    assert "not valid TOML" in str(error.value) and "(at line" not in error.value.message


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (('format = "gmr-markermap 1"', 'format = "gmr-markermap 2"'), "format is 'gmr-markermap 2': expected"),
        (("scale = 0.5", 'scale = "half"'), "[alignment]"),
        (("scale = 0.5", "offset = [1.0, 2.0]"), "[alignment]: a similarity needs a positive scale"),
        (('markers = ["hips", "left", "back"]', 'markers = ["hips", "left"]'), "[pelvis] needs markers"),
        (('markers = ["hips", "left", "back"]', 'markers = "hips"'), "[pelvis] needs markers"),
        (('markers = ["hips", "left", "back"]', 'markers = ["hips", "left", 3]'), "[pelvis] needs markers"),
        (('markers = ["hips", "left", "back"]', 'mark = ["hips", "left", "back"]'), "[pelvis] needs markers"),
        (
            ('markers = ["hips", "left", "back"]', 'markers = ["hips", "left", "back"]\nhome = [[0, 0, 0]]'),
            "[pelvis] home must be three points of three numbers",
        ),
        (("[virtual.hips]", "[bones]\nknee = 3\n\n[virtual.hips]"), '[bones] needs JOINT = "START" lines'),
        (
            ("[virtual.hips]", '[bones]\nknee = "left"\nelbow = "hips"\nback = "wrist"\n\n[virtual.hips]'),
            "[bones] names virtual markers the map does not define: elbow = hips, back = wrist",
        ),
        (('marker = "C"', 'marker = ""'), "[virtual.back] marker must name markers"),
        (('mean = ["A", "B"]', "mean = []"), "[virtual.left] mean must name markers"),
        (('mean = ["A", "B"]', 'mean = ["A", 2]'), "[virtual.left] mean must name markers"),
        (
            ('cluster = ["A", "B", "C", "D"]', 'cluster = ["A", "B", "C", "D"]\noffset = [1, 2]'),
            "[virtual.hips] offset must be 3 numbers and template 4 points",
        ),
        (
            (
                'cluster = ["A", "B", "C", "D"]',
                'cluster = ["A", "B", "C", "D"]\noffset = [1, 2, 3]\ntemplate = [[1, 2, 3]]',
            ),
            "[virtual.hips] offset must be 3 numbers and template 4 points",
        ),
        (('cluster = ["@left", "E", "F"]', 'cluster = ["@knee", "E", "F"]'), "@knee, which is not an earlier"),
        (('cluster = ["A", "B", "C", "D"]', 'cluster = ["@hips", "A", "B"]'), "@hips, which is not an earlier"),
        (('marker = "C"', 'marker = "C"\ncluster = ["A", "B", "C"]'), "[virtual.back] needs exactly one of"),
        (('marker = "C"', 'markers = "C"'), "[virtual.back] needs exactly one of"),
    ],
)
def test_bad_map_files_are_refused_naming_the_fault(tmp_path, change, message):
    with pytest.raises(MotionFileError) as error:
        load_marker_map(written(tmp_path, SMALL.replace(*change)))
    assert message in str(error.value), str(error.value)


def test_a_map_without_virtual_markers_or_with_bones_that_are_no_table(tmp_path):
    with pytest.raises(MotionFileError, match=r"the map defines no \[virtual.NAME\] section"):
        load_marker_map(written(tmp_path, 'format = "gmr-markermap 1"\nname = "empty"\n'))
    with pytest.raises(MotionFileError, match='needs JOINT = "START" lines'):
        load_marker_map(written(tmp_path, SMALL.replace('name = "small"', 'name = "small"\nbones = 3'), "b.toml"))


def test_a_cluster_may_be_calibrated_with_an_offset_and_template_of_its_size(tmp_path):
    text = SMALL.replace(
        'cluster = ["@left", "E", "F"]',
        'cluster = ["@left", "E", "F"]\noffset = [1, 2, 3]\ntemplate = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\nrms = 2',
    )
    knee = load_marker_map(written(tmp_path, text)).virtual[3]
    assert knee.calibrated and knee.rms == 2.0 and type(knee.rms) is float
    np.testing.assert_array_equal(knee.offset, [1.0, 2.0, 3.0])
    assert knee.offset.dtype == np.float64 and knee.template.shape == (3, 3)
    only_offset = SMALL.replace('cluster = ["@left", "E", "F"]', 'cluster = ["@left", "E", "F"]\noffset = [1, 2, 3]')
    with pytest.raises(MotionFileError, match="offset must be 3 numbers and template 3 points"):
        load_marker_map(written(tmp_path, only_offset, "half.toml"))
