"""An edit's result and how its world transforms follow from the input's.

Most edits change every frame in a way forward kinematics passes straight through: shift
root, split, join and removing dummy joints keep every joint's world position (and frame,
or hand the frames along a path); trim keeps some frames; scale multiplies every world
position; up axis and mirror turn or reflect the whole world (mirror also swaps left and
right joints). An :class:`Edited` says which, so that a caller holding the input's world
transforms (the app's cache) gets the result's in one pass over the frames instead of
running forward kinematics again.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.kinematics import engine as fk_engine
from gmr_studio.core.model.motion import Motion


@dataclasses.dataclass(frozen=True, eq=False)
class Edited:
    """An operation's result, and where the world transforms of its joints come from.

    With ``P`` and ``W`` the input's world positions and rotations, frame ``f`` and joint
    ``n`` of the result are at ``scale * turn @ P[first + f, joints[n]] + shift`` with the
    world rotation ``turn @ W[first + f, frames[n]] @ turn.T``.

    motion : the result (J' joints).
    joints : (J',) int64, the joint of the input whose world position each joint of the
        result has (all, in order, but after removing dummy joints; the partner after a mirror).
    frames : (J',) int64, the joint of the input whose world rotation each joint of the
        result has (shift root hands the frames along its path), or None when they are not
        the input's (a post-rotation input converted first).
    rows : (first, stop) or (first, stop, step), the input's frames the result keeps (trim;
        a resample taking every n-th frame), or None for all.
    turn : (3, 3) the orthogonal matrix the world is turned or reflected by (up axis,
        mirror), or None for none.
    scale : the factor of every length (scale).
    shift : (3,) added to every world position after turning and scaling (mirror's
        reflection through a plane off the origin), or None for none.
    """

    motion: Motion
    joints: np.ndarray
    frames: np.ndarray | None
    rows: tuple[int, ...] | None = None
    turn: np.ndarray | None = None
    scale: float = 1.0
    shift: np.ndarray | None = None

    @classmethod
    def same_joints(cls, motion: Motion, frames: np.ndarray | None = None, **world) -> Edited:
        """A result with the input's joints, each keeping its world rotation unless
        ``frames`` says otherwise; ``world``: the other fields (rows, turn, scale, shift)."""
        every = np.arange(motion.n_joints)
        return cls(motion, every, every if frames is None else np.asarray(frames, dtype=np.int64), **world)

    def kinematics(
        self, positions: np.ndarray, rotations: np.ndarray, *, threads: int | None = 1
    ) -> tuple[np.ndarray, np.ndarray]:
        """The result's world positions (F', J', 3) and rotations (F', J', 3, 3) from the
        input's (F, J, 3) and (F, J, 3, 3) (class docstring): the very arrays where nothing
        changes, else made in one pass over the frames (on ``threads``;
        :func:`core.kinematics.engine.turned_joints`). They equal the result's forward
        kinematics to rounding (~1e-15 of the size): the edits keep, turn or scale every
        world position and frame exactly in theory. Raises ValueError when the frames are
        not the input's."""
        return self.world_positions(positions, threads=threads), self.world_rotations(rotations, threads=threads)

    def world_positions(self, positions: np.ndarray, *, threads: int | None = 1) -> np.ndarray:
        """The result's world positions (F', J', 3) from the input's (F, J, 3), as
        :meth:`kinematics` gives them."""
        self._check_frames()
        return self._taken(positions, self.joints, self._turn(), self._moved(), threads)

    def world_rotations(self, rotations: np.ndarray, *, threads: int | None = 1) -> np.ndarray:
        """The result's world rotations (F', J', 3, 3) from the input's (F, J, 3, 3), as
        :meth:`kinematics` gives them."""
        self._check_frames()
        return self._taken(rotations, self.frames, self._turn(), False, threads)

    def keeps_rotations(self, rotations: np.ndarray) -> bool:
        """Whether the result's world rotations are the input's (F, J, 3, 3) array itself
        (every joint keeps its frame, every frame stays, nothing turned): handing them on
        costs nothing."""
        if self.frames is None or self._turn() is not None:
            return False
        every = self.frames.size == rotations.shape[1] and np.array_equal(self.frames, np.arange(self.frames.size))
        return every and self._kept_rows(rotations.shape[0]) is None

    def _check_frames(self) -> None:
        if self.frames is None:
            raise ValueError("the result's world rotations are not the input's: compute its forward kinematics")

    def _turn(self) -> np.ndarray | None:
        """``turn``, or None when it is the identity."""
        return self.turn if self.turn is not None and not np.array_equal(self.turn, np.eye(3)) else None

    def _moved(self) -> bool:
        return self.scale != 1.0 or (self.shift is not None and bool(np.any(self.shift != 0.0)))

    def _kept_rows(self, n_frames: int) -> tuple[int, ...] | None:
        """``rows``, or None when they are every frame of ``n_frames``."""
        if self.rows is None or tuple(self.rows) in ((0, n_frames), (0, n_frames, 1)):
            return None
        return self.rows

    def _taken(
        self, array: np.ndarray, joints: np.ndarray, turn: np.ndarray | None, moved: bool, threads: int | None
    ) -> np.ndarray:
        """The result's part of the input's ``array``: ``array`` itself when every joint,
        frame and axis stays, else :func:`core.kinematics.engine.turned_joints`."""
        every = joints.size == array.shape[1] and np.array_equal(joints, np.arange(joints.size))
        rows = self._kept_rows(array.shape[0])
        if rows is not None and len(rows) == 3 and rows[2] != 1:
            array, rows = array[slice(*rows)], None  # every n-th frame: a view, copied below
            if every and turn is None and not moved:
                return array.copy()
        if every and rows is None and turn is None and not moved:
            return array
        if every and turn is None and not moved:
            return array[rows[0] : rows[1]].copy()  # a copy: the input's cache may be let go
        return fk_engine.turned_joints(
            array,
            joints,
            rows=rows,
            turn=turn,
            scale=self.scale if moved else 1.0,
            shift=self.shift if moved else None,
            threads=threads,
        )
