"""The built skeleton's motion: the closed form with the segments' third markers, and the refinement.

:func:`markers_to_built_motion` builds the skeleton (:func:`core.markers.build.build_skeleton`),
runs the paper's closed form on it (:func:`core.markers.solve.solve_positions`, twists from
each segment's third marker) and, asked to, the refinement over every marker of the set
(:func:`core.markers.refine.refine_motion`), each marker riding on its segment
(:data:`SEGMENT_ROLES`). What the command ``gmr markers`` without ``--skeleton`` and the app's
"open a C3D alone" call.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.markers.build import BuiltSkeleton, build_skeleton
from gmr_studio.core.markers.markerset import MarkerSet
from gmr_studio.core.markers.refine import Refinement
from gmr_studio.core.markers.sets import SetMatch
from gmr_studio.core.markers.solve import MarkerMotion, RootAt


@dataclasses.dataclass(frozen=True, eq=False)
class BuiltMotion:
    """:func:`markers_to_built_motion`'s result: ``result`` the closed form's MarkerMotion
    (its ``motion`` replaced by the refined one when refined), ``built`` the skeleton,
    ``refinement`` (None unless asked), ``labels`` (M,) the real markers used by the
    refinement and ``bones`` (M,) the joint whose bone carries each."""

    result: MarkerMotion
    built: BuiltSkeleton
    refinement: Refinement | None
    labels: tuple[str, ...]
    bones: np.ndarray


#: of the refinement's iterations, those run after the markers are placed again: from a
#: converged fit their places move by a few mm, and two iterations give the figures of five
#: (3 + 2 against 5 + 5: every shared file's worst marker within 0.07 mm, its RMS within 0.005)
PLACED_ITERATIONS = 2

#: bones rigid with their parent segment: the refinement keeps their local rotations
RIGID_WITH_PARENT = ("pelvis_front", "LHJC", "RHJC")

#: the bone (by the joint it ends at) each role rides on
SEGMENT_ROLES = {
    "pelvis": ("ASI", "PSI", "SACR"),
    "KJC": (
        *("THI", "KNE", "KNM", "TH1", "TH2", "TH3", "THAP", "THAD", "WAND1", "FTC", "LFC", "MFC", "FLE", "FME"),
        *("THU", "THF", "THR"),
    ),
    "AJC": (
        *("TIB", "ANK", "MED", "TB1", "TB2", "TB3", "TIAP", "TIAD", "WAND2", "TTC", "FAX", "LMAL", "MMAL", "FAL"),
        *("TAM", "SHU", "SHF", "SHR"),
    ),
    "TOE": (
        *("HEE", "TOE", "MT1", "MT2", "MT5", "CAL", "FCC", "FM1", "FM5", "VMH", "FMH", "MIDS", "MIDL", "TOEL"),
        "TOEM",
    ),
    "thorax": ("C7", "T10", "CLAV", "STRN", "RBAK", "T8", "SJN", "SXS"),
    "head": ("FHD", "BHD"),
    "SJC": ("SHO",),
    "EJC": ("UPA", "ELB", "ELM", "HLE", "HME", "WAND3"),
    "WJC": ("FRA", "WRA", "WRB", "RSP", "UHE", "WAND4"),
    "HAND": ("FIN", "HM2", "HM5"),
}


def role_bones(match: SetMatch, names: tuple[str, ...]) -> dict[str, int]:
    """Each real marker label of the set -> the joint whose bone carries it (markers of
    segments the skeleton lacks are left out)."""
    out: dict[str, int] = {}
    for role, label in match.found.items():
        side, base = (role[0], role[1:]) if role[:1] in "LR" and role[1:] in _SIDED_BASES else ("", role)
        for joint, roles in SEGMENT_ROLES.items():
            name = joint if joint in ("pelvis", "thorax", "head") else side + joint
            if base in roles and name in names:
                for part in label.split("+"):
                    out.setdefault(part, names.index(name))
    return out


_CENTRE_ROLES = {"C7", "T10", "CLAV", "STRN", "RBAK", "T8", "SJN", "SXS", "SACR"}
_SIDED_BASES = {r for roles in SEGMENT_ROLES.values() for r in roles} - _CENTRE_ROLES


def markers_to_built_motion(
    markers: MarkerSet,
    hip: str = "harrington",
    refine: bool = False,
    iterations: int = 5,
    weights: dict[str, float] | None = None,
    place_markers: bool = True,
    knee: str = "functional",
    root_at: RootAt = "pelvis",
) -> BuiltMotion:
    """Build the skeleton (:func:`build_skeleton`), run the paper's closed form on it with the
    twists from the segments' third markers, and with ``refine`` the global refinement
    (:func:`core.markers.refine.refine_motion`) over every marker of the set (``weights``: label
    -> weight, 1 for the others; a weight 0 leaves a marker out), each riding on
    the bone it moves with most rigidly. Millimetres, the file's axes.

    Each marker's place on its bone (its constant offset) is first the median over the frames
    of where the closed form puts it; with ``place_markers`` (the default) it is then placed
    again where the refined skeleton puts it and the refinement run once more from there, as
    OpenSim's Scale tool places its markers after an inverse-kinematics solve (the
    MarkerPlacer: Delp S.L. et al. 2007, "OpenSim: open-source software to create and analyze
    dynamic simulations of movement", IEEE Trans. Biomed. Eng. 54:1940-1950). The closed form's
    offsets carry its own errors (a fixed-length chain, one marker for each twist); a marker
    seen in few frames (the knee markers of walking5's TRC excerpt: one frame with a pelvis)
    would otherwise keep them. Of the ``iterations``, the last :data:`PLACED_ITERATIONS` run
    after the placement (so it costs no more); ``residuals_before`` stays the closed form's.
    ``root_at``: where the closed form puts the root (:mod:`core.markers.root_fit`): by default
    at the pelvis markers' root, the mid-point of the hip centres the markers place rigidly,
    which the app shows as the recovered pelvis (docs/markersets.md)."""
    from gmr_studio.core.markers.refine import attach_markers, refine_motion
    from gmr_studio.core.markers.solve import solve_positions

    markers = markers.in_units("mm")
    built = build_skeleton(markers, hip=hip, knee=knee)
    result = solve_positions(
        built.centres,
        built.skeleton,
        built.pelvis,
        frame_time=1.0 / markers.rate,
        twist_markers=built.twist_markers,
        root_at=root_at,
        pelvis_points="joint centre",
    )
    note = f"from markers {markers.source or '(memory)'}: skeleton built from set {built.set_match.definition.name}"
    result = dataclasses.replace(
        result, motion=result.motion.replace(comments=(note,)), reasons=(*built.notes, *result.reasons)
    )
    carried = role_bones(built.set_match, built.skeleton.names)
    used = sorted(carried, key=markers.labels.index)
    bones = np.array([carried[label] for label in used], dtype=np.int64)
    targets = np.stack([markers.positions[:, markers.index(label)] for label in used], axis=1)
    targets[~result.frame_valid] = np.nan  # frames without a pelvis copy a good frame: not fitted
    refinement = None
    if refine:
        rigid = tuple(built.skeleton.joint_index(n) for n in RIGID_WITH_PARENT if n in built.skeleton.names)
        weight = np.array([(weights or {}).get(label, 1.0) for label in used])
        placed_iterations = min(PLACED_ITERATIONS, iterations - 1) if place_markers else 0
        offsets = attach_markers(result.motion, targets, bones)  # from the closed form
        first = iterations - placed_iterations
        refinement = refine_motion(result.motion, targets, bones, offsets, weight, first, fixed=rigid)
        if placed_iterations > 0:  # OpenSim's marker placement: each marker where the fitted skeleton puts it
            offsets = attach_markers(refinement.motion, targets, bones)
            placed = refine_motion(refinement.motion, targets, bones, offsets, weight, placed_iterations, fixed=rigid)
            refinement = dataclasses.replace(
                placed, residuals_before=refinement.residuals_before, iterations=iterations
            )
        result = dataclasses.replace(result, motion=refinement.motion)
    return BuiltMotion(result, built, refinement, tuple(used), bones)
