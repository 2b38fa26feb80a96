"""Skeleton from markers (issue 22): joint-centre formulas against hand-worked examples, the
exact case for every marker set (markers generated from a known skeleton and motion give that
motion back), the refinement, and missing markers named."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.core.errors import OperationError
from gmr_studio.core.kinematics.fk import world_positions
from gmr_studio.core.markers import joint_centres as jc
from gmr_studio.core.markers.build import SYNONYMS, build_skeleton, functional_centre
from gmr_studio.core.markers.built_motion import markers_to_built_motion
from gmr_studio.core.markers.limbs import about_axis
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.markers.refine import refine_motion
from gmr_studio.core.markers.sets import identify_marker_set, known_sets, set_by_name
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


# ------------------------------------------------------------------ bone lengths
def test_a_bones_spread_is_the_rms_about_its_fitted_median_length():
    """The toe marker slid 4 mm out along the foot at three of eight frames (a one-sided
    slide, where the mean and the median differ): the toe bone keeps its rigid length (the
    median) and its spread is the RMS about that length, 4 * sqrt(3/8) mm, not the standard
    deviation about the mean (4 * sqrt(15)/8 mm)."""
    markers, joints = generated_markers("helen-hayes", n_frames=8, seed=4)
    built = build_skeleton(markers)
    j = built.skeleton.joint_index("LTOE")
    foot = joints["LTOE"] - joints["LAJC"]
    foot /= np.linalg.norm(foot, axis=1, keepdims=True)
    out = np.array([0.0, 4.0, 0.0, 0.0, 4.0, 0.0, 4.0, 0.0])
    positions = markers.positions.copy()
    positions[:, markers.index("LTOE")] += out[:, None] * foot
    moved = build_skeleton(markers.replace(positions=positions))
    assert moved.lengths[j] == pytest.approx(built.lengths[j], rel=1e-12)
    assert moved.spread[j] == pytest.approx(4.0 * np.sqrt(3 / 8), rel=1e-9)


def test_walking5s_knee_spreads_are_the_rms_about_the_median_lengths():
    """On a real gait trial, whose thigh lengths lean to one side (their mean 1.4-1.6 mm
    above their median), each spread is the RMS of the measured lengths about the fitted
    one, recomputed here from the joint centres."""
    from gmr_studio.core.markers import read_markers
    from tests.conftest import shared_path

    built = build_skeleton(read_markers(shared_path("c3d/opensim-core_walking5.c3d")))
    for name in ("LKJC", "RKJC"):
        j = built.skeleton.joint_index(name)
        lengths = np.linalg.norm(built.centres[:, j] - built.centres[:, built.skeleton.parents[j]], axis=1)
        lengths = lengths[np.isfinite(lengths)]
        assert built.lengths[j] == pytest.approx(np.median(lengths), rel=1e-12)
        assert built.spread[j] == pytest.approx(np.sqrt(np.mean((lengths - np.median(lengths)) ** 2)), rel=1e-9)


def test_a_pelvis_never_seen_whole_is_an_error_naming_its_markers_not_a_crash():
    """The Vicon gait trial with its pelvis markers mostly hidden (LASI missing in frames
    0-49, RASI in 50-99, SACR from 100 on: never all three in one frame): an OperationError
    saying how much of each is missing and what to do, not numpy's All-NaN ValueError."""
    from gmr_studio.core.markers import read_markers
    from tests.conftest import shared_path

    markers = read_markers(shared_path("c3d/c3dorg_s03_gait-pig.c3d"))
    positions = markers.positions.copy()
    for label, frames in (("LASI", slice(0, 50)), ("RASI", slice(50, 100)), ("SACR", slice(100, None))):
        positions[frames, markers.index(label)] = np.nan
    with pytest.raises(OperationError) as error:
        markers_to_built_motion(markers.replace(positions=positions))
    assert str(error.value).startswith(
        "the pelvis is in no frame: its markers are never seen together (missing: LASI 55%, RASI 55%, SACR 30% of "
        "the 142 frames)"
    )
