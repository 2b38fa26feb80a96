"""Skeleton from markers (core/markers/build.py): joint-centre formulas against hand-worked
examples, the exact case for every marker set (markers generated from a known skeleton and
motion give that motion back), the refinement, missing markers named; the rest pose's bone
directions, the root alone translating, the bone lengths' spread and span, the subject's
widths, and the pelvis or a leg the markers cannot place."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.errors import OperationError
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers import joint_centres as jc
from gmr_studio.core.markers.build import (
    DEFAULT_WIDTHS,
    SYNONYMS,
    build_skeleton,
    functional_centre,
    joint_centre_trajectories,
)
from gmr_studio.core.markers.built_motion import markers_to_built_motion
from gmr_studio.core.markers.limbs import about_axis
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.markers.refine import refine_motion
from gmr_studio.core.markers.sets import identify_marker_set, known_sets, match_set, set_by_name
from gmr_studio.core.rotations.euler import nearest_rotation


# ------------------------------------------------------------------ formulas, by hand
def test_harrington_by_hand():
    # PW 250, PD 150 mm: x = -0.24*150 - 9.9 = -45.9, superior = -0.30*250 - 10.9 = -85.9,
    # lateral = 0.33*250 + 7.3 = 89.8 (Harrington et al. 2007, right hip, ISB z to the right)
    hips = jc.hip_harrington(250.0, 150.0)
    assert np.allclose(hips[0], [-45.9, 89.8, -85.9], atol=1e-12)  # left: y (left) positive
    assert np.allclose(hips[1], [-45.9, -89.8, -85.9], atol=1e-12)


def test_davis_by_hand():
    # leg 900, ASIS distance 250, marker radius 7: C = 88.2, X_dis + r = 74.36;
    # x = 88.2 cos .5 sin .314 - 74.36 cos .314 = 23.90708 - 70.72385 = -46.81677
    # y = 125 - 88.2 sin .5 = 125 - 42.28533 = 82.71467
    # z = -88.2 cos .5 cos .314 - 74.36 sin .314 = -73.61783 - 22.96724 = -96.58507
    hips = jc.hip_davis(900.0, 250.0, 7.0)
    assert np.allclose(hips[0], [-46.81677, 82.71467, -96.58507], atol=2e-5)
    assert np.allclose(hips[1], [-46.81677, -82.71467, -96.58507], atol=2e-5)


def test_pelvis_frame_by_hand():
    origin, frame = jc.pelvis_frame(np.array([10.0, 125, 0]), np.array([10.0, -125, 0]), np.array([-140.0, 0, 0]))
    assert np.allclose(origin, [10, 0, 0]) and np.allclose(frame, np.eye(3), atol=1e-15)


def test_chord_by_hand():
    # knee centre at 0, lateral knee marker 60 mm to the side, hip 400 mm above: the angle
    # hip-centre-marker is right; the thigh wand is lateral, above the knee
    centre = jc.chord(np.array([0.0, 0, 400]), np.array([0.0, 60, 0]), np.array([0.0, 100, 150]), 60.0)
    assert np.allclose(centre, 0.0, atol=1e-12)


def test_chord_properties_on_random_triangles():
    rng = np.random.default_rng(4)
    p, lateral = rng.normal(size=(50, 3)) * 300, rng.normal(size=(50, 3)) * 300
    wand = rng.normal(size=(50, 3)) * 300
    delta = rng.uniform(20, 60, 50)
    centre = jc.chord(p, lateral, wand, delta)
    assert np.allclose(np.linalg.norm(centre - lateral, axis=1), delta)  # at delta from the marker
    assert np.allclose(np.sum((p - centre) * (lateral - centre), axis=1), 0, atol=1e-8)  # right angle
    normal = np.cross(lateral - p, wand - p)
    assert np.allclose(np.sum((centre - p) * normal, axis=1), 0, atol=1e-6)  # in the plane
    side_wand = np.sum(np.cross(lateral - p, wand - p) * normal, axis=1)
    side_centre = np.sum(np.cross(lateral - p, centre - p) * normal, axis=1)
    assert (np.sign(side_wand) != np.sign(side_centre)).all()  # away from the wand


def test_shoulder_rab_by_hand():
    up = np.array([0.0, 0, 1])
    centre = jc.shoulder_rab(np.array([0.0, 200, 1400]), np.array([0.0, -200, 1400]), up)
    assert np.allclose(centre, [0, 200, 1400 - 0.17 * 400])


# ------------------------------------------------------------------ generated markers
#: canonical role -> (segment, local offset for the LEFT side in the segment frame: x forward,
#: y left, z up at rest), placed so each formula gives its joint centre back exactly
WIDTH, RADIUS = 100.0, 7.0
DELTA = WIDTH / 2 + RADIUS
LOCAL = {
    "ASI": ("pelvis", (0.0, 125.0, 0.0)),
    "PSI": ("pelvis", (-150.0, 45.0, 0.0)),
    "SACR": ("pelvis", (-150.0, 0.0, 0.0)),
    "THI": ("thigh", (0.0, DELTA + 40.0, 150.0)),
    "KNE": ("thigh", (0.0, DELTA, 0.0)),
    "KNM": ("thigh", (0.0, -DELTA, 0.0)),
    "TH1": ("thigh", (30.0, 50.0, 200.0)),
    "TH2": ("thigh", (40.0, 60.0, 120.0)),
    "TH3": ("thigh", (-20.0, 70.0, 160.0)),
    "TIB": ("shank", (0.0, DELTA + 30.0, 150.0)),
    "ANK": ("shank", (0.0, DELTA, 0.0)),
    "MED": ("shank", (0.0, -DELTA, 0.0)),
    "TB1": ("shank", (40.0, 30.0, 200.0)),
    "TB2": ("shank", (50.0, 10.0, 150.0)),
    "TB3": ("shank", (30.0, 40.0, 100.0)),
    "TOE": ("foot", (150.0, 0.0, -40.0)),
    "HEE": ("foot", (-60.0, 0.0, -50.0)),
    "MT5": ("foot", (110.0, 40.0, -45.0)),
    "FM5": ("foot", (105.0, 45.0, -45.0)),
    "C7": ("thorax", (-80.0, 0.0, 0.0)),
    "CLAV": ("thorax", (80.0, 0.0, 0.0)),
    "T10": ("thorax", (-90.0, 0.0, -200.0)),
    "STRN": ("thorax", (90.0, 0.0, -180.0)),
    "RBAK": ("thorax", (-100.0, -80.0, -100.0)),
    "SHO": ("thorax", (0.0, 180.0, 30.0)),
    "FHD": ("head", (70.0, 60.0, 0.0)),
    "BHD": ("head", (-70.0, 60.0, 0.0)),
    "UPA": ("upperarm", (0.0, DELTA + 30.0, 120.0)),
    "ELB": ("upperarm", (0.0, DELTA, 0.0)),
    "ELM": ("upperarm", (0.0, -DELTA, 0.0)),
    "FRA": ("forearm", (20.0, 40.0, 120.0)),
    "WRA": ("forearm", (0.0, 30.0, 0.0)),
    "WRB": ("forearm", (0.0, -30.0, 0.0)),
    "FIN": ("hand", (0.0, 0.0, -80.0)),
}
CENTRE_ROLES = ("SACR", "C7", "CLAV", "T10", "STRN", "RBAK")


def _pose(n_frames: int, rng) -> dict[str, np.ndarray]:
    """World rotations (F, 3, 3) of every segment, near a standing pose."""

    def turn(scale):
        return nearest_rotation(np.eye(3) + rng.normal(scale=scale, size=(n_frames, 3, 3)))

    base = turn(3.0)  # any orientation of the whole body
    segments = {"pelvis": base}
    for side in "LR":
        segments[side + "thigh"] = base @ turn(0.3)
        knee = about_axis(np.array([0.0, 1, 0]), rng.uniform(0, 1.2, n_frames))
        segments[side + "shank"] = segments[side + "thigh"] @ knee
        segments[side + "foot"] = segments[side + "shank"] @ turn(0.2)
    segments["thorax"] = base @ turn(0.2)
    segments["head"] = segments["thorax"] @ turn(0.2)
    for side in "LR":
        segments[side + "upperarm"] = segments["thorax"] @ turn(0.4)
        segments[side + "forearm"] = segments[side + "upperarm"] @ turn(0.4)
        segments[side + "hand"] = segments[side + "forearm"] @ turn(0.2)
    return segments


def generated_markers(set_name: str, n_frames: int = 6, seed: int = 0):
    """Markers of a set, generated from a known pose so that every formula is exact; and the
    true joint centres (name -> (F, 3)) they define."""
    definition = set_by_name(set_name)
    rng = np.random.default_rng(seed)
    seg = _pose(n_frames, rng)
    origin = rng.normal(scale=500.0, size=(n_frames, 3))

    def place(segment, centre, local, side):
        v = np.array(local) * (1, -1 if side == "R" else 1, 1)
        return centre + np.einsum("fab,b->fa", seg[segment], v)

    hips = jc.hip_harrington(250.0, 150.0)
    joints = {"pelvis_front": origin}
    for side in "LR":
        hjc = joints[side + "HJC"] = place("pelvis", origin, hips[0], side)
        kjc = joints[side + "KJC"] = place(side + "thigh", hjc, (0, 0, -420.0), side)
        ajc = joints[side + "AJC"] = place(side + "shank", kjc, (0, 0, -400.0), side)
        joints[side + "TOE"] = place(side + "foot", ajc, LOCAL["TOE"][1], side)
    joints["pelvis"] = 0.5 * (joints["LHJC"] + joints["RHJC"])
    thorax = joints["thorax"] = place("thorax", joints["pelvis"], (0, 0, 500.0), "")
    joints["head"] = place("head", thorax, (0, 0, 200.0), "")
    for side in "LR":
        sjc = joints[side + "SJC"] = place("thorax", thorax, (0, 180.0, 30.0 - 0.17 * 360.0), side)
        ejc = joints[side + "EJC"] = place(side + "upperarm", sjc, (0, 0, -280.0), side)
        wjc = joints[side + "WJC"] = place(side + "forearm", ejc, (0, 0, -250.0), side)
        joints[side + "HAND"] = place(side + "hand", wjc, LOCAL["FIN"][1], side)
    labels, columns = [], []
    for role, (segment, local) in LOCAL.items():
        sides = [""] if role in CENTRE_ROLES else ["L", "R"]
        for side in sides:
            name = _set_role(definition, role, side)
            if name is None:
                continue
            base = {
                "pelvis": "pelvis_front", "thigh": "KJC", "shank": "AJC", "foot": "AJC", "thorax": "thorax",
                "head": "head", "upperarm": "EJC", "forearm": "WJC", "hand": "WJC",
            }[segment]  # fmt: skip
            base = joints[base] if base in joints else joints[side + base]
            segname = segment if segment in ("pelvis", "thorax", "head") else side + segment
            for label in definition.labels_of(name):
                if "+" not in label:
                    labels.append(label)
                    columns.append(place(segname, base, local, side))
                    break
    markers = MarkerSet(
        labels=labels, positions=np.stack(columns, axis=1), rate=100.0, units="mm",
        parameters={"KneeWidth": WIDTH, "AnkleWidth": WIDTH, "ElbowWidth": WIDTH, "MarkerDiameter": 2 * RADIUS},
    )  # fmt: skip
    return markers, joints


def _set_role(definition, role: str, side: str) -> str | None:
    """The set's role for a canonical role (through the builder's synonyms), or None."""
    for name in SYNONYMS.get(role, (role,)):
        if side + name in definition.roles and all("+" not in label for label in definition.labels_of(side + name)):
            return side + name
    return None


BUILDABLE = [
    "plug-in-gait-lower", "plug-in-gait-full", "cgm2", "helen-hayes", "cmu", "opensim-rajagopal", "qualisys-sports",
]  # fmt: skip


def test_every_set_file_is_covered():
    assert {s.name for s in known_sets()} == {*BUILDABLE, "opensim-gait2392"}


@pytest.mark.parametrize("set_name", BUILDABLE)
@pytest.mark.parametrize("refine", [False, True])
@pytest.mark.parametrize("root_at", ["pelvis", "fit"])
def test_exact_case_every_set(set_name, refine, root_at):
    markers, joints = generated_markers(set_name)
    assert identify_marker_set(markers).definition.name == set_name or set_name == "plug-in-gait-lower"
    built = markers_to_built_motion(markers, refine=refine, iterations=3, root_at=root_at)
    motion = built.result.motion
    positions = world_positions(motion)
    size = max(np.ptp(positions[0], axis=0))
    worst = 0.0
    for j, name in enumerate(motion.names):
        worst = max(worst, np.abs(positions[:, j] - joints[name]).max())
    assert worst <= 1e-9 * size, (set_name, worst)
    assert np.nanmax(built.built.spread) < 1e-9 * size  # constant bone lengths, fitted exactly
    if refine:
        assert np.nanmax(built.refinement.residuals) < 1e-9 * size


def test_refinement_recovers_a_perturbed_pose():
    markers, _ = generated_markers("plug-in-gait-full", seed=3)
    built = markers_to_built_motion(markers)
    motion = built.result.motion
    rng = np.random.default_rng(1)
    noisy = motion.rotations @ nearest_rotation(np.eye(3) + rng.normal(scale=0.05, size=motion.rotations.shape))
    seed = motion.replace(rotations=noisy)
    targets = world_positions(motion)
    bones = np.arange(motion.n_joints)
    offsets = np.where((bones == motion.roots[0])[:, None], 0.0, motion.offsets)
    result = refine_motion(seed, targets, bones, offsets, iterations=20)
    assert result.residuals_before.max() > 1.0
    assert np.abs(world_positions(result.motion) - targets).max() < 1e-8


# ------------------------------------------------------------------ messages
def test_missing_markers_are_named():
    markers, _ = generated_markers("plug-in-gait-full")
    keep = [label for label in markers.labels if label not in ("LKNE", "RWRB")]
    with pytest.raises(OperationError, match="miss LKNE, RWRB"):
        build_skeleton(markers.select(keep))


def test_a_set_without_knee_markers_says_why():
    labels = ["L.ASIS", "R.ASIS", "V.Sacral", "L.Heel", "R.Heel", "L.Toe.Tip", "R.Toe.Tip"]
    labels += [f"{s}.{seg}.{part}" for s in "LR" for seg in ("Thigh", "Shank") for part in ("Upper", "Front", "Rear")]
    fake = MarkerSet(labels=labels, positions=np.random.default_rng(0).normal(size=(3, 19, 3)), rate=60.0, units="mm")
    assert identify_marker_set(fake).definition.name == "opensim-gait2392"
    with pytest.raises(OperationError, match=r"no lateral knee and ankle markers.*three markers on each of thigh"):
        build_skeleton(fake)  # two foot markers only: no functional ankle either


def test_functional_centre_of_a_ball_joint_is_exact():
    # two clusters turning about a common point (a ball joint): SCoRE finds it in every frame
    rng = np.random.default_rng(2)
    n_frames = 30
    centre = rng.normal(scale=300.0, size=(n_frames, 3))
    near = nearest_rotation(np.eye(3) + rng.normal(scale=0.6, size=(n_frames, 3, 3)))
    far = nearest_rotation(np.eye(3) + rng.normal(scale=0.6, size=(n_frames, 3, 3)))
    proximal_local = np.array([[0.0, 50, 200], [40, -30, 150], [-50, 10, 250]])
    distal_local = np.array([[30.0, 40, -150], [-40, 30, -220], [10, -50, -100], [0, 0, -300]])
    proximal = centre[:, None] + np.einsum("fab,kb->fka", near, proximal_local)
    distal = centre[:, None] + np.einsum("fab,kb->fka", far, distal_local)
    found = functional_centre(proximal, distal)
    assert np.abs(found - centre).max() < 1e-8


def test_no_known_set_lists_what_a_map_needs():
    strange = MarkerSet(labels=["A", "B", "C"], positions=np.zeros((2, 3, 3)), rate=50.0, units="mm")
    assert identify_marker_set(strange) is None
    with pytest.raises(OperationError, match=r"no known marker set fits.*ASIS"):
        build_skeleton(strange)


def test_davis_hips_place_the_generated_pelvis():
    # the leg length as a parameter, the ASIS distance from the markers: the built hips are
    # Davis's offsets in the pelvis frame
    markers, joints = generated_markers("plug-in-gait-lower")
    markers = markers.replace(parameters={**markers.parameters, "LegLength": 880.0})
    built = build_skeleton(markers, hip="davis")
    local = jc.hip_davis(880.0, 250.0, RADIUS)
    origin = joints["pelvis_front"]
    hips = built.centres[:, [built.skeleton.joint_index("LHJC"), built.skeleton.joint_index("RHJC")]]
    lasi = markers.positions[:, markers.index("LASI")]
    rasi = markers.positions[:, markers.index("RASI")]
    psi = 0.5 * (markers.positions[:, markers.index("LPSI")] + markers.positions[:, markers.index("RPSI")])
    _, frame = jc.pelvis_frame(lasi, rasi, psi)
    assert np.allclose(hips, origin[:, None] + np.einsum("fab,kb->fka", frame, local), atol=1e-9)


def test_davis_hips_without_a_leg_length_measure_it():
    # no LegLength parameter: the leg is the median ASIS-knee-ankle length of the markers
    markers, _ = generated_markers("plug-in-gait-lower")
    assert "LegLength" not in markers.parameters
    lasi, kne, ank = (markers.positions[:, markers.index(label)] for label in ("LASI", "LKNE", "LANK"))
    leg = np.median(np.linalg.norm(lasi - kne, axis=1) + np.linalg.norm(kne - ank, axis=1))
    built = build_skeleton(markers, hip="davis")
    with_leg = build_skeleton(markers.replace(parameters={**markers.parameters, "LegLength": leg}), hip="davis")
    assert np.allclose(built.centres, with_leg.centres, atol=1e-9, equal_nan=True)
    assert any("no LegLength parameter" in note for note in built.notes)


def test_hidden_pelvis_and_medial_markers_are_carried_by_their_segment():
    # a hidden ASIS is placed by the other pelvis markers, a hidden medial knee marker by the
    # thigh's: the generated pose comes back exactly in those frames too
    markers, joints = generated_markers("cgm2", n_frames=8, seed=5)
    positions = markers.positions.copy()
    positions[[2, 5], markers.index("LASI")] = np.nan
    positions[[1, 3, 6], markers.index("RKNM")] = np.nan
    built = markers_to_built_motion(markers.replace(positions=positions))
    assert built.result.frame_valid.all()
    motion = built.result.motion
    result = world_positions(motion)
    size = max(np.ptp(result[0], axis=0))
    for j, name in enumerate(motion.names):
        assert np.abs(result[:, j] - joints[name]).max() <= 1e-9 * size, name


DOWN = ("LKJC", "LAJC", "RKJC", "RAJC", "LEJC", "LWJC", "LHAND", "REJC", "RWJC", "RHAND")


@pytest.fixture(scope="module")
def full_body():
    markers, _ = generated_markers("plug-in-gait-full", n_frames=6, seed=2)
    return markers, build_skeleton(markers)


def test_the_rest_pose_hangs_legs_and_arms_below_the_trunk(full_body):
    _, built = full_body
    skeleton = built.skeleton
    offsets = np.asarray(skeleton.offsets)
    up = offsets[skeleton.joint_index("thorax")] / np.linalg.norm(offsets[skeleton.joint_index("thorax")])
    assert np.count_nonzero(np.abs(up) > 1e-12) == 1  # one of the file's axes
    for name in DOWN:
        j = skeleton.joint_index(name)
        np.testing.assert_allclose(offsets[j], -built.lengths[j] * up, atol=1e-9, err_msg=name)
    np.testing.assert_allclose(np.linalg.norm(offsets[1:], axis=1), built.lengths[1:], rtol=1e-12)


def test_the_root_alone_translates_at_the_markers_rate_and_the_source_is_named(full_body):
    markers, built = full_body
    skeleton = built.skeleton
    assert skeleton.has_translation.tolist() == [True] + [False] * (skeleton.n_joints - 1)
    assert skeleton.frame_time == pytest.approx(1 / markers.rate, rel=1e-15)
    assert skeleton.comments == ("skeleton built from the markers of (memory), set plug-in-gait-full",)
    named = build_skeleton(markers.replace(source="walk.c3d", rate=250.0))
    assert named.skeleton.comments[0] == "skeleton built from the markers of walk.c3d, set plug-in-gait-full"
    assert named.skeleton.frame_time == pytest.approx(1 / 250.0, rel=1e-15)


def test_a_bones_length_is_the_median_its_spread_the_rms_about_it_and_its_span_5_to_95(rng):
    """The toe marker slid along the foot by +d and -d in turn: the toe bone's length is the
    rigid one, its spread d, its span the 5th and 95th percentiles."""
    markers, joints = generated_markers("helen-hayes", n_frames=8, seed=4)
    built = build_skeleton(markers)
    j = built.skeleton.joint_index("LTOE")
    rigid = built.lengths[j]
    assert built.spread[j] < 1e-9
    foot = joints["LTOE"] - joints["LAJC"]
    foot /= np.linalg.norm(foot, axis=1, keepdims=True)
    slide = 3.0 * np.array([1.0, -1.0] * 4)[:, None] * foot
    positions = markers.positions.copy()
    positions[:, markers.index("LTOE")] += slide
    moved = build_skeleton(markers.replace(positions=positions))
    assert moved.lengths[j] == pytest.approx(rigid, rel=1e-12)
    assert moved.spread[j] == pytest.approx(3.0, rel=1e-9)
    np.testing.assert_allclose(moved.span[j], np.percentile(rigid + 3.0 * np.array([1.0, -1.0] * 4), [5, 95]))
    assert np.isnan(moved.lengths[0]) and np.isnan(moved.spread[0]) and np.isnan(moved.span[0]).all()


def test_the_rest_pose_stands_up_the_files_axis_nearest_the_pelvis_vertical(full_body):
    """z (up) of the rest pose is the file's axis nearest the pelvis frame's mean vertical, with
    its sign: for the markers as generated and turned a quarter about x (z to -y)."""
    from gmr_studio.core.markers import joint_centres as jc

    markers, _ = full_body
    quarter = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
    seen = set()
    for turned in (markers, markers.transformed(quarter)):
        lasi, rasi = (turned.positions[:, turned.index(n)] for n in ("LASI", "RASI"))
        psi = 0.5 * (turned.positions[:, turned.index("LPSI")] + turned.positions[:, turned.index("RPSI")])
        vertical = np.nanmean(jc.pelvis_frame(lasi, rasi, psi)[1][:, :, 2], axis=0)
        k = int(np.argmax(np.abs(vertical)))
        expected = np.zeros(3)
        expected[k] = np.sign(vertical[k])
        built = build_skeleton(turned)
        thorax = built.skeleton.joint_index("thorax")
        np.testing.assert_allclose(built.skeleton.offsets[thorax] / built.lengths[thorax], expected, atol=1e-12)
        seen.add(tuple(expected))
    assert len(seen) == 2


def test_span_is_the_5th_and_95th_percentiles_of_the_lengths():
    markers, joints = generated_markers("helen-hayes", n_frames=21, seed=4)
    j = build_skeleton(markers).skeleton.joint_index("LTOE")
    foot = joints["LTOE"] - joints["LAJC"]
    foot /= np.linalg.norm(foot, axis=1, keepdims=True)
    steps = 0.3 * np.arange(-10, 11)
    positions = markers.positions.copy()
    positions[:, markers.index("LTOE")] += steps[:, None] * foot
    moved = build_skeleton(markers.replace(positions=positions))
    rigid = moved.lengths[j]
    np.testing.assert_allclose(moved.span[j], rigid + np.percentile(steps, [5, 95]), rtol=1e-12)
    assert moved.spread[j] == pytest.approx(np.sqrt(np.mean(steps**2)), rel=1e-9)


def test_widths_by_side_then_in_general_else_assumed_and_said_once():
    """A knee's width is the side's (LKneeWidth, RightKneeWidth...), else the general one,
    else the assumed one (a width of 0 is none), said once in the notes: the knees and ankles
    placed by Plug-in Gait's chord, without medial markers."""
    markers, match = lower_body(drop=("LKNM", "RKNM", "LMED", "RMED"))

    def centres(**widths):
        found, _, _, notes = joint_centre_trajectories(markers.replace(parameters=widths), match)
        return found, [n for n in notes if "PROCESSING" in n]

    def same(a, b, name):
        np.testing.assert_array_equal(a[0][name], b[0][name], err_msg=name)

    by_side = centres(LKneeWidth=90.0, RightKneeWidth=110.0, KneeWidth=120.0, AnkleWidth=70.0)
    same(by_side, centres(KneeWidth=90.0, AnkleWidth=70.0), "LKJC")
    same(by_side, centres(KneeWidth=110.0, AnkleWidth=70.0), "RKJC")
    assert by_side[1] == []
    general = centres(LKneeWidth=95.0, RKneeWidth=0.0, KneeWidth=120.0, AnkleWidth=70.0)
    same(general, centres(KneeWidth=120.0, AnkleWidth=70.0), "RKJC")
    same(general, centres(KneeWidth=95.0, AnkleWidth=70.0), "LKJC")
    assert np.abs(general[0]["LKJC"] - by_side[0]["LKJC"]).max() > 1e-3  # the width places the centre
    assumed = centres(KneeWidth=0.5, AnkleWidth=0.0)  # any positive width; 0 is none
    same(assumed, centres(KneeWidth=0.5, AnkleWidth=DEFAULT_WIDTHS["AnkleWidth"]), "LAJC")
    assert assumed[1] == ["no AnkleWidth in the file's PROCESSING parameters: 70 mm assumed"]
    assert centres()[1] == [
        "no KneeWidth in the file's PROCESSING parameters: 100 mm assumed",
        "no AnkleWidth in the file's PROCESSING parameters: 70 mm assumed",
    ]


def test_unknown_methods_are_refused():
    markers, _ = generated_markers("helen-hayes", n_frames=2)
    with pytest.raises(ValueError, match=r"hip 'bell' or knee 'functional': expected one of"):
        build_skeleton(markers, hip="bell")
    with pytest.raises(ValueError, match=r"hip 'harrington' or knee 'hinge'"):
        build_skeleton(markers, knee="hinge")


def lower_body(drop=(), add=None):
    markers, _ = generated_markers("plug-in-gait-lower", n_frames=4, seed=6)
    keep = [label for label in markers.labels if label not in drop]
    markers = markers.select(keep)
    if add:
        for label, values in add.items():
            markers = markers.replace(
                labels=(*markers.labels, label), subjects=(*markers.subjects, ""),
                positions=np.concatenate([markers.positions, values[:, None]], axis=1),
            )  # fmt: skip
    return markers, match_set(markers.labels, set_by_name("plug-in-gait-lower"))


@pytest.mark.parametrize("hidden", ["LPSI", "RPSI"])
def test_a_sacral_marker_stands_in_for_a_psis_hidden_throughout(hidden):
    full, match = lower_body()
    sacrum = 0.5 * (full.positions[:, full.index("LPSI")] + full.positions[:, full.index("RPSI")])
    markers, match = lower_body(drop=(hidden,), add={"SACR": sacrum})
    centres = joint_centre_trajectories(markers, match)[0]
    expected = joint_centre_trajectories(full, match_set(full.labels, set_by_name("plug-in-gait-lower")))[0]
    for name in ("LHJC", "RHJC", "pelvis"):
        np.testing.assert_allclose(centres[name], expected[name], atol=1e-9)


@pytest.mark.parametrize("drop", [("LASI",), ("RASI",), ("LPSI",), ("RPSI",), ("LASI", "LPSI"), ("RASI", "LPSI")])
def test_a_pelvis_the_markers_cannot_place_is_refused(drop):
    """An ASIS missing throughout, or a PSIS without a sacral marker; with the sacral marker
    standing in for the PSIS, an ASIS missing still."""
    full, _ = lower_body()
    sacrum = 0.5 * (full.positions[:, full.index("LPSI")] + full.positions[:, full.index("RPSI")])
    markers, match = lower_body(drop=drop, add={"SACR": sacrum} if len(drop) == 2 else None)
    with pytest.raises(
        OperationError, match=r"^set plug-in-gait-lower: the pelvis needs both ASIS and the PSIS or a sacral"
    ):
        joint_centre_trajectories(markers, match)


@pytest.mark.parametrize("drop", ["LANK", "LKNE"])
def test_a_leg_without_its_lateral_knee_or_ankle_marker_is_refused(drop):
    markers, match = lower_body(drop=(drop,))
    with pytest.raises(OperationError, match=r"^set plug-in-gait-lower has no lateral knee and ankle markers"):
        joint_centre_trajectories(markers, match)
