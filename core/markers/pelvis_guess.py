"""Which three joints give the pelvis when a marker map does not say (the ``joints`` map).

The technical note's triple is X1 the pelvis root, X2 the left femur and X3 the lower back.
On most BVH rigs both hips sit level with the root, so root and hips are collinear and give
no frame; the lower back (the first spine joint) is above them. :func:`choose_pelvis` tries,
in order:

1. the note's triple: the skeleton's root, the left femur (a pelvis joint named left and
   leg-like: ``LeftUpLeg``, ``lfemur``, ``L_Thigh``, ``LHipJoint``...), the lower back (a
   pelvis joint named like the spine: ``LowerBack``, ``Spine``, ``lowerback``...);
2. the named guesses of :data:`~core.markers.markermap.PELVIS_GUESSES` (root and both hips);
3. every other triple of pelvis joints (the root, its children, and the children of
   zero-length bones at the root, such as CMU's ``LHipJoint``), in skeleton order;

and takes the first whose three markers form a triangle that is not collinear (sine of the
angle at X1 at least :data:`MIN_SINE`) and keeps its shape over the frames: the three points
move with the pelvis. The shape is measured on the skeleton's own motion when it has several
frames (exact positions: side lengths within :data:`EXACT_SHAPE_CHANGE` of the size), else on
the markers (within :data:`MAX_SHAPE_CHANGE`: marker noise passes). ASF's ``lowerback`` turns
with the spine and is refused. If none keeps its shape, the non-collinear triple that
changes least is taken, and said.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Sequence

import numpy as np

#: the smallest sine of the angle at X1 between X2 and X3 accepted (about 3 degrees)
MIN_SINE = 0.05
#: the largest change of the triangle's side lengths accepted (5th to 95th percentile over the
#: frames), as a fraction of its longest side, when measured on the markers: noise passes, a
#: spine turning by tens of degrees does not
MAX_SHAPE_CHANGE = 0.02
#: the same when measured on the skeleton's own motion (exact positions): rigid, or not
EXACT_SHAPE_CHANGE = 1e-6
#: frames of the skeleton's motion sampled for that measure
MOTION_SAMPLES = 2000

_LEG_WORDS = ("upleg", "upperleg", "thigh", "femur", "hip")
_BACK_WORDS = ("lowerback", "spine", "lumbar", "abdomen", "back", "waist", "torso", "chest")


@dataclasses.dataclass(frozen=True)
class PelvisChoice:
    """The pelvis triple chosen: names (X1, X2, X3), how it was found, the sine of its angle
    at X1 and the change of its shape over the frames (fraction of its size)."""

    triple: tuple[str, str, str]
    how: str
    sine: float
    shape_change: float

    def describe(self) -> str:
        return (
            f"pelvis triple {', '.join(self.triple)} ({self.how}; angle at {self.triple[0]} "
            f"{np.degrees(np.arcsin(min(self.sine, 1.0))):.0f} deg, shape kept to {100 * self.shape_change:.2g}%)"
        )


def side(name: str) -> str | None:
    """ "left", "right" or None, from a joint name (``LeftUpLeg``, ``lfemur``, ``L_Thigh``,
    ``thigh.L``, ``LHipJoint``)."""
    lower = name.lower()
    for word, letter in (("left", "l"), ("right", "r")):
        if word in lower or re.match(rf"^{letter}[_.\-\s]", lower) or re.search(rf"[_.\-\s]{letter}$", lower):
            return word
        if name[:1].upper() == letter.upper() and len(name) > 1 and name[1].isupper():  # LHipJoint
            return word
        if lower.startswith(letter) and any(lower[1:].startswith(w) for w in _LEG_WORDS):  # lfemur
            return word
    return None


def _rank(name: str, words: tuple[str, ...]) -> int | None:
    """The index of the first of ``words`` in the name (lower case), or None."""
    lower = name.lower()
    return next((k for k, word in enumerate(words) if word in lower), None)


def pelvis_joints(parents: Sequence[int], offsets: np.ndarray, root: int) -> list[int]:
    """The joints that move with the pelvis: the root's children and, through bones of length
    zero at the root, their children; in index order."""
    children: dict[int, list[int]] = {}
    for j, p in enumerate(parents):
        children.setdefault(int(p), []).append(j)
    found, todo = [], list(children.get(root, []))
    while todo:
        j = todo.pop(0)
        found.append(j)
        if not np.any(offsets[j]):
            todo += children.get(j, [])
    return sorted(found)


def candidates(names: Sequence[str], parents=None, offsets=None) -> list[tuple[tuple[str, str, str], str]]:
    """Triples to try, best first, each with how it was found (see the module docstring)."""
    from gmr_studio.core.markers.markermap import PELVIS_GUESSES

    out: list[tuple[tuple[str, str, str], str]] = []
    if parents is not None:
        roots = [j for j, p in enumerate(parents) if p < 0]
        root = max(roots, key=lambda r: len(pelvis_joints(parents, offsets, r)))
        near = [names[j] for j in pelvis_joints(parents, offsets, root)]
        left = sorted((n for n in near if side(n) == "left" and _rank(n, _LEG_WORDS) is not None), key=_leg_order)
        back = [n for n in near if side(n) is None and _rank(n, _BACK_WORDS) is not None]
        for femur in left:
            for spine in back:
                out.append(((names[root], femur, spine), "the technical note's: root, left femur, lower back"))
    lower = {n.lower(): n for n in names}
    for guess in PELVIS_GUESSES:
        if all(g.lower() in lower for g in guess):
            out.append((tuple(lower[g.lower()] for g in guess), "root and both hips, by their names"))
    if parents is not None:
        for a in range(len(near)):
            for b in range(a + 1, len(near)):
                out.append(((names[root], near[a], near[b]), "a triple of pelvis joints that is not collinear"))
    seen: set = set()
    return [c for c in out if not (c[0] in seen or seen.add(c[0]))]


def _leg_order(name: str) -> int:
    return _rank(name, _LEG_WORDS)


def triangle_quality(points: np.ndarray) -> tuple[float, float]:
    """(sine of the median angle at X1, shape change) of a triangle's (F, 3, 3) positions
    (NaN frames ignored); (0, inf) when no frame has all three."""
    seen = np.isfinite(points).all(axis=(1, 2))
    if not seen.any():
        return 0.0, np.inf
    p = points[seen]
    a, b = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    cross = np.linalg.norm(np.cross(a, b), axis=1)
    lengths = np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1)
    sine = float(np.median(np.where(lengths > 0, cross / np.where(lengths > 0, lengths, 1.0), 0.0)))
    sides = np.stack([np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1), np.linalg.norm(a - b, axis=1)], axis=1)
    size = float(np.median(sides.max(axis=1)))
    if size == 0:
        return 0.0, np.inf
    spread = np.percentile(sides, 95, axis=0) - np.percentile(sides, 5, axis=0)
    return sine, float(spread.max() / size)


def choose_pelvis(
    names: Sequence[str],
    positions: np.ndarray,
    parents=None,
    offsets=None,
    motion_positions: np.ndarray | None = None,
) -> PelvisChoice | None:
    """The pelvis triple for markers labelled with joint names (see the module docstring).

    Parameters
    ----------
    names : the N joint names that have markers.
    positions : (F, N, 3) their marker positions (NaN gaps).
    parents, offsets : the skeleton's (J,) parents and (J, 3) offsets, indexed like ``names``
        when given (then ``names`` are all J joints and ``positions`` (F, J, 3)).
    motion_positions : (S, J, 3) the skeleton's own joint positions over S frames (its motion),
        where rigidity is measured exactly when S >= 2.

    Returns
    -------
    PelvisChoice, or None when every candidate is missing or collinear.
    """
    index = {n: k for k, n in enumerate(names)}
    exact = motion_positions is not None and motion_positions.shape[0] >= 2
    limit = EXACT_SHAPE_CHANGE if exact else MAX_SHAPE_CHANGE
    fallback = None
    for triple, how in candidates(names, parents, offsets):
        columns = [index[n] for n in triple]
        sine, change = triangle_quality(positions[:, columns])
        if sine < MIN_SINE:
            continue
        if exact:
            change = triangle_quality(motion_positions[:, columns])[1]
        if change <= limit:
            return PelvisChoice(triple, how, sine, change)
        if fallback is None or change < fallback.shape_change:
            fallback = PelvisChoice(triple, f"{how}; no triple keeps its shape, this one changes least", sine, change)
    return fallback


def sampled_positions(skeleton) -> np.ndarray:
    """(S, J, 3) world positions of at most :data:`MOTION_SAMPLES` frames of a skeleton's motion."""
    from gmr_studio.core.kinematics.fk import world_positions

    step = skeleton.n_frames // MOTION_SAMPLES + 1
    return world_positions(skeleton if step == 1 else skeleton.frame_slice(slice(None, None, step)))
