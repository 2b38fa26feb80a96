"""Quantities over time for one joint (or marker): what the curves dock and ``gmr curves`` plot.

Every function is vectorised over frames and returns frames first. A :class:`Curves` is a
block of named columns ``(F, C)`` in one unit; columns are named ``JOINT.QUANTITY.AXIS``
(``LeftKnee.euler.Z``) or ``JOINT.QUANTITY`` for scalars (``LeftKnee.speed``).

Quantities (:data:`QUANTITIES`): a joint's rotation comes in two conventions, and each has
its own name (the dock, ``gmr curves``, their CSV and the inspector use these names):

- ``channels``: the joint's own rotation channels **as the file has them** (degrees, one
  column per channel, labelled as the file labels it): a BVH joint's ``CHANNELS`` rotations
  (the rotation of the bones leaving it; an End Site has none), an AMC bone's rotation dofs in
  its ASF axis frame (``lradius.channels.rx`` alone for CMU's one-axis elbow), a GMR file's
  channels (its GMR rotation). The file's values as written when they still make the
  motion's rotation (:class:`core.channels.FileChannels`); otherwise (an edit changed it, or
  no file said) the same columns computed from the motion, continuous over time.
  ``euler`` is an alias of ``channels`` (what ``gmr curves --quantity euler`` always gave).
- ``gmr-euler``: the **GMR rotation** ``R_j`` (the rotation of the bone that ends at the
  joint; on a BVH the parent's channels) as Euler angles in the GMR joint's order (the
  parent's BVH order), degrees, continuous (:func:`continuous_euler`).
- ``angle``: the rotation angle of the GMR rotation (degrees, 0 to 180).
- ``quaternion``: the GMR rotation as ``w, x, y, z`` with signs kept continuous over frames.
- ``local-pre``: the local translation as GMR composes it, ``R_j t_j`` (``[R, R t]``);
  ``local-post``: as BVH does, ``t_j`` (``[R, t]``). For a root both are its world
  position ``G``.
- ``world``: the world position (forward kinematics), file units.
- ``speed``: the norm of the world velocity, units per second; ``acceleration``: the norm of
  the world acceleration, units per second squared. Derivatives are central differences
  over time (one-sided at the ends), via ``numpy.gradient``.

Every quantity is the same whichever convention the motion is held in (a BVH read as it is
by ``gmr curves``, or converted to GMR by the app). Times are :mod:`core.clock`'s.

Markers: :func:`marker_curves` gives a marker's coordinates with NaN in its gaps and
:func:`gap_spans` the gaps as frame ranges (for shading).
"""

from __future__ import annotations

import dataclasses
import weakref

import numpy as np

from gmr_studio.core.channels import FileChannels
from gmr_studio.core.clock import frame_seconds
from gmr_studio.core.convert import DEFAULT_ORDER
from gmr_studio.core.errors import OperationError
from gmr_studio.core.kinematics import joint_world_transform
from gmr_studio.core.motion import Motion
from gmr_studio.core.quaternions import continuous_quaternions, quaternion_from_matrix
from gmr_studio.core.rotations import complete_order, euler_from_matrix, rotation_angle

QUANTITIES = (
    "channels",
    "gmr-euler",
    "angle",
    "quaternion",
    "local-pre",
    "local-post",
    "world",
    "speed",
    "acceleration",
)
#: other names accepted for a quantity (documented; each means exactly one quantity)
ALIASES = {"euler": "channels"}
#: children whose GMR rotations differ by less than this (max abs entry) share one BVH rotation
SHARED_TOLERANCE = 1e-12
#: curves of live motions (:func:`values_at`)
_CACHE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
#: radians: the Euler branch may change only where the middle angle is beyond this, on the way
#: through 90 degrees (:func:`continuous_euler`)
EULER_BRANCH_MIDDLE = np.radians(60.0)
UNITS = {
    "channels": "deg",
    "gmr-euler": "deg",
    "angle": "deg",
    "quaternion": "",
    "local-pre": "units",
    "local-post": "units",
    "world": "units",
    "speed": "units/s",
    "acceleration": "units/s²",
}


@dataclasses.dataclass(frozen=True, eq=False)
class Curves:
    """Named columns over frames.

    Attributes
    ----------
    columns : C names, ``JOINT.QUANTITY[.AXIS]``.
    values : (F, C) float64 (NaN where there is no value, e.g. a marker's gaps).
    unit : the unit of every column (``"deg"``, ``"units/s"``, ...).
    """

    columns: tuple[str, ...]
    values: np.ndarray
    unit: str

    @staticmethod
    def concatenate(blocks: list[Curves]) -> Curves:
        """Columns of several blocks side by side (same frames); the unit is the first's."""
        if not blocks:
            return Curves((), np.zeros((0, 0)), "")
        return Curves(
            tuple(c for b in blocks for c in b.columns),
            np.concatenate([b.values for b in blocks], axis=1),
            blocks[0].unit,
        )


def _wrapped(angles: np.ndarray) -> np.ndarray:
    """Angles in radians wrapped to [-pi, pi)."""
    return (angles + np.pi) % (2 * np.pi) - np.pi


def continuous_euler(angles: np.ndarray) -> np.ndarray:
    """Three-axis Euler angles over frames (F, 3), radians, made continuous.

    Every rotation has two Tait-Bryan solutions, ``(a, b, c)`` and ``(a + pi, pi - b, c + pi)``;
    :func:`core.rotations.euler_from_matrix` returns the one with ``|b| <= pi/2``, so a motion
    whose middle angle passes 90 degrees (a BVH root turning over) jumps there. Frame ``f``
    switches branch when the other solution is nearer frame ``f - 1`` than its own while the
    middle angle is beyond :data:`EULER_BRANCH_MIDDLE` at both frames, i.e. when it passes
    90 degrees (a jump in the data itself, such as CMU's T-pose first frame, switches
    nothing; the nearness of two frames' solutions does not depend on which branch both are on, so the
    switches add up with a cumulative sum), then each column is unwrapped. The first frame
    keeps the principal solution.
    """
    other = np.stack([angles[:, 0] + np.pi, np.pi - angles[:, 1], angles[:, 2] + np.pi], axis=-1)
    stay = np.sum(_wrapped(angles[1:] - angles[:-1]) ** 2, axis=-1)
    switch = np.sum(_wrapped(other[1:] - angles[:-1]) ** 2, axis=-1)
    steep = np.abs(angles[:, 1]) > EULER_BRANCH_MIDDLE
    crossing = (switch < stay) & steep[1:] & steep[:-1]
    branch = np.concatenate([[0], np.cumsum(crossing) % 2]).astype(bool)
    return np.unwrap(np.where(branch[:, None], other, angles), axis=0)


def euler_degrees(rotations: np.ndarray, order: str) -> np.ndarray:
    """Continuous Euler angles in degrees of rotations over frames: (F, 3, 3) -> (F, len(order)).

    The angles are those of :func:`core.rotations.euler_from_matrix` in the completed
    order made continuous (:func:`continuous_euler`), keeping the first ``len(order)`` (the
    others are zero for a rotation that has only those channels).
    """
    if not order:
        return np.zeros((rotations.shape[0], 0))
    angles = euler_from_matrix(rotations, complete_order(order))
    if len(order) < 3:  # the other solution would give the missing axes 180 degrees
        return np.degrees(np.unwrap(angles[:, : len(order)], axis=0))
    return np.degrees(continuous_euler(angles))


def local_translations(motion: Motion, joint: int, composition: str) -> np.ndarray:
    """(F, 3) local translation of a joint: ``"pre"`` gives GMR's ``R_j t_j``, ``"post"``
    BVH's ``t_j`` (a root's is ``G`` either way).

    On a post-rotation motion the GMR rotation of a joint is its parent's post rotation
    (:func:`core.convert.pre_from_post`), used here without converting the whole motion.
    """
    translation = motion.translations[:, joint]
    parent = int(motion.parents[joint])
    if composition == "post" or parent < 0:
        return np.array(translation)
    rotation = motion.rotations[:, joint] if motion.convention == "pre" else motion.rotations[:, parent]
    return np.einsum("fab,fb->fa", rotation, translation)


def derivative(values: np.ndarray, frame_time: float) -> np.ndarray:
    """Time derivative over frames (F, ...) -> (F, ...): central differences, one-sided at the
    ends; zeros for a single frame."""
    if values.shape[0] < 2:
        return np.zeros_like(values)
    return np.gradient(values, frame_time, axis=0)


def world_speed(positions: np.ndarray, frame_time: float) -> np.ndarray:
    """Speed |dP/dt| over frames: positions (F, ..., 3) -> (F, ...) in units per second."""
    return np.linalg.norm(derivative(positions, frame_time), axis=-1)


def world_acceleration(positions: np.ndarray, frame_time: float) -> np.ndarray:
    """Acceleration |d²P/dt²| over frames: positions (F, ..., 3) -> (F, ...), units per second²."""
    return np.linalg.norm(derivative(derivative(positions, frame_time), frame_time), axis=-1)


def quantity_name(quantity: str) -> str:
    """The quantity a name or alias means (:data:`ALIASES`); OperationError for none."""
    name = ALIASES.get(quantity, quantity)
    if name not in QUANTITIES:
        known = ", ".join((*QUANTITIES, *ALIASES))
        raise OperationError(f"unknown quantity {quantity!r}: expected one of {known}")
    return name


def gmr_rotations(motion: Motion, joint: int) -> tuple[np.ndarray, str]:
    """(F, 3, 3) a joint's GMR rotation (the bone ending at it) and its GMR Euler order, in
    either convention: a post motion's joint takes its parent's rotation and order (a root
    the identity), as :func:`core.convert.pre_from_post` gives it."""
    if motion.convention == "pre":
        return motion.rotations[:, joint], motion.rotation_orders[joint]
    parent = int(motion.parents[joint])
    if parent < 0:
        identity = np.broadcast_to(np.eye(3), (motion.n_frames, 3, 3))
        return identity, motion.rotation_orders[joint] or DEFAULT_ORDER
    return motion.rotations[:, parent], motion.rotation_orders[parent] or DEFAULT_ORDER


def bvh_rotations(motion: Motion, joint: int) -> np.ndarray | None:
    """(F, 3, 3) a joint's BVH rotation (the bones leaving it), in either convention; None
    for a leaf and where its GMR children turn independently (a BVH needs dummy joints)."""
    if motion.convention == "post":
        return motion.rotations[:, joint] if motion.rotation_orders[joint] else None
    children = list(motion.children[joint])
    if not children:
        return None
    first = motion.rotations[:, children[0]]
    for child in children[1:]:
        if np.abs(motion.rotations[:, child] - first).max(initial=0.0) > SHARED_TOLERANCE:
            return None
    return motion.rotations[:, joint] @ first if motion.parents[joint] < 0 else first


def channel_curves(motion: Motion, joint: int, file_channels: FileChannels | None = None) -> Curves:
    """The ``channels`` quantity of one joint (module docstring): ``(F, k)`` degrees."""
    name = motion.names[joint]
    if file_channels is None:  # the motion's own channels (a GMR file, a motion made in memory)
        order = motion.rotation_orders[joint]
        labels = tuple(f"{axis}rotation" for axis in order)
        values = euler_degrees(motion.rotations[:, joint], order) if order else np.zeros((motion.n_frames, 0))
        return Curves(tuple(f"{name}.channels.{label}" for label in labels), values, UNITS["channels"])
    labels = file_channels.label_of(name)
    columns = tuple(f"{name}.channels.{label}" for label in labels)
    if not labels:  # the file gives this joint no rotation channels (an End Site)
        return Curves(columns, np.zeros((motion.n_frames, 0)), UNITS["channels"])
    if file_channels.convention == "post":
        rotations = bvh_rotations(motion, joint)
    else:
        rotations = motion.rotations[:, joint] if motion.convention == "pre" else gmr_rotations(motion, joint)[0]
    written = file_channels.angles[name]
    if rotations is None:
        if not motion.children[joint] and written.shape[0] == motion.n_frames:
            # a leaf's channels turn nothing (GMR keeps no rotation for them): the file's stand
            return Curves(columns, np.array(written), UNITS["channels"])
        # children turning independently: no single rotation to give
        return Curves(columns, np.full((motion.n_frames, len(labels)), np.nan), UNITS["channels"])
    if written.shape[0] == motion.n_frames and (not len(written) or file_channels.still_make(name, rotations)):
        return Curves(columns, np.array(written), UNITS["channels"])
    return Curves(columns, file_channels.angles_from(name, rotations, euler_degrees), UNITS["channels"])


def joint_curves(
    motion: Motion,
    joint: int | str,
    quantity: str,
    positions: np.ndarray | None = None,
    file_channels: FileChannels | None = None,
) -> Curves:
    """One quantity of one joint over every frame.

    Parameters
    ----------
    motion : any motion, in either convention (every quantity means the same in both).
    joint : name or index.
    quantity : one of :data:`QUANTITIES` or an alias (:data:`ALIASES`).
    positions : optional (F, J, 3) world positions already computed (the app's cache);
        otherwise the joint's root path is walked.
    file_channels : the channels of the file the motion was read from
        (:func:`core.formats.read_motion_with_channels`), for ``channels``.

    Raises
    ------
    OperationError : unknown joint or quantity.
    """
    j = motion.joint_index(joint)
    name = motion.names[j]
    quantity = quantity_name(quantity)
    unit = UNITS[quantity]
    if quantity == "channels":
        return channel_curves(motion, j, file_channels)
    if quantity in ("gmr-euler", "angle", "quaternion"):
        rotations, order = gmr_rotations(motion, j)
        if quantity == "gmr-euler":
            return Curves(tuple(f"{name}.gmr-euler.{axis}" for axis in order), euler_degrees(rotations, order), unit)
        if quantity == "angle":
            return Curves((f"{name}.angle",), np.degrees(rotation_angle(rotations))[:, None], unit)
        values = continuous_quaternions(quaternion_from_matrix(rotations))
        return Curves(tuple(f"{name}.quaternion.{c}" for c in "wxyz"), values, unit)
    if quantity in ("local-pre", "local-post"):
        values = local_translations(motion, j, quantity.removeprefix("local-"))
        return Curves(tuple(f"{name}.{quantity}.{a}" for a in "xyz"), values, unit)
    world = positions[:, j] if positions is not None else joint_world_transform(motion, j)[1]
    if quantity == "world":
        return Curves(tuple(f"{name}.world.{a}" for a in "xyz"), np.array(world), unit)
    if quantity == "speed":
        return Curves((f"{name}.speed",), world_speed(world, motion.frame_time)[:, None], unit)
    return Curves((f"{name}.acceleration",), world_acceleration(world, motion.frame_time)[:, None], unit)


def values_at(
    motion: Motion,
    joint: int | str,
    quantity: str,
    frame: int,
    positions: np.ndarray | None = None,
    file_channels: FileChannels | None = None,
) -> tuple[tuple[str, ...], np.ndarray]:
    """(columns, (C,) values) of :func:`joint_curves` at one frame: the inspector's numbers.

    The curves of a motion are computed once (continuity needs every frame) and kept while
    the motion lives (a weak cache keyed by the motion).
    """
    j = motion.joint_index(joint)
    key = (j, quantity_name(quantity), id(file_channels))
    cache = _CACHE.setdefault(motion, {})
    if key not in cache:
        cache[key] = (joint_curves(motion, j, quantity, positions, file_channels), file_channels)
    curves = cache[key][0]
    return curves.columns, curves.values[frame]


def marker_curves(label: str, positions: np.ndarray) -> Curves:
    """A marker's coordinates over frames: positions (F, 3) with NaN in gaps -> ``LABEL.x/y/z``."""
    return Curves(tuple(f"{label}.{a}" for a in "xyz"), np.asarray(positions, dtype=np.float64), "units")


def gap_spans(positions: np.ndarray) -> np.ndarray:
    """Frame ranges where a marker is missing: positions (F, 3) -> (G, 2) int64 half-open
    ``[start, stop)`` runs of frames with any NaN coordinate."""
    missing = np.isnan(np.asarray(positions, dtype=np.float64)).any(axis=-1)
    edges = np.diff(np.concatenate([[0], missing.astype(np.int8), [0]]))
    return np.stack([np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)], axis=1).astype(np.int64)


def frame_times(frames: np.ndarray, frame_time: float) -> np.ndarray:
    """Seconds of 0-based frame numbers: (F,) -> (F,) (:func:`core.clock.frame_seconds`)."""
    return frame_seconds(np.asarray(frames), frame_time)
