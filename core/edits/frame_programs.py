"""The per-frame work of the operations as one compiled pass over the motion.

:mod:`core.edits.operations` and :mod:`core.edits.dummies` decide the new forest in Python (parents,
offsets, soft links: a few joints) and describe what happens to every frame as a
:class:`FrameProgram`: a list of steps on one frame's local rotations (J, 3, 3) and
translations (J, 3), in order:

- ``swap(a, b, others, kids)``: the root ``a`` hands the root over to its child ``b``
  (paper 4.1.1): ``t_b <- t_a + R_a R_b t_b``, ``t_a <- -t_b``, ``R_a <-> R_b``, the other
  children of ``a`` get ``R_b^T R_i`` and the children of ``b`` get ``R_b R_k``;
- ``split(j, path)``: ``j`` takes its world transform, walked down its root ``path``;
- ``join(j, path)``: the root ``j`` goes under the last joint ``p`` of ``path``:
  ``R_j <- R_p^T R_j``, ``t_j <- R_j^T (t_j - t_p)`` in world terms (its offset, per
  frame; the pass also sums it and keeps its extremes, and the caller writes the static
  offset over it when the joint is rigid over all frames, :func:`set_static`);
- ``fold(d, children)``: the dummy ``d``'s rotation goes into each child, ``R_c <- R_d R_c``.

Split and join read the input's world transforms, walked in the input's forest (every
operation keeps them): a program of several joins (join all) needs no order between them.
Swap and fold read and write the frame as the steps before left it.

The compiled kernel (:mod:`core.edits._kernels`) loads each frame once, runs every
step on it in cache and writes it once, on up to ``threads`` threads (the result does
not depend on the number). Rotations recomputed from others are orthonormalised as the
numpy path does (:func:`core.rotations.orthonormalize`); a split computes the joint's
world transform with the FK engine's operations, so its result is bit for bit the FK
engine's for that joint. The numpy path of the operations is the reference: the two agree
to rounding (tested on random forests to 1e-12 of the size).

Memory: the new rotations (F, J, 3, 3) and translations (F, J, 3), nothing else of size F.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gmr_studio.core.compiled import chosen_kernels, optional_kernels
from gmr_studio.core.kinematics.engine import in_blocks
from gmr_studio.core.model.motion import Motion

#: the kinds of step (the first number of a row of :meth:`FrameProgram.tables`; the kernels
#: import them from here)
SWAP, SPLIT, JOIN, FOLD = 0, 1, 2, 3

_kernels = optional_kernels("gmr_studio.core.edits._kernels")

#: frames whose join offsets are summed together before the blocks are added up (in a
#: fixed order, so that the means do not depend on the number of threads)
MEASURE_BLOCK_FRAMES = 4096


def available() -> bool:
    """True when the compiled kernel can run the programs."""
    return _kernels is not None


def use_kernel(backend: str) -> bool:
    """Whether an operation asked for ``backend`` ('auto', 'numba' or 'numpy') runs the
    compiled kernel; 'numba' without numba installed is an error."""
    return chosen_kernels(backend, _kernels) is not None


@dataclasses.dataclass
class FrameProgram:
    """Steps to run on every frame (see the module docstring); build with the methods."""

    steps: list[tuple[int, ...]] = dataclasses.field(default_factory=list)
    lists: list[int] = dataclasses.field(default_factory=list)
    joins: int = 0

    def _list(self, joints) -> tuple[int, int]:
        first = len(self.lists)
        self.lists.extend(int(j) for j in joints)
        return first, len(self.lists) - first

    def swap(self, old_root: int, new_root: int, others, kids) -> None:
        """``others``: the other children of ``old_root``; ``kids``: those of ``new_root``."""
        self.steps.append((SWAP, old_root, new_root, *self._list(others), *self._list(kids), 0))

    def split(self, joint: int, path: list[int], leaf: bool) -> None:
        """``path`` from the root down to ``joint`` in the input's forest; ``leaf``: it has
        no children (the FK engine then computes its position as ``P_p + W_p (R_j t_j)``)."""
        self.steps.append((SPLIT, joint, path[-1], *self._list(path), 0, 0, int(leaf)))

    def join(self, joint: int, path: list[int]) -> int:
        """``path`` from its root down to the new parent, in the input's forest; returns
        the join's index."""
        self.steps.append((JOIN, joint, path[-1], *self._list(path), 0, 0, self.joins))
        self.joins += 1
        return self.joins - 1

    def fold(self, dummy: int, children) -> None:
        self.steps.append((FOLD, dummy, -1, *self._list(children), 0, 0, 0))

    def tables(self) -> tuple[np.ndarray, np.ndarray]:
        """The steps (S, 8) and the lists of joints as int64 arrays, for the kernel."""
        return np.array(self.steps, dtype=np.int64).reshape(-1, 8), np.array(self.lists, dtype=np.int64)

    def copied(self, n_joints: int) -> np.ndarray:
        """(C, 2) int64 ranges [first, stop) of the joints the kernel copies into the edited
        frame before the steps: all of them when a step reads the edited frame (swap, fold)
        or when the steps write fewer than half of the joints (a frame copied as one row runs
        at a copy's speed, by ranges markedly slower), else those no split or join
        writes (each writes the whole of its joint): each number of the output written once."""
        written = {step[1] for step in self.steps}
        if any(step[0] not in (SPLIT, JOIN) for step in self.steps) or 2 * len(written) < n_joints:
            return np.array([[0, n_joints]], dtype=np.int64)
        kept = np.ones(n_joints + 2, bool)  # a False on either side closes every range
        kept[[0, -1]] = False
        kept[[j + 1 for j in written]] = False
        edges = np.flatnonzero(np.diff(kept.astype(np.int8)))
        return edges.reshape(-1, 2).astype(np.int64)


@dataclasses.dataclass(frozen=True)
class JoinOffsets:
    """What the pass found for each join of a program, over all frames.

    mean, low, high : (n_joins, 3) the mean, minimum and maximum of each joint's offset
        under its new parent (``R_j^T (t_j - t_p)`` with the world transforms of that frame).
    """

    mean: np.ndarray
    low: np.ndarray
    high: np.ndarray

    @property
    def spread(self) -> np.ndarray:
        """(n_joins,) the largest distance of any frame's offset from the mean, per axis
        (``max |offset - mean|``, exactly: rounding of ``x - mean`` is monotone in x)."""
        return np.maximum(np.abs(self.high - self.mean), np.abs(self.low - self.mean)).max(axis=1)


def run(
    motion: Motion,
    program: FrameProgram,
    *,
    kept: np.ndarray | None = None,
    static: np.ndarray | None = None,
    threads: int | None = 1,
) -> tuple[np.ndarray, np.ndarray, JoinOffsets]:
    """The edited rotations (F, J', 3, 3) and translations (F, J', 3) of every frame, and
    what the program's joins measured.

    kept : (J',) the joints written, in that order (None: all).
    static : (n_joins, 3) the offset each join is expected to keep over all frames, written
        as its translation in every frame, or a row of NaN (None: all NaN).
    threads : blocks of frames edited at once (None: one per core); the result does not
        depend on it.

    A join without a static offset gets its per-frame offset as its translation: where the
    caller finds the joint rigid, it writes the static offset over it (:func:`set_static`);
    one with a static offset that turns out not rigid needs the pass again without it.
    """
    steps, lists = program.tables()
    rotations = np.ascontiguousarray(motion.rotations)
    translations = np.ascontiguousarray(motion.translations)
    n_frames, n_joints = motion.n_frames, motion.n_joints
    kept = np.zeros(0, np.int64) if kept is None else np.asarray(kept, dtype=np.int64)
    width = kept.size or n_joints
    copied = program.copied(n_joints)
    expected = np.full((max(program.joins, 1), 3), np.nan)
    if static is not None and program.joins:
        expected[:] = static
    blocks = max(1, -(-n_frames // MEASURE_BLOCK_FRAMES))
    sums = np.zeros((blocks, program.joins, 3))
    lows = np.full((blocks, program.joins, 3), np.inf)
    highs = np.full((blocks, program.joins, 3), -np.inf)
    out_rotations = np.empty((n_frames, width, 3, 3))
    out_translations = np.empty((n_frames, width, 3))
    out_rows, out_rows_t = out_rotations.reshape(n_frames, -1), out_translations.reshape(n_frames, -1)

    def work(frames: slice) -> None:
        _kernels.run_program(
            rotations, translations, rotations.reshape(n_frames, -1), translations.reshape(n_frames, -1), steps, lists,
            kept, copied, frames.start, frames.stop, MEASURE_BLOCK_FRAMES, sums, lows, highs, out_rotations,
            out_translations, out_rows, out_rows_t, np.empty((n_joints, 3, 3)), np.empty((n_joints, 3)),
            np.empty((max(program.joins, 1), 3, 4)), expected,
        )  # fmt: skip

    if n_frames:
        in_blocks(work, n_frames, threads, align=MEASURE_BLOCK_FRAMES)
    total = np.zeros((program.joins, 3))
    for block in sums:  # in frame order, whatever the threads
        total += block
    measured = JoinOffsets(total / max(n_frames, 1), lows.min(axis=0), highs.max(axis=0))
    return out_rotations, out_translations, measured


def set_static(translations: np.ndarray, joints, offsets: np.ndarray) -> None:
    """Write each joint's static offset (K, 3) over its column of ``translations`` (F, J, 3)."""
    joints = np.asarray(joints, dtype=np.int64)
    if joints.size:  # one masked pass over the frames (numpy's fancy assignment is far slower)
        row = np.zeros(translations.shape[1:])
        row[joints] = offsets
        mask = np.zeros(translations.shape[1:], bool)
        mask[joints] = True
        np.copyto(translations, row, where=mask)
