"""A skeleton built from the markers alone, then the paper's method onto it.

:func:`build_skeleton` recognises the marker set (:mod:`core.markers.sets`), places the joint
centres of every frame by the published methods (:mod:`core.markers.joint_centres`: hips by
Harrington et al. 2007 or Davis et al. 1991, knees and ankles by the medial/lateral midpoint
or Plug-in Gait's chord with the subject's widths, or functionally (SCoRE, Ehrig et al.
2006) between segment clusters for sets without knee and ankle markers; a knee whose thigh
and shank carry clusters of three markers is moved onto its functional flexion axis (SARA,
Ehrig et al. 2007, as CGM 2.x's functional knee) when the take flexes it enough; shoulders by Rab et
al. 2002, elbows and
wrists by their epicondyles, styloids or wrist bar), fits one constant length per bone (the
median over the frames, with its spread reported), and lays the bones out in a rest pose
(standing, facing the pelvis's anterior axis, up the file's vertical axis).
:func:`core.markers.built_motion.markers_to_built_motion` then runs the paper's closed form
(:func:`core.markers.solve.solve_positions`): pelvis by Procrustes, limb angles from the
joint-centre directions, each segment's twist from its third marker (the lateral knee for
the thigh, the lateral ankle for the shank, the heel for the foot, the lateral elbow for the
upper arm, the wrist bar for the forearm...) and from least change only where it has none.

Joints (``(F, J, 3)`` arrays follow this order, those the set cannot place left out):
``pelvis`` (root, mid-point of the hip centres, as Plug-in Gait's PELO), ``pelvis_front``
(mid-ASIS), ``LHJC``, ``LKJC``, ``LAJC``, ``LTOE`` and the right side, ``thorax`` (mid C7-CLAV),
``head`` (the head markers' centre), ``LSJC``, ``LEJC``, ``LWJC``, ``LHAND`` and the right side.
Units: millimetres; axes: the file's.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.errors import OperationError
from gmr_studio.core.markers import joint_centres as jc
from gmr_studio.core.markers.functional_joints import fill_from_cluster, functional_centre, knee_on_axis, most_seen
from gmr_studio.core.markers.limbs import swing
from gmr_studio.core.markers.markerset import MarkerSet, frame_ranges
from gmr_studio.core.markers.sets import SetMatch, identify_marker_set, match_set, no_match_text, role_positions
from gmr_studio.core.model.facts import FileFacts
from gmr_studio.core.model.motion import Motion
from gmr_studio.core.space.units import unit_named

#: assumed widths (mm) when the file stores none (adult means; said in the notes)
DEFAULT_WIDTHS = {"KneeWidth": 100.0, "AnkleWidth": 70.0, "ElbowWidth": 70.0}
#: the roles each place is found by, in order (the sets' own names for the same landmark)
SYNONYMS = {
    "KNE": ("KNE", "LFC", "FLE"),
    "KNM": ("KNM", "MFC", "FME"),
    "THI": ("THI", "WAND1", "TH1", "FTC"),
    "ANK": ("ANK", "LMAL", "FAL"),
    "MED": ("MED", "MMAL", "TAM"),
    "TIB": ("TIB", "WAND2", "TB1", "TTC"),
    "TOE": ("TOE", "MT2", "FM1", "MT5"),
    "HEE": ("HEE", "CAL", "FCC"),
    "ELB": ("ELB", "HLE"),
    "ELM": ("ELM", "HME"),
    "WRA": ("WRA", "RSP"),
    "WRB": ("WRB", "UHE"),
    "FIN": ("FIN", "HM2"),
    "C7": ("C7",),
    "CLAV": ("CLAV", "SJN"),
    "T10": ("T10", "T8"),
    "STRN": ("STRN", "SXS"),
}

#: markers rigid with the thigh and with the shank (wands, clusters, bony landmarks)
THIGH = ("THI", "TH1", "TH2", "TH3", "THAP", "THAD", "WAND1", "FTC", "THU", "THF", "THR")
SHANK = ("TIB", "TB1", "TB2", "TB3", "TIAP", "TIAD", "WAND2", "TTC", "FAX", "SHU", "SHF", "SHR")
FOOT = ("HEE", "CAL", "FCC", "MIDS", "MIDL", "TOE", "TOEL", "TOEM", "MT1", "MT2", "MT5", "FM1", "FM5")


#: the hip centre regressions: Harrington et al. 2007 (the default), Davis et al. 1991 (Plug-in Gait)
HIP_METHODS = ("harrington", "davis")
#: the knee centre: on the functional flexion axis where clusters allow (the default), or anatomical
KNEE_METHODS = ("functional", "anatomical")


def _functional_leg(roles, side: str, hjc: np.ndarray, methods: dict):
    """Knee and ankle centres by SCoRE from thigh, shank and foot clusters (sets without knee
    and ankle markers, such as OpenSim's gait2392), and the markers giving the twists; None
    when a segment has fewer than three markers."""
    thigh, shank, foot = (roles.all(group, side) for group in (THIGH, SHANK, FOOT))
    if min(len(thigh), len(shank), len(foot)) < 3:
        return None
    kjc = functional_centre(np.stack(thigh, 1), np.stack(shank, 1))
    ajc = functional_centre(np.stack(shank, 1), np.stack(foot, 1))
    how = "functional centre (SCoRE, Ehrig et al. 2006) of the {} and {} clusters"
    methods[side + "KJC"], methods[side + "AJC"] = how.format("thigh", "shank"), how.format("shank", "foot")
    return kjc, ajc, most_seen(thigh), most_seen(shank)


@dataclasses.dataclass(frozen=True, eq=False)
class BuiltSkeleton:
    """What :func:`build_skeleton` found.

    skeleton : GMR rest pose (0 frames), joints as in the module docstring, mm.
    centres : (F, J, 3) joint centres per frame (NaN: not placed in that frame).
    twist_markers : (F, J, 3) the third marker giving each joint's bone twist (NaN: none).
    lengths : (J,) fitted bone lengths (median), spread : (J,) RMS of the measured lengths
        about them, span : (J, 2) their 5th and 95th percentiles (mm; NaN for the root).
    methods : joint -> how its centre was placed (formula and citation).
    pelvis : the Procrustes triple (root, left hip, mid-ASIS).
    set_match : the recognised marker set; notes : assumptions (widths assumed...).
    """

    skeleton: Motion
    centres: np.ndarray
    twist_markers: np.ndarray
    lengths: np.ndarray
    spread: np.ndarray
    span: np.ndarray
    methods: dict[str, str]
    pelvis: tuple[str, str, str]
    set_match: SetMatch
    notes: tuple[str, ...] = ()


class _Roles:
    """Role trajectories of both sides, found through :data:`SYNONYMS`."""

    def __init__(self, found: dict[str, np.ndarray]):
        self.found = found

    def all(self, roles: tuple[str, ...], side: str = "") -> list[np.ndarray]:
        """Every found trajectory among ``roles`` (not through synonyms)."""
        return [self.found[side + r] for r in roles if side + r in self.found]

    def get(self, role: str, side: str = "") -> np.ndarray | None:
        for name in SYNONYMS.get(role, (role,)):
            value = self.found.get(side + name)
            if value is not None:
                return value
        return None


def _width(parameters: dict[str, float], name: str, side: str, notes: list[str]) -> float:
    for key in (("L" if side == "L" else "R") + name, ("Left" if side == "L" else "Right") + name, name):
        if key in parameters and parameters[key] > 0:
            return parameters[key]
    note = f"no {name} in the file's PROCESSING parameters: {DEFAULT_WIDTHS[name]:g} mm assumed"
    if note not in notes:
        notes.append(note)
    return DEFAULT_WIDTHS[name]


def joint_centre_trajectories(
    markers: MarkerSet, match: SetMatch, hip: str = "harrington", knee: str = "functional"
) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray], dict[str, str], list[str]]:
    """Joint centres (F, 3) and twist markers (F, 3) by joint name, the method of each, notes.

    ``markers`` in millimetres. ``hip``: the hip regression (:data:`HIP_METHODS`); ``knee``
    (:data:`KNEE_METHODS`): "functional" moves a knee onto its flexion axis where the thigh and
    shank clusters allow it, "anatomical" keeps the mid-point of the condyles (or the chord), as
    Plug-in Gait places it (what ``--against-file-model`` compares with). Raises OperationError
    when the set cannot place the pelvis, hips, knees and ankles (e.g. OpenSim's gait2392 set,
    which has no knee or ankle markers).
    """
    roles = _Roles(role_positions(markers, match))
    params = markers.parameters
    notes: list[str] = []
    radius = params.get("MarkerDiameter", jc.MARKER_DIAMETER) / 2
    lasi, rasi, sacrum = _pelvis_points(roles)
    if lasi is None or rasi is None or sacrum is None:
        raise OperationError(f"set {match.definition.name}: the pelvis needs both ASIS and the PSIS or a sacral marker")
    origin, frame = jc.pelvis_frame(lasi, rasi, sacrum)
    placed = np.isfinite(frame).all(axis=(1, 2))
    if not placed.any():
        raise OperationError(pelvis_never_seen(markers, match))
    if not placed.all():
        notes.append(pelvis_gaps_note(markers, match, ~placed))
    width = np.linalg.norm(lasi - rasi, axis=-1)
    if hip == "davis":
        leg = params.get("LegLength")
        if leg is None:
            ank, kne = roles.get("ANK", "L"), roles.get("KNE", "L")
            leg = np.nanmedian(np.linalg.norm(lasi - kne, axis=-1) + np.linalg.norm(kne - ank, axis=-1))
            notes.append(f"no LegLength parameter: {leg:.0f} mm measured (ASIS-knee-ankle, median)")
        local = jc.hip_davis(leg, np.nanmedian(width), radius)
        how = "Davis et al. 1991 (Plug-in Gait), leg length and ASIS distance (median over the take)"
    else:
        depth = np.linalg.norm(origin - sacrum, axis=-1)
        local = jc.hip_harrington(np.nanmedian(width), np.nanmedian(depth))
        how = "Harrington et al. 2007, pelvis width and depth (medians over the take)"
    hips = origin[:, None] + np.einsum("fab,kb->fka", frame, local)
    centres = {"pelvis": 0.5 * (hips[:, 0] + hips[:, 1]), "pelvis_front": origin}
    twists: dict[str, np.ndarray] = {}
    methods = {"pelvis": "mid-point of the hip centres", "pelvis_front": "mid-point of the ASIS markers"}
    for k, side in enumerate("LR"):
        hjc = centres[side + "HJC"] = hips[:, k]
        methods[side + "HJC"] = how
        kne, knm, thi = roles.get("KNE", side), roles.get("KNM", side), roles.get("THI", side)
        ank, med, tib = roles.get("ANK", side), roles.get("MED", side), roles.get("TIB", side)
        if kne is None or ank is None:
            functional = _functional_leg(roles, side, hjc, methods)
            if functional is None:
                raise OperationError(
                    f"set {match.definition.name} has no lateral knee and ankle markers: the knee and ankle centres "
                    "need them, or three markers on each of thigh, shank and foot for functional centres"
                )
            centres[side + "KJC"], centres[side + "AJC"] = functional[:2]
            twists[side + "KJC"], twists[side + "AJC"] = functional[2:]
            toe = roles.get("TOE", side)
            if toe is not None:
                centres[side + "TOE"], methods[side + "TOE"] = toe, "the toe marker"
                if (heel := roles.get("HEE", side)) is not None:
                    twists[side + "TOE"] = heel
            continue
        hinge = (match.definition.name, side, params, notes, radius, methods)
        kjc = _hinge(hinge, "KJC", hjc, kne, knm, thi, "KneeWidth", ("knee", "hip", "thigh wand"))
        thigh_markers = [hjc, kne, *roles.all(THIGH, side)]
        kjc = fill_from_cluster(kjc, thigh_markers)
        ajc = _hinge(hinge, "AJC", kjc, ank, med, tib, "AnkleWidth", ("ankle", "knee", "tibia wand"))
        ajc = fill_from_cluster(ajc, [kjc, ank, *roles.all(SHANK, side)])
        if knee == "functional":
            kjc = _knee_on_axis(roles, side, hjc, kjc, ajc, thigh_markers, methods, notes)
        centres[side + "KJC"], centres[side + "AJC"] = kjc, ajc
        twists[side + "KJC"] = most_seen([kne, *roles.all(THIGH, side)])
        twists[side + "AJC"] = most_seen([ank, *roles.all(SHANK, side)])
        toe = roles.get("TOE", side)
        if toe is not None:
            centres[side + "TOE"], methods[side + "TOE"] = toe, "the toe marker"
            heel = roles.get("HEE", side)
            if heel is not None:
                twists[side + "TOE"] = heel
    _upper_body(roles, centres, twists, methods, params, notes, radius)
    return centres, twists, methods, notes


def _knee_on_axis(roles: _Roles, side: str, hjc, kjc, ajc, thigh_markers, methods: dict, notes: list) -> np.ndarray:
    """The knee centre on the knee's functional flexion axis where the thigh and shank clusters
    allow it (:func:`core.markers.functional_joints.knee_on_axis`), else ``kjc`` unchanged."""
    found = knee_on_axis(roles.all(THIGH, side), roles.all(SHANK, side), hjc, kjc, ajc)
    if found is None:
        return kjc
    moved, distance = found
    methods[side + "KJC"] += (
        f", moved onto the flexion axis of the thigh and shank clusters by {distance:.1f} mm (SARA, Ehrig et al. "
        "2007; CGM 2.x's functional knee)"
    )
    notes.append(f"{side} knee centre on the functional flexion axis (SARA), {distance:.1f} mm from the anatomical one")
    return fill_from_cluster(moved, thigh_markers)


def _hinge(context, joint, proximal, lateral, medial, wand, width_name, words):
    """A knee or ankle centre: the mid-point of the lateral and medial markers, else Plug-in
    Gait's chord with the wand and the subject's width; OperationError when neither is there."""
    set_name, side, params, notes, radius, methods = context
    name, parent, wand_name = words
    if medial is not None:
        methods[side + joint] = f"mid-point of the lateral and medial {name} markers"
        return jc.midpoint(lateral, medial)
    if wand is None:
        raise OperationError(f"set {set_name}: the {side} {name} needs a medial marker or a {wand_name}")
    methods[side + joint] = f"Plug-in Gait chord ({parent} centre, {name} marker, {wand_name})"
    return jc.chord(proximal, lateral, wand, _width(params, width_name, side, notes) / 2 + radius)


def _upper_body(roles: _Roles, centres, twists, methods, params, notes, radius) -> None:
    c7, clav, t10, strn = (roles.get(r) for r in ("C7", "CLAV", "T10", "STRN"))
    if c7 is None or clav is None:
        return
    centres["thorax"], methods["thorax"] = 0.5 * (c7 + clav), "mid-point of C7 and CLAV"
    twists["thorax"] = c7
    heads = [h for h in (roles.get(r, s) for r in ("FHD", "BHD") for s in "LR") if h is not None]
    if len(heads) == 4:
        centres["head"], methods["head"] = np.mean(heads, axis=0), "centre of the four head markers"
        twists["head"] = roles.get("FHD", "L")
    up = jc.thorax_up(c7, clav, t10, strn) if t10 is not None and strn is not None else None
    sho = {s: roles.get("SHO", s) for s in "LR"}
    if up is None or sho["L"] is None or sho["R"] is None:
        return
    for side, other in (("L", "R"), ("R", "L")):
        sjc = centres[side + "SJC"] = jc.shoulder_rab(sho[side], sho[other], up)
        methods[side + "SJC"] = "Rab et al. 2002 (17% of the shoulder distance below the shoulder marker)"
        elb, elm = roles.get("ELB", side), roles.get("ELM", side)
        wra, wrb = roles.get("WRA", side), roles.get("WRB", side)
        if elb is None or wra is None or wrb is None:
            continue
        wjc = centres[side + "WJC"] = jc.midpoint(wra, wrb)
        methods[side + "WJC"] = "mid-point of the wrist markers (bar or styloids)"
        if elm is not None:
            ejc = fill_from_cluster(jc.midpoint(elb, elm), [sjc, elb, *roles.all(("UPA", "WAND3"), side)])
            centres[side + "EJC"], methods[side + "EJC"] = ejc, "mid-point of the epicondyles"
        else:
            delta = _width(params, "ElbowWidth", side, notes) / 2 + radius
            upa = roles.get("UPA", side)
            wand, what = (upa, "upper-arm marker") if upa is not None else (wjc, "wrist centre")
            centres[side + "EJC"] = jc.chord(sjc, elb, wand, delta)
            methods[side + "EJC"] = f"Plug-in Gait chord (shoulder, elbow, {what})"
        twists[side + "EJC"], twists[side + "WJC"] = elb, wra
        fin = roles.get("FIN", side)
        if fin is not None:
            centres[side + "HAND"], methods[side + "HAND"] = fin, "the finger (hand) marker"
            twists[side + "HAND"] = wra


#: joint -> parent, in depth-first order; rest direction in the pelvis frame (x fwd, y left, z up)
TREE = (
    ("pelvis", None, None),
    ("pelvis_front", "pelvis", "mean"),
    ("LHJC", "pelvis", "mean"),
    ("LKJC", "LHJC", (0, 0, -1)),
    ("LAJC", "LKJC", (0, 0, -1)),
    ("LTOE", "LAJC", (1, 0, 0)),
    ("RHJC", "pelvis", "mean"),
    ("RKJC", "RHJC", (0, 0, -1)),
    ("RAJC", "RKJC", (0, 0, -1)),
    ("RTOE", "RAJC", (1, 0, 0)),
    ("thorax", "pelvis", (0, 0, 1)),
    ("head", "thorax", (0, 0, 1)),
    ("LSJC", "thorax", "mean"),
    ("LEJC", "LSJC", (0, 0, -1)),
    ("LWJC", "LEJC", (0, 0, -1)),
    ("LHAND", "LWJC", (0, 0, -1)),
    ("RSJC", "thorax", "mean"),
    ("REJC", "RSJC", (0, 0, -1)),
    ("RWJC", "REJC", (0, 0, -1)),
    ("RHAND", "RWJC", (0, 0, -1)),
)


def build_skeleton(
    markers: MarkerSet, match: SetMatch | None = None, hip: str = "harrington", knee: str = "functional"
) -> BuiltSkeleton:
    """The skeleton of the subject in ``markers`` (any units: converted to mm); see the module
    docstring. Raises OperationError naming what is missing when no known set fits or the set
    cannot place the legs."""
    if hip not in HIP_METHODS or knee not in KNEE_METHODS:
        raise ValueError(f"hip {hip!r} or knee {knee!r}: expected one of {HIP_METHODS} and one of {KNEE_METHODS}")
    markers = markers.in_units("mm")
    match = match or identify_marker_set(markers)
    if match is None:
        seen = markers.present.any(axis=0) if markers.n_frames else np.zeros(markers.n_markers, bool)
        labels = [label for label, s in zip(markers.labels, seen) if s]
        unseen = [label for label, s in zip(markers.labels, seen) if not s]
        named = identify_marker_set(list(markers.labels))
        if named is not None and named.complete:  # the set's labels are all there, not all seen
            lacking = match_set(labels, named.definition).missing
            raise OperationError(
                f"this file's markers are set {named.definition.name}, but {', '.join(lacking)} "
                f"{'is' if len(lacking) == 1 else 'are'} missing in every frame of the {markers.n_frames} read: "
                "no skeleton is built without them (convert frames where they are seen, --frames A:B)"
            )
        raise OperationError(no_match_text(labels, unseen))
    if match.missing:
        raise OperationError(
            f"this file's markers are set {match.definition.name} but miss {', '.join(match.missing)}: "
            "no skeleton is built without them"
        )
    centres, twists, methods, notes = joint_centre_trajectories(markers, match, hip, knee)
    tree = [(n, parent, rest) for n, parent, rest in TREE if n in centres and (parent is None or parent in centres)]
    names = [t[0] for t in tree]
    index = {n: i for i, n in enumerate(names)}
    n_joints = len(names)
    stacked = np.stack([centres[n] for n in names], axis=1)
    twist_markers = np.full_like(stacked, np.nan)
    for name, points in twists.items():
        if name in index:
            twist_markers[:, index[name]] = points
    _, frame = jc.pelvis_frame(*_pelvis_points(_Roles(role_positions(markers, match))))
    up = _up_rotation(frame)
    parents = np.array([-1 if p is None else index[p] for _, p, _ in tree])
    lengths, spread = np.full(n_joints, np.nan), np.full(n_joints, np.nan)
    span = np.full((n_joints, 2), np.nan)
    offsets = np.zeros((n_joints, 3))
    for j, (name, parent, rest) in enumerate(tree):
        if parent is None:
            continue
        bone = stacked[:, j] - stacked[:, index[parent]]
        length = np.linalg.norm(bone, axis=1)
        ok = np.isfinite(length)
        if not ok.any():
            raise OperationError(f"{name}: never placed (its markers are missing in every frame)")
        lengths[j] = np.median(length[ok])
        spread[j] = np.sqrt(np.mean((length[ok] - lengths[j]) ** 2))
        span[j] = np.percentile(length[ok], [5, 95])
        if rest == "mean":
            local = np.einsum("fba,fb->fa", frame, bone)
            direction = jc.unit(np.nanmean(local, axis=0))
        else:
            direction = np.asarray(rest, dtype=np.float64)
        offsets[j] = lengths[j] * (up @ direction)
    skeleton = Motion(
        names=names,
        parents=parents,
        offsets=offsets,
        rotation_orders=("ZYX",) * n_joints,
        has_translation=parents < 0,
        rotations=np.zeros((0, n_joints, 3, 3)),
        translations=np.zeros((0, n_joints, 3)),
        frame_time=1.0 / markers.rate,
        convention="pre",
        comments=(f"skeleton built from the markers of {markers.source or '(memory)'}, set {match.definition.name}",),
        facts=FileFacts(unit=unit_named(markers.units)),
    )
    return BuiltSkeleton(
        skeleton=skeleton,
        centres=stacked,
        twist_markers=twist_markers,
        lengths=lengths,
        spread=spread,
        span=span,
        methods={n: methods[n] for n in names},
        pelvis=("pelvis", "LHJC", "pelvis_front"),
        set_match=match,
        notes=tuple(notes),
    )


def _pelvis_labels(match: SetMatch) -> list[str]:
    """The labels of the set's pelvis markers (ASIS, PSIS, sacrum) in the file."""
    found = [match.found[role] for role in ("LASI", "RASI", "LPSI", "RPSI", "SACR") if role in match.found]
    return list(dict.fromkeys(part for label in found for part in label.split("+")))


def pelvis_gaps_note(markers: MarkerSet, match: SetMatch, missing: np.ndarray) -> str:
    """A note for the frames (``missing``: (F,) bool) where the pelvis markers are too few to
    place the pelvis: each marker missing there, and the joint centres computed from them."""
    gone = [
        f"{label} in {frame_ranges(missing & ~markers.present[:, markers.index(label)])}"
        for label in _pelvis_labels(match)
        if (missing & ~markers.present[:, markers.index(label)]).any()
    ]
    return (
        f"the pelvis markers are missing in frames {frame_ranges(missing)} ({'; '.join(gone)}): the joint centres "
        "computed from them (pelvis, pelvis_front, LHJC, RHJC) are not placed there"
    )


def pelvis_never_seen(markers: MarkerSet, match: SetMatch) -> str:
    """The message for markers whose pelvis is in no frame: which pelvis markers are missing
    how often, and what the user can do."""
    labels = _pelvis_labels(match)
    missing = ", ".join(
        f"{label} {100 * (1 - markers.present[:, markers.index(label)].mean()):.0f}%" for label in labels
    )
    return (
        f"the pelvis is in no frame: its markers are never seen together (missing: {missing} of the "
        f"{markers.n_frames} frames), and every joint centre hangs from it. Fill the gaps in the capture "
        "software, interpolate short ones with --fill-gaps N, or keep the frames where they are seen with --frames A:B"
    )


def _pelvis_points(roles: _Roles):
    """LASI, RASI and the sacrum (mid-PSIS or SACR), (F, 3) each or None. A pelvis marker
    missing in a frame is placed by a rigid fit of the other pelvis markers there (pelvis
    markers are often hidden: walking5's LASI is seen in 587 of 1103 frames, its TRC's in 13)."""
    points = [roles.get("ASI", "L"), roles.get("ASI", "R"), roles.get("PSI", "L"), roles.get("PSI", "R")]
    if points[2] is None or points[3] is None:
        points[2:] = [roles.get("SACR")]
    if any(p is None for p in points):
        return points[0], points[1], points[2] if len(points) == 3 else None
    if len(points) == 4:
        points = [fill_from_cluster(p, [q for q in points if q is not p]) for p in points]
    sacrum = 0.5 * (points[2] + points[3]) if len(points) == 4 else points[2]
    return points[0], points[1], sacrum


def _up_rotation(frame: np.ndarray) -> np.ndarray:
    """The rotation (3, 3) taking the rest pose's canonical axes (x forward, y left, z up) to
    the file's: z to the file axis nearest the pelvis's mean vertical (Z-up C3D, Y-up TRC)."""
    vertical = np.nanmean(frame[:, :, 2], axis=0)
    axis = np.zeros(3)
    k = int(np.nanargmax(np.abs(vertical)))
    axis[k] = np.sign(vertical[k])
    return swing(np.array([0.0, 0.0, 1.0]), axis[None])[0]
